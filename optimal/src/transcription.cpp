// optimal/src/transcription.cpp: the DMOC transcription of run-time size (transcription.hpp):
// its sizes, bounds, starting points and cost. The equations and their derivatives are in
// transcription_derivatives.cpp, the constraints' parts in transcription_constraints.cpp.
#include "varsym/optimize/transcription.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace varsym::optimal {

dmoc_transcription::dmoc_transcription(std::shared_ptr<const controlled_system> system,
                                       const control_problem& problem)
    : sys_(std::move(system)) {
    if (!sys_) throw std::invalid_argument("transcribe: no system");
    d_ = sys_->dimension();
    m_ = sys_->inputs();
    k_ = sys_->constraint_count();
    if (d_ < 1 || k_ < 0 || k_ >= d_)
        throw std::invalid_argument("transcribe: a system needs d >= 1 coordinates and fewer "
                                    "constraints than coordinates");
    p_ = detail::checked(problem, d_, m_);
    const auto member = family_member(p_.scheme);
    tab_ = galerkin::tableau::make(member.first, member.second);
    s_ = tab_.degree;
    r_ = static_cast<int>(tab_.quad.size());
    n_ = p_.steps;
    // The unknowns and equations are counted in int (IPOPT's Index).
    if (static_cast<double>(n_) * (s_ * (d_ + k_) + r_ * m_ + 1) + 4.0 * d_ + 2.0 > 2.0e9)
        throw std::invalid_argument(std::to_string(n_) +
                                    " steps make more than 2e9 unknowns, beyond what IPOPT can "
                                    "index: take fewer steps");
    h_ = p_.time / n_;
    input_terms ends;
    bool acts = false;
    for (const bool first : {true, false}) {
        sys_->force(first ? p_.q_start : p_.q_end, first ? p_.v_start : p_.v_end, 0.0,
                    vector::Zero(m_), ends, true);
        acts = acts || !ends.fu.isZero(0.0);
    }
    if (!acts)
        throw std::invalid_argument("the inputs do not act on the system at either boundary "
                                    "state (df/du = 0 there): nothing to control");
    if (p_.free_time && sys_->time_dependent())
        throw std::invalid_argument("a free final time needs an autonomous system: this "
                                    "Lagrangian depends on t");
    points_ = n_ * s_ + 1;
    free_end_ = p_.free_end();
    if (p_.end_target && p_.end_target_weight == 0.0) t_ = p_.end_target->rows();
    nodes_ = k_ == 0 && n_ > 1 &&
             ((p_.velocity_lower.array() > -unbounded).any() ||
              (p_.velocity_upper.array() < unbounded).any());
    setup_path_bounds();
    setup_structure();
    lagrangian_terms<dynamic> t;
    sys_->gradient(p_.q_start, p_.v_start, 0.0, t);
    p_start_ = t.lv;
    sys_->gradient(p_.q_end, p_.v_end, p_.time, t);
    p_end_ = t.lv;
    check_boundary_constraints();
}

void dmoc_transcription::bounds(vector& lower, vector& upper) const {
    lower = vector::Constant(variables(), -unbounded); // the impulses Λ are free
    upper = vector::Constant(variables(), unbounded);
    for (int g = 0; g < points_; ++g) {
        lower.segment(g * d_, d_) = p_.position_lower;
        upper.segment(g * d_, d_) = p_.position_upper;
    }
    lower.head(d_) = upper.head(d_) = p_.q_start; // fixed ends
    for (int i = 0; i < d_; ++i) {                // the end: fixed, or free within the bounds
        if (p_.free_end_position[static_cast<std::size_t>(i)]) continue;
        lower((points_ - 1) * d_ + i) = upper((points_ - 1) * d_ + i) = p_.q_end(i);
    }
    for (int c = 0; c < n_ * r_; ++c) {
        lower.segment(control_index(c), m_) = p_.control_lower;
        upper.segment(control_index(c), m_) = p_.control_upper;
    }
    for (int i = 0; free_end_ && i < d_; ++i) { // a free one within the velocity bounds
        const bool free = p_.free_end_velocity[static_cast<std::size_t>(i)];
        lower(end_velocity_index() + i) = free ? p_.velocity_lower(i) : p_.v_end(i);
        upper(end_velocity_index() + i) = free ? p_.velocity_upper(i) : p_.v_end(i);
    }
    for (int n = 1; nodes_ && n < n_; ++n) {
        lower.segment(node_velocity_index(n), d_) = p_.velocity_lower;
        upper.segment(node_velocity_index(n), d_) = p_.velocity_upper;
    }
    if (p_.free_time) {
        lower(time_index()) = p_.time_lower;
        upper(time_index()) = p_.time_upper;
    }
}

