// varsym/contact/stepper.hpp: hard contact with Coulomb friction inside the variational step.
//
// A step of the chosen member of the family (the general engine, with the free base's
// quaternion constraint if any), Inner, maps (q_j, p_j) to (q_{j+1}, p_{j+1}); its first equation
// is the discrete Euler–Lagrange equation p_j + D₁L_d(q_j, q_{j+1}) = 0 (variational.hpp). The
// contact impulses enter it as a discrete Lagrange–d'Alembert impulse at the step's start:
//   p_j + J(q_j)ᵀ λ + D₁L_d(q_j, q_{j+1}) = 0,   p_{j+1} = D₂L_d(q_j, q_{j+1}),          (K1)
// with J's rows per contact i the normal n·∂P_i/∂q and the tangents t·∂F_i/∂q (P_i the point
// that defines the gap, F_i the body's material point at the contact at q_j), and λ = (γ_i, b_i)
// solving, at the step's end,
//   φ_i(q_{j+1}) ≥ 0 ⊥ γ_i ≥ 0,  (μγ_i, b_i) ∈ K ⊥ (η_i, d_i) ∈ K,                         (K2)
// d_i = T(F_i(q_{j+1}) − F_i(q_j)) the slip over the step (cone_solver.hpp): the gap at the end
// of every step is non-negative, impacts are inelastic (the normal velocity is removed, not
// reversed), friction sticks inside the cone and slides on its boundary against the slip
// (maximal dissipation). As Dojo's integrator (Howell et al. 2022) with J taken at q_j.
//
// Solution: the step without impulses first; if no gap is negative at its end, λ = 0 solves (K2)
// and the step is the family member's own (free flight costs one check of the gaps). Otherwise
// Newton's method on λ through the step: with S = ∂q_{j+1}/∂p_j (the step's own Jacobian), the
// gaps and slips are linearised as (φ, d) ≈ (φ, d)(λ_k) + G S Jᵀ (λ − λ_k), the linear conic
// complementarity problem is solved by the interior-point method (cone_solver.hpp), the step is
// taken again with the new impulses, until the gaps and slips at its end agree with their
// linearisation to `tolerance` [m]. The contacts solved for are the pairs whose gap is below
// the free step's largest point motion and the last step's; a pair found below zero at the end
// joins them. Warm start: the last step's impulses are the first iterate, and S is taken at the
// step with them (two linearisations a step for a robot standing: the A1's 4.0 fell to 2.0).
//
// The contact's work over a step is the change in E − W (W the forces' work) that the impulses
// make, against the same step taken without them; total_work() includes it, so E − E₀ − W
// measures the scheme's own error in and out of contact.
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "varsym/contact/cone_solver.hpp"
#include "varsym/contact/geometry.hpp"
#include "varsym/solvers/compensated.hpp"
#include "varsym/solvers/newton.hpp"

namespace varsym::contact {

struct contact_options {
    double tolerance = 1e-12; ///< [m] on the gaps and slips at a step's end
    int max_iterations = 30;  ///< linearisations per step
};

/// What the last step's contacts did.
struct contact_report {
    int active = 0;           ///< contacts with a normal impulse
    double normal = 0.0;      ///< Σ γ_i [N s]
    double friction = 0.0;    ///< Σ |b_i| [N s]
    double penetration = 0.0; ///< max(0, −min φ) at the step's end [m]
    double work = 0.0;        ///< the impulses' work over the step [J]
    int iterations = 0;       ///< linearisations (0: no contact)
};

template <class Inner>
class contact_stepper : public Inner {
    static constexpr int history_size = 7;

  public:
    static constexpr int dim = Inner::dim;

    contact_stepper(Inner inner, std::shared_ptr<const multibody::tree> t,
                    std::vector<obstacle> world, contact_options o = {})
        : Inner(std::move(inner)), kin_(t), points_(contact_points(*t)), world_(std::move(world)),
          opt_(o) {
        if (kin_.dimension() != this->system().dimension())
            throw std::invalid_argument("contact: the robot's coordinates are not the system's");
        for (const obstacle& w : world_)
            if (!(w.friction >= 0.0 && std::isfinite(w.friction)))
                throw std::invalid_argument("the friction coefficient of " + w.name +
                                            " must be finite and >= 0");
    }

