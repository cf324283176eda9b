// varsym/contact/stepper_step.hpp: the contact step of contact_stepper (stepper.hpp): the free
// step, the linearisations with the interior-point solve and the warm start. Included by
// stepper.hpp.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace varsym::contact {

/// Rows of J (at the start, `start` true: the material points and tangents are set there) or G
/// (at the end) for the active pairs at the last kinematics, and the gaps and slips there.
template <class Inner>
void contact_stepper<Inner>::rows(bool start, Eigen::MatrixXd& m, Eigen::VectorXd* values) {
    const int k = static_cast<int>(active_.size()), d = kin_.dimension();
    m.resize(3 * k, d);
    if (values) values->resize(3 * k);
    dp_.resize(3, d);
    for (int i = 0; i < k; ++i) {
        pair_state& a = active_[static_cast<std::size_t>(i)];
        const contact_point& p = point(a.pair);
        const multibody::pose body = kin_.pose(p.body);
        const vec3 centre = body.point(p.point);
        vec3 n;
        const double distance = plane(a.pair).distance(centre, n);
        if (start) { // the material point at the contact's onset, and its tangent plane
            const double tau = onset(a.pair);
            multibody::pose at = body;
            vec3 c = centre, normal = n;
            if (tau > 0.0) { // a contact that begins in the step: where the free path meets it
                q_onset_ = from_.q + tau * (q_free_ - from_.q);
                onset_kin_.at(q_onset_);
                at = onset_kin_.pose(p.body);
                c = at.point(p.point);
                plane(a.pair).distance(c, normal);
            }
            tangents(normal, a.t1, a.t2);
            a.start = c - p.radius * normal;
            a.friction_point = at.rotation.transpose() * (a.start - at.origin);
        }
        kin_.jacobian(p.body, centre, dp_);
        m.row(3 * i) = n.transpose() * dp_;
        const vec3 f = body.point(a.friction_point);
        kin_.jacobian(p.body, f, dp_);
        m.row(3 * i + 1) = a.t1.transpose() * dp_;
        m.row(3 * i + 2) = a.t2.transpose() * dp_;
        if (!values) continue;
        (*values)(3 * i) = distance - p.radius;
        (*values)(3 * i + 1) = a.t1.dot(f - a.start);
        (*values)(3 * i + 2) = a.t2.dot(f - a.start);
    }
}

/// Where on the free step's path q_j + τ (q_free − q_j) pair c's contact begins, τ ∈ [0, 1]: 0
/// for a contact closed at the step's start; else the last point of the path found still open
/// (φ ≥ 0) by regula falsi on the gap from the bracket [0, 1]. The slip is measured from there,
/// so that a contact made within a step does not count the approach before it: a body stopped at
/// its impact does not slip. (From a point already inside, stopping at φ = 0 would slip back,
/// which high friction can jam: no impulse in the cone stops it, as in Painlevé's paradox.)
template <class Inner>
double contact_stepper<Inner>::onset(int c) {
    const auto k = static_cast<std::size_t>(c);
    double lo = 0.0, hi = 1.0, glo = start_gap_[k], ghi = end_gap_[k];
    if (!(glo > 0.0) || !(ghi < 0.0)) return 0.0;
    const contact_point& p = point(c);
    vec3 n;
    for (int i = 0; i < 4; ++i) {
        const double tau = lo + (hi - lo) * glo / (glo - ghi);
        q_onset_ = from_.q + tau * (q_free_ - from_.q);
        onset_kin_.at(q_onset_);
        const double g = plane(c).distance(onset_kin_.pose(p.body).point(p.point), n) - p.radius;
        if (g >= 0.0) {
            lo = tau;
            glo = g;
        } else {
            hi = tau;
            ghi = g;
        }
        if (glo <= 1e-3 * opt_.tolerance) break;
    }
    return lo;
}

/// The step from from_ with impulses λ into y, the inner stepper's running sums as before it.
/// Where the inner stepper offers it (the free base's), from the last step taken from from_ (the
/// free step or the last take) moved to first order for the change of kick, by chord updates.
template <class Inner>
bool contact_stepper<Inner>::take(phase_state<dim>& y, const Eigen::VectorXd& lambda,
                                  newton_report& rep) {
    restore();
    y = from_;
    kick_.noalias() = jac_.transpose() * lambda;
    bool near = false;
    if constexpr (requires(Inner & i, const vec<dim>& dp) { i.start_next_near(dp); }) {
        if (near_ready_) {
            dkick_ = kick_ - last_kick_;
            Inner::start_next_near(dkick_);
            near = true;
        }
    }
    y.p += kick_;
    newton_report r = Inner::step(y);
    rep.iterations += r.iterations;
    if (!r.converged && near) { // from the predictor, as without a start near the last
        restore();
        y = from_;
        y.p += kick_;
        r = Inner::step(y);
        rep.iterations += r.iterations;
    }
    rep.residual = r.residual;
    near_ready_ = r.converged;
    last_kick_ = kick_;
    return r.converged;
}