vector dmoc_transcription::start() const {
    vector x = vector::Zero(variables());
    const double span = static_cast<double>(points_ - 1);
    const vector q_end = end_guess();
    for (int g = 0; g < points_; ++g) {
        const double a = static_cast<double>(g) / span;
        x.segment(g * d_, d_) = (1.0 - a) * p_.q_start + a * q_end;
    }
    const vector u0 = vector::Zero(m_).cwiseMax(p_.control_lower).cwiseMin(p_.control_upper);
    for (int c = 0; c < n_ * r_; ++c)
        x.segment(control_index(c), m_) = u0;
    if (free_end_) x.segment(end_velocity_index(), d_) = p_.v_end;
    for (int n = 1; nodes_ && n < n_; ++n) // the straight line's velocity, within the bounds
        x.segment(node_velocity_index(n), d_) = ((q_end - p_.q_start) / p_.time)
                                                    .cwiseMax(p_.velocity_lower)
                                                    .cwiseMin(p_.velocity_upper);
    if (p_.free_time) x(time_index()) = p_.time;
    // The interpolated positions put on the constraints by Gauss–Newton, where it converges.
    vector g;
    matrix jac;
    for (int n = 1; k_ > 0 && n + 1 < points_; ++n) {
        vector q = x.segment(n * d_, d_);
        bool ok = false;
        for (int it = 0; it < 50 && !ok; ++it) {
            sys_->constraint(q, g, jac);
            ok = g.lpNorm<Eigen::Infinity>() <= 1e-13 * std::max(1.0, q.lpNorm<Eigen::Infinity>());
            if (!ok) q -= jac.transpose() * (jac * jac.transpose()).ldlt().solve(g);
        }
        if (ok && q.allFinite()) x.segment(n * d_, d_) = q;
    }
    return x;
}

vector dmoc_transcription::start_along(const std::function<vector(double)>& q) const {
    vector x = start();
    for (int g = 1; g + 1 < points_; ++g) {
        const vector at = q((g / s_ + tab_.control[static_cast<std::size_t>(g % s_)]) * h_);
        detail::require(at.size() == d_ && at.allFinite(), "the guessed path must give " +
                                                               std::to_string(d_) +
                                                               " finite coordinates at every time");
        x.segment(g * d_, d_) = at;
    }
    return x;
}

vector dmoc_transcription::start_from(const trajectory& guess) const {
    vector x = start();
    const double horizon = guess.node_times(guess.node_times.size() - 1);
    for (int k = 0; k < n_; ++k)
        for (int i = (k == 0 ? 1 : 0); i <= s_; ++i) {
            const double frac = (k + tab_.control[static_cast<std::size_t>(i)]) / n_;
            const vector q = guess.position(frac * horizon);
            for (int a = 0; a < d_; ++a) // the fixed ends stay
                if (k < n_ - 1 || i < s_ || p_.free_end_position[static_cast<std::size_t>(a)])
                    x((k * s_ + i) * d_ + a) = q(a);
        }
    for (int a = 0; free_end_ && a < d_; ++a)
        if (p_.free_end_velocity[static_cast<std::size_t>(a)])
            x(end_velocity_index() + a) = guess.v(a, guess.v.cols() - 1);
    const auto& ct = guess.control_times;
    for (int k = 0; k < n_; ++k)
        for (int j = 0; j < r_; ++j) {
            const double t = (k + tab_.quad.nodes[static_cast<std::size_t>(j)]) / n_ * horizon;
            const auto at = std::lower_bound(ct.data(), ct.data() + ct.size(), t) - ct.data();
            const Eigen::Index hi = std::clamp<Eigen::Index>(at, 1, ct.size() - 1), lo = hi - 1;
            const double span = ct(hi) - ct(lo),
                         a = span > 0 ? std::clamp((t - ct(lo)) / span, 0.0, 1.0) : 0.0;
            const vector u = (1.0 - a) * guess.u.col(lo) + a * guess.u.col(hi);
            x.segment(control_index(k * r_ + j), m_) =
                u.cwiseMax(p_.control_lower).cwiseMin(p_.control_upper);
        }
    for (int n = 1; nodes_ && n < n_; ++n) { // the guess's node velocities, interpolated
        const double t = static_cast<double>(n) / n_ * horizon;
        const auto& nt = guess.node_times;
        const auto at = std::lower_bound(nt.data(), nt.data() + nt.size(), t) - nt.data();
        const Eigen::Index hi = std::clamp<Eigen::Index>(at, 1, nt.size() - 1), lo = hi - 1;
        const double span = nt(hi) - nt(lo),
                     a = span > 0 ? std::clamp((t - nt(lo)) / span, 0.0, 1.0) : 0.0;
        x.segment(node_velocity_index(n), d_) = ((1.0 - a) * guess.v.col(lo) + a * guess.v.col(hi))
                                                    .cwiseMax(p_.velocity_lower)
                                                    .cwiseMin(p_.velocity_upper);
    }
    if (p_.free_time) x(time_index()) = std::clamp(horizon, p_.time_lower, p_.time_upper);
    return x;
}