    [[nodiscard]] const contact_report& last_contact() const { return last_; }
    [[nodiscard]] double contact_work() const { return work_ + carry_; }
    [[nodiscard]] double total_work() const { return Inner::total_work() + contact_work(); }
    [[nodiscard]] int pairs() const { return static_cast<int>(points_.size() * world_.size()); }
    /// min φ over every pair at q [m] (+∞ without any).
    [[nodiscard]] double lowest_gap(const Eigen::VectorXd& q) {
        kin_.at(q);
        double low = std::numeric_limits<double>::infinity();
        for (int c = 0; c < pairs(); ++c)
            low = std::min(low, gap(c));
        return low;
    }

    newton_report step(phase_state<dim>& x);

    std::string diagnose(const phase_state<dim>& x) {
        return failure_.empty() ? Inner::diagnose(x) : failure_;
    }

    /// The tangent map of a step without contact; refused across one (not differentiable).
    void step_jacobian(const phase_state<dim>& from, Eigen::MatrixXd& out) {
        if (last_.iterations > 0)
            throw std::invalid_argument("the step's tangent map is not defined across a contact "
                                        "(its impulses switch on and off)");
        Inner::step_jacobian(from, out);
    }

    /// The inner stepper's history, then the last step's contacts and impulses (4 numbers a
    /// contact: the warm start), their count, the contact's work with its carry and the last
    /// step's report: a resumed run takes the steps the straight one would have.
    void save_history(std::vector<double>& out) const {
        Inner::save_history(out);
        for (std::size_t i = 0; i < warm_pairs_.size(); ++i) {
            out.push_back(warm_pairs_[i]);
            for (int j = 0; j < 3; ++j)
                out.push_back(warm_lambda_(3 * static_cast<Eigen::Index>(i) + j));
        }
        out.push_back(static_cast<double>(warm_pairs_.size()));
        out.insert(out.end(), {work_, carry_, double(last_.active), last_.normal,
                               last_.friction, last_.penetration, last_.work});
    }
    void restore_history(const phase_state<dim>& x, const std::vector<double>& in) {
        last_ = {};
        work_ = carry_ = 0.0;
        warm_pairs_.clear();
        const std::size_t fixed = history_size + 1;
        const auto count =
            in.size() >= fixed ? static_cast<std::size_t>(in[in.size() - fixed]) : 0U;
        if (in.size() < fixed || in.size() < fixed + 4 * count) {
            Inner::restore_history(x, in);
            return;
        }
        const auto warm = in.end() - static_cast<std::ptrdiff_t>(fixed + 4 * count);
        Inner::restore_history(x, std::vector<double>(in.begin(), warm));
        warm_lambda_.resize(3 * static_cast<Eigen::Index>(count));
        for (std::size_t i = 0; i < count; ++i) {
            warm_pairs_.push_back(static_cast<int>(warm[static_cast<std::ptrdiff_t>(4 * i)]));
            for (int j = 0; j < 3; ++j)
                warm_lambda_(3 * static_cast<Eigen::Index>(i) + j) =
                    warm[static_cast<std::ptrdiff_t>(4 * i) + 1 + j];
        }
        const auto split = in.end() - history_size;
        work_ = split[0];
        carry_ = split[1];
        last_.active = static_cast<int>(split[2]);
        last_.normal = split[3];
        last_.friction = split[4];
        last_.penetration = split[5];
        last_.work = split[6];
    }

  private:
    struct pair_state {
        int pair;
        vec3 friction_point = vec3::Zero(); ///< F in its body's frame
        vec3 start = vec3::Zero();          ///< F(q_j) in the world
        vec3 t1 = vec3::UnitX(), t2 = vec3::UnitY(); ///< the tangents at q_j
    };
    [[nodiscard]] const contact_point& point(int c) const {
        return points_[static_cast<std::size_t>(c) / world_.size()];
    }
    [[nodiscard]] const obstacle& plane(int c) const {
        return world_[static_cast<std::size_t>(c) % world_.size()];
    }
    /// φ of pair c at the last kinematics.
    [[nodiscard]] double gap(int c) const {
        const contact_point& p = point(c);
        vec3 n;
        return plane(c).distance(kin_.pose(p.body).point(p.point), n) - p.radius;
    }
    // The inner stepper's running sums, kept across trial steps.
    void save() {
        saved_t_ = this->t_;
        saved_work_ = this->total_work_;
        saved_carry_ = this->work_carry_;
        saved_sum_ = this->sum_;
    }
    void restore() {
        this->t_ = saved_t_;
        this->total_work_ = saved_work_;
        this->work_carry_ = saved_carry_;
        this->sum_ = saved_sum_;
    }
    /// Rows of J (at the start, `start` true) or G (at the end) for the active pairs at the last
    /// kinematics, and the gaps and slips there.
    void rows(bool start, Eigen::MatrixXd& m, Eigen::VectorXd* values);
    bool take(phase_state<dim>& y, const Eigen::VectorXd& lambda, newton_report& rep);