template <class Inner>
newton_report contact_stepper<Inner>::step(phase_state<dim>& x) {
    failure_.clear();
    from_ = x;
    save();
    last_ = {};
    newton_report total;
    if (!warm_pairs_.empty()) { // from the last step's contacts and impulses
        if (warm(total)) {
            finish(x);
            return total;
        }
        // Cold: the free step, whose Jacobian the linearisation starts from.
        failure_.clear();
        last_ = {};
        restore();
    }
    y_ = x;
    const newton_report rep = Inner::step(y_);
    free_step_taken(rep.converged);
    total.iterations += rep.iterations;
    total.residual = rep.residual;
    if (!rep.converged) {
        restore();
        return total;
    }
    // The free step's end: if no gap is negative, λ = 0 solves (K2).
    q_free_ = y_.q;
    if (!select()) {
        warm_pairs_.clear();
        impulses_.clear();
        x = y_;
        total.converged = true;
        return total;
    }
    rows(true, jac_, nullptr);
    lambda_.setZero(jac_.rows());
    Inner::position_sensitivity(from_, s_); // the free step's
    s_kept_ = false;
    if (iterate(total)) {
        finish(x);
        return total;
    }
    restore();
    return total;
}

/// Every pair's gap at the free step's end q_free_ (taken, or estimated by warm()) and at q_j;
/// active_ the pairs closer at that end than the farthest a point moved. False if no gap there
/// is negative. Leaves the kinematics at q_j where it returns true.
template <class Inner>
bool contact_stepper<Inner>::select() {
    kin_.at(q_free_);
    end_gap_.resize(static_cast<std::size_t>(pairs()));
    double lowest = std::numeric_limits<double>::infinity();
    for (int c = 0; c < pairs(); ++c)
        lowest = std::min(lowest, end_gap_[static_cast<std::size_t>(c)] = gap(c));
    if (!(lowest < 0.0)) return false;
    ends_.resize(points_.size());
    for (std::size_t i = 0; i < points_.size(); ++i)
        ends_[i] = kin_.pose(points_[i].body).point(points_[i].point);
    kin_.at(from_.q);
    start_gap_.resize(static_cast<std::size_t>(pairs()));
    for (int c = 0; c < pairs(); ++c)
        start_gap_[static_cast<std::size_t>(c)] = gap(c);
    double reach = 0.0;
    for (std::size_t i = 0; i < points_.size(); ++i)
        reach =
            std::max(reach, (kin_.pose(points_[i].body).point(points_[i].point) - ends_[i]).norm());
    active_.clear();
    for (int c = 0; c < pairs(); ++c)
        if (end_gap_[static_cast<std::size_t>(c)] < reach) active_.push_back({c});
    return true;
}

/// The warm start, without a free step: the step with the last step's pressing contacts and
/// impulses (their contact points at q_j) from the scheme's predictor, S there, and from these
/// the free step's end to first order, q_{j+1} − S Jᵀλ, which chooses the contacts and places
/// the onsets as the free step's end does (select()); then Newton's method on λ. False where that
/// step fails, where no gap at the estimate is negative or no impulse is left (the contacts
/// open: the free step decides), or where the iteration fails.
template <class Inner>
bool contact_stepper<Inner>::warm(newton_report& total) {
    kin_.at(from_.q);
    start_gap_.assign(static_cast<std::size_t>(pairs()), 0.0);
    end_gap_ = start_gap_; // no onset within the step yet (onset() is 0 where no gap is > 0)
    active_.clear();
    for (const int pair : warm_pairs_)
        active_.push_back({pair});
    rows(true, jac_, nullptr);
    lambda_ = warm_lambda_;
    near_ready_ = false;                       // no step taken from q_j yet
    if constexpr (reuses) Inner::reuse_next(); // the last step's matrix, by chord updates
    bool taken = take(y_, lambda_, total);
    if constexpr (reuses) {
        if (!taken) taken = take(y_, lambda_, total); // without it: Newton's from the predictor
    }
    if (!taken) return false;
    sensitivity(true);
    q_free_ = y_.q;
    q_free_.noalias() -= s_ * kick_;
    if (!select()) return false;
    for (const int pair : warm_pairs_)
        if (std::none_of(active_.begin(), active_.end(),
                         [pair](const pair_state& a) { return a.pair == pair; }))
            active_.push_back({pair});
    rows(true, jac_, nullptr);
    lambda_.setZero(jac_.rows());
    for (std::size_t i = 0; i < active_.size(); ++i)
        for (std::size_t j = 0; j < warm_pairs_.size(); ++j)
            if (active_[i].pair == warm_pairs_[j])
                lambda_.segment<3>(3 * static_cast<Eigen::Index>(i)) =
                    warm_lambda_.segment<3>(3 * static_cast<Eigen::Index>(j));
    // Every contact open after all (the estimate's gap below zero, the step's not): the free
    // step decides, so that a step without impulses is the scheme's own.
    return iterate(total) && !lambda_.isZero(0.0);
}