void dmoc_transcription::point(cvector x, int k, int j, vector& q, vector& v) const {
    q.setZero(d_);
    v.setZero(d_);
    const double h = h_of(x);
    for (int i = 0; i <= s_; ++i) {
        const auto qi = x.segment((k * s_ + i) * d_, d_);
        q += tab_.phi(i, j) * qi;
        v += tab_.dphi(i, j) / h * qi;
    }
}

double dmoc_transcription::terminal_cost(cvector x, vector* gradient) const {
    if (!free_end_) return 0.0;
    const double target = target_cost(x, gradient);
    const vector dq = x.segment((points_ - 1) * d_, d_) - p_.q_end,
                 dv = x.segment(end_velocity_index(), d_) - p_.v_end;
    const vector &a = p_.cost.terminal_position, &b = p_.cost.terminal_velocity;
    if (gradient) {
        gradient->segment((points_ - 1) * d_, d_) += a.cwiseProduct(dq);
        gradient->segment(end_velocity_index(), d_) += b.cwiseProduct(dv);
    }
    return target + 0.5 * (dq.dot(a.cwiseProduct(dq)) + dv.dot(b.cwiseProduct(dv)));
}

vector dmoc_transcription::end_momentum(cvector x) const {
    if (!free_end_) return p_end_;
    lagrangian_terms<dynamic> t;
    sys_->gradient(x.segment((points_ - 1) * d_, d_), x.segment(end_velocity_index(), d_),
                   n_ * h_of(x), t);
    return t.lv;
}

double dmoc_transcription::integrand(cvector x, int k, int j, vector* g, matrix* hz) const {
    vector q, v;
    point(x, k, j, q, v);
    return running_cost_at(*sys_, p_.cost, p_.effort, q, v, point_time(k, j, h_of(x)),
                           control(x, k, j), g, hz);
}

double dmoc_transcription::cost(cvector x) const {
    const double h = h_of(x);
    double j = p_.cost.time * h * n_ + terminal_cost(x, nullptr);
    for (int k = 0; k < n_; ++k)
        for (int q = 0; q < r_; ++q)
            j += h * weight(q) * integrand(x, k, q, nullptr, nullptr);
    return j;
}

void dmoc_transcription::cost_gradient(cvector x, vector& gradient) const {
    gradient.setZero(variables());
    const double h = h_of(x);
    if (p_.free_time) gradient(time_index()) = p_.cost.time;
    (void)terminal_cost(x, &gradient);
    vector g, q, v;
    for (int k = 0; k < n_; ++k)
        for (int j = 0; j < r_; ++j) {
            const double c = integrand(x, k, j, &g, nullptr);
            const double hw = h * weight(j);
            for (int l = 0; l <= s_; ++l)
                gradient.segment((k * s_ + l) * d_, d_) +=
                    hw * (tab_.phi(l, j) * g.head(d_) + tab_.dphi(l, j) / h * g.segment(d_, d_));
            if (p_.free_time) { // d(h w c(q, V/h, u))/dT = w (c − ∇_v c · v) / N
                point(x, k, j, q, v);
                gradient(time_index()) += weight(j) * (c - g.segment(d_, d_).dot(v)) / n_;
            }
            gradient.segment(control_index(k * r_ + j), m_) += hw * g.tail(m_);
        }
}

} // namespace varsym::optimal