    robot_kinematics kin_;
    std::vector<contact_point> points_;
    std::vector<obstacle> world_;
    contact_options opt_;
    contact_report last_;
    double work_ = 0.0, carry_ = 0.0;
    std::string failure_;
    // Scratch.
    std::vector<pair_state> active_;
    std::vector<int> warm_pairs_; // the last step's contacts and their impulses
    Eigen::VectorXd warm_lambda_;
    phase_state<dim> from_, y_;
    double saved_t_ = 0.0, saved_work_ = 0.0, saved_carry_ = 0.0;
    compensated_update<dim> saved_sum_;
    Eigen::MatrixXd jac_, g_, sj_, s_;
    Eigen::Matrix<double, 3, Eigen::Dynamic> dp_;
};

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
        if (start) { // the material point at the contact, and the tangent plane there
            tangents(n, a.t1, a.t2);
            a.start = centre - p.radius * n;
            a.friction_point = body.rotation.transpose() * (a.start - body.origin);
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

/// The step from from_ with impulses λ into y.
template <class Inner>
bool contact_stepper<Inner>::take(phase_state<dim>& y, const Eigen::VectorXd& lambda,
                                  newton_report& rep) {
    restore();
    y = from_;
    y.p.noalias() += jac_.transpose() * lambda;
    const newton_report r = Inner::step(y);
    rep.iterations += r.iterations;
    rep.residual = r.residual;
    return r.converged;
}

template <class Inner>
newton_report contact_stepper<Inner>::step(phase_state<dim>& x) {
    failure_.clear();
    from_ = x;
    save();
    const double w_start = Inner::total_work();
    y_ = x;
    newton_report rep = Inner::step(y_);
    last_ = {};
    if (!rep.converged) return rep;
    // The free step's end: its gaps, and how far the points moved.
    kin_.at(y_.q);
    double lowest = std::numeric_limits<double>::infinity();
    for (int c = 0; c < pairs(); ++c)
        lowest = std::min(lowest, gap(c));
    if (!(lowest < 0.0)) {
        warm_pairs_.clear();
        x = y_;
        return rep;
    }
    const double e_free = this->system().energy(y_) - (Inner::total_work() - w_start);
    std::vector<vec3> end(points_.size());
    for (std::size_t i = 0; i < points_.size(); ++i)
        end[i] = kin_.pose(points_[i].body).point(points_[i].point);
    std::vector<double> end_gap(static_cast<std::size_t>(pairs()));
    for (int c = 0; c < pairs(); ++c)
        end_gap[static_cast<std::size_t>(c)] = gap(c);
    kin_.at(from_.q);
    double reach = 0.0;
    for (std::size_t i = 0; i < points_.size(); ++i)
        reach = std::max(reach, (kin_.pose(points_[i].body).point(points_[i].point) - end[i]).norm());
    active_.clear();
    for (int c = 0; c < pairs(); ++c)
        if (end_gap[static_cast<std::size_t>(c)] < reach) active_.push_back({c});

    for (std::size_t i = 0; i < warm_pairs_.size(); ++i) // the last step's contacts join
        if (std::none_of(active_.begin(), active_.end(),
                         [&](const pair_state& a) { return a.pair == warm_pairs_[i]; }))
            active_.push_back({warm_pairs_[i]});
    // S = ∂q_{j+1}/∂p_j, kept for the step's linearisations (Newton's method with its Jacobian
    // frozen: the impulses change S by O(h λ), which the iteration absorbs): at the step with
    // the last step's impulses where there were any (warm: usually one more linearisation
    // converges), else at the free step.
    const int d = kin_.dimension();
    Eigen::VectorXd lambda, values, predicted;
    cone_problem prob;
    bool fresh = true; // the active set changed: J's rows, λ extended by zeros
    newton_report total = rep;
    if (warm_pairs_.empty()) {
        Inner::step_jacobian(from_, sj_);
    } else {
        kin_.at(from_.q);
        rows(true, jac_, nullptr);
        lambda.setZero(jac_.rows());
        for (std::size_t i = 0; i < active_.size(); ++i)
            for (std::size_t j = 0; j < warm_pairs_.size(); ++j)
                if (active_[i].pair == warm_pairs_[j])
                    lambda.segment<3>(3 * static_cast<Eigen::Index>(i)) =
                        warm_lambda_.segment<3>(3 * static_cast<Eigen::Index>(j));
        fresh = false;
        if (!take(y_, lambda, total)) {
            restore();
            total.converged = false;
            return total;
        }
        phase_state<dim> kicked = from_;
        kicked.p.noalias() += jac_.transpose() * lambda;
        Inner::step_jacobian(kicked, sj_);
    }
    s_ = sj_.block(0, d, d, d);
    for (int it = 1;; ++it) {
        if (fresh) {
            kin_.at(from_.q);
            rows(true, jac_, nullptr);
            const Eigen::Index known = lambda.size();
            lambda.conservativeResize(jac_.rows());
            lambda.tail(jac_.rows() - known).setZero();
            predicted.resize(0);
            fresh = false;
        }
        kin_.at(y_.q);
        rows(false, g_, &values);
        if (predicted.size() == values.size() &&
            (values - predicted).lpNorm<Eigen::Infinity>() <= opt_.tolerance) {
            // Converged for these pairs: does any other sink?
            const std::size_t before = active_.size();
            for (int c = 0; c < pairs(); ++c)
                if (gap(c) < 0.0 && std::none_of(active_.begin(), active_.end(),
                                                 [c](const pair_state& a) { return a.pair == c; }))
                    active_.push_back({c});
            if (active_.size() == before) {
                const int k = static_cast<int>(active_.size());
                last_.iterations = it;
                double low = std::numeric_limits<double>::infinity();
                for (int c = 0; c < pairs(); ++c)
                    low = std::min(low, gap(c));
                last_.penetration = std::max(0.0, -low);
                const double gamma_max = lambda.size() ? lambda(Eigen::seq(0, Eigen::last, 3)).maxCoeff() : 0.0;
                for (int i = 0; i < k; ++i) {
                    last_.normal += lambda(3 * i);
                    last_.friction += lambda.segment<2>(3 * i + 1).norm();
                    last_.active += lambda(3 * i) > 1e-9 * gamma_max ? 1 : 0;
                }
                last_.work = this->system().energy(y_) - (Inner::total_work() - w_start) - e_free;
                const double sum = work_ + last_.work; // Neumaier
                carry_ += std::abs(work_) >= std::abs(last_.work) ? (work_ - sum) + last_.work
                                                                   : (last_.work - sum) + work_;
                work_ = sum;
                warm_pairs_.clear();
                for (const pair_state& a : active_)
                    warm_pairs_.push_back(a.pair);
                warm_lambda_ = lambda;
                x = y_;
                total.converged = true;
                return total;
            }
            fresh = true;
            continue;
        }
        if (it > opt_.max_iterations) {
            failure_ = "the contact impulses did not converge in " +
                       std::to_string(opt_.max_iterations) +
                       " linearisations (gaps and slips off by " +
                       std::to_string((values - predicted).lpNorm<Eigen::Infinity>()) + " m)";
            break;
        }
        prob.a.noalias() = g_ * s_ * jac_.transpose();
        prob.c = values - prob.a * lambda;
        const int k = static_cast<int>(active_.size());
        prob.mu.resize(k);
        for (int i = 0; i < k; ++i)
            prob.mu(i) = plane(active_[static_cast<std::size_t>(i)].pair).friction;
        cone_options co;
        co.tolerance = 0.1 * opt_.tolerance;
        const cone_result r = solve_cone(prob, co);
        if (!r.converged) {
            failure_ = "the contact problem's interior-point solve did not converge in " +
                       std::to_string(r.iterations) + " iterations";
            break;
        }
        lambda = r.lambda;
        predicted = r.values;
        if (!take(y_, lambda, total)) break;
    }
    restore();
    total.converged = false;
    return total;
}

} // namespace varsym::contact