/// S = ∂q_{j+1}/∂p_j of the last step taken (from from_, kicked by kick_) into s_. Where
/// `kept` and the inner stepper offers it (the free base's), from the saddle-point matrix that
/// step iterated with, already factorised (its last Newton iterate's, or an earlier step's
/// kept: constrained_stepper::reuse_next): no second derivatives, and an approximation whose
/// linearisations the iteration on λ checks against the steps it takes (iterate() takes S
/// exactly where one misses).
template <class Inner>
void contact_stepper<Inner>::sensitivity(bool kept) {
    s_kept_ = false;
    if constexpr (requires(Inner & i, Eigen::MatrixXd & s) { i.kept_position_sensitivity(s); }) {
        if (kept) {
            Inner::kept_position_sensitivity(s_);
            s_kept_ = true;
            return;
        }
    }
    phase_state<dim> kicked = from_;
    kicked.p += kick_;
    Inner::position_sensitivity(kicked, s_);
}

/// Newton's method on λ (stepper.hpp) from lambda_, with y_ the step taken from it (from warm(),
/// with J's rows before the onsets were placed) and S taken there. True when converged: y_ and
/// lambda_ are then the step's.
template <class Inner>
bool contact_stepper<Inner>::iterate(newton_report& total) {
    predicted_.resize(0);
    cone_problem prob;
    bool stalled = false;
    for (int it = 1;; ++it) {
        kin_.at(y_.q);
        rows(false, g_, &values_);
        const bool known = predicted_.size() == values_.size();
        double miss = std::numeric_limits<double>::infinity(), gap_miss = miss;
        if (known) {
            miss = (values_ - predicted_).lpNorm<Eigen::Infinity>();
            gap_miss = 0.0;
            for (Eigen::Index r = 0; r < values_.size(); r += 3) { // NaN included
                const double off = std::abs(values_(r) - predicted_(r));
                if (!(off <= gap_miss)) gap_miss = off;
            }
        }
        // With the kept S the linearisations converge linearly, not quadratically: the first
        // within the tolerance may end just inside it, a penetration of up to the tolerance, so
        // the gaps must agree to a tenth of it (the interior point's own tolerance).
        const bool agrees =
            miss <= opt_.tolerance && gap_miss <= (s_kept_ ? 0.1 : 1.0) * opt_.tolerance;
        if (agrees) {
            // Converged for these pairs: does any other sink?
            const std::size_t before = active_.size();
            for (int c = 0; c < pairs(); ++c)
                if (gap(c) < 0.0 && std::none_of(active_.begin(), active_.end(),
                                                 [c](const pair_state& a) { return a.pair == c; }))
                    active_.push_back({c});
            if (active_.size() == before) {
                last_.iterations = it;
                total.converged = true;
                return true;
            }
            // It joins, with λ = 0: J's rows again, the step (y_) unchanged.
            kin_.at(from_.q);
            rows(true, jac_, nullptr);
            const Eigen::Index had = lambda_.size();
            lambda_.conservativeResize(jac_.rows());
            lambda_.tail(jac_.rows() - had).setZero();
            predicted_.resize(0);
            continue;
        }
        if (it > opt_.max_iterations) {
            const auto metres = [](double v) { // std::to_string would print 1e-10 as 0.000000
                char text[32];
                std::snprintf(text, sizeof text, "%.3g m", v);
                return std::string(text);
            };
            failure_ = "the contact impulses did not converge in " +
                       std::to_string(opt_.max_iterations) + " linearisations (" +
                       (stalled ? std::string("the interior point stalled on the last one")
                        : known && s_kept_ && miss <= opt_.tolerance
                            ? "gaps off their linearisation by " + metres(gap_miss) +
                                  ", above a tenth of the tolerance"
                        : known ? "gaps and slips off their linearisation by " + metres(miss)
                                : std::string("the set of contacts was still growing")) +
                       "): try a smaller step";
            return false;
        }
        // A linearisation with the warm start's kept S that missed its prediction by more than
        // the tolerance (or whose interior point stalled), or the second to miss the gaps' tenth:
        // S taken at this step instead, once (as on the cold path, it is then kept for the step).
        if (it > 1 && s_kept_ && (!(miss <= opt_.tolerance) || it > 2)) sensitivity(false);
        prob.a.noalias() = g_ * s_ * jac_.transpose();
        prob.c = values_ - prob.a * lambda_;
        const int k = static_cast<int>(active_.size());
        prob.mu.resize(k);
        for (int i = 0; i < k; ++i)
            prob.mu(i) = plane(active_[static_cast<std::size_t>(i)].pair).friction;
        cone_options co;
        co.tolerance = 0.1 * opt_.tolerance;
        const cone_result r = solve_cone(prob, co);
        if (!r.converged && !r.failure.empty()) {
            failure_ = "the contact problem's interior-point solve " + r.failure;
            return false;
        }
        // An interior point that stalls (a linearisation with no exact solution: a body stopping
        // at its impact, the gap's and the slip's rows taken where the free step ended) gives
        // its last iterate, and the step is linearised again where it leads.
        lambda_ = r.lambda;
        if (r.converged)
            predicted_ = r.values;
        else
            predicted_.resize(0);
        stalled = !r.converged;
        if (!take(y_, lambda_, total)) return false;
    }
}

} // namespace varsym::contact
