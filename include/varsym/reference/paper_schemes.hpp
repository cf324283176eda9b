// varsym/reference/paper_schemes.hpp: the paper's full per-step Newton systems, F_N (2 blocks)
// and F_S (3 blocks) with the Jacobians it prints. Slower than the reduced steppers of
// newmark.hpp and simpson.hpp; kept as the reference those are tested against.
//
// The unknowns are written as increments over the paper's starting point (p_j, q_j) — e.g.
// Δp = p − p_j — which is the same system with the same Jacobian and the same first iterate
// (Δ = 0), but resolves the increments to their own relative precision; they are accumulated
// with compensated summation like the fast steppers do.
#pragma once

#include <algorithm>
#include <string_view>

#include "varsym/solvers/compensated.hpp"
#include "varsym/solvers/newton.hpp"
#include "varsym/systems/separable.hpp"

namespace varsym::paper_reference {

namespace detail {
// Size of the increments of a step: h (|M⁻¹p| + |∇V|); the scale of Newton's stopping test.
template <class System>
double increment_scale(const System& sys, const phase_state<System::dim>& x,
                       const vec<System::dim>& grad, double h) {
    return h * std::max((sys.inverse_mass() * x.p).template lpNorm<Eigen::Infinity>(),
                        grad.template lpNorm<Eigen::Infinity>());
}
} // namespace detail

/// Newmark: unknowns z = (Δp, Δq) = (p_{j+1} − p_j, q_{j+1} − q_j), started at 0, solving
///   F_N = [ Δp + h ∇V(q_j + Δq/2) ;  Δq − (h/2) M⁻¹ (2 p_j + Δp) ] = 0
/// (eq. systeme-dynamique-discret-ordre-2), Jacobian [[I, (h/2)∇²V(q̄)], [−(h/2)M⁻¹, I]].
template <class System>
class newmark_stepper {
  public:
    static constexpr int dim = System::dim;
    using system_type = System;
    static constexpr std::string_view scheme_name = "newmark-paper";

    newmark_stepper(System sys, double h, const newton_options& opt = {})
        : sys_(std::move(sys)), h_(h), opt_(opt) {}
    [[nodiscard]] double step_size() const { return h_; }
    [[nodiscard]] const System& system() const { return sys_; }

    newton_report step(phase_state<dim>& x) {
        constexpr int Z = blocks(2, dim);
        const int d = static_cast<int>(x.q.size());
        const auto& minv = sys_.inverse_mass();
        const auto& v = sys_.potential();
        const double h = h_;
        newton_options opt = opt_;
        opt.typical = detail::increment_scale(sys_, x, v.gradient(x.q), h);
        vec<Z> z = vec<Z>::Zero(2 * d);
        const newton_report rep = newton_solve<Z>(
            z,
            [&](const vec<Z>& y, vec<Z>& r, mat<Z>& jac) {
                const vec<dim> dp = block_of<dim>(y, 0, d);
                const vec<dim> dq = block_of<dim>(y, 1, d);
                const vec<dim> qbar = x.q + 0.5 * dq;
                block_of<dim>(r, 0, d) = dp + h * v.gradient(qbar); // eq. systeme-...-ordre-2
                block_of<dim>(r, 1, d) =
                    dq - 0.5 * h * minv * (2.0 * x.p + dp); // eq. systeme-...-ordre-2
                const mat<dim> id = mat<dim>::Identity(d, d);
                block_of<dim>(jac, 0, 0, d) = id;
                block_of<dim>(jac, 0, 1, d) = 0.5 * h * v.hessian(qbar);
                block_of<dim>(jac, 1, 0, d) = -0.5 * h * minv;
                block_of<dim>(jac, 1, 1, d) = id;
            },
            opt);
        if (rep.converged) {
            sum_.add_q(x, block_of<dim>(z, 1, d));
            sum_.add_p(x, block_of<dim>(z, 0, d));
        }
        return rep;
    }

  private:
    System sys_;
    double h_;
    newton_options opt_;
    compensated_update<dim> sum_;
};

/// Simpson: unknowns z = (q_m − q_j, Δp, Δq), started at 0 (the paper's (q_j, p_j, q_j)), solving
///   F_S = [ q_m − (h²/8) M⁻¹∇V(q_m) − (q_j + q)/2 ;                  (eq.
///   equation-milieu-intervalle)
///           p − p_j + (h/6)(∇V_j + 4∇V(q_m) + ∇V(q)) ;                (eq. simpson-hamilton, 1st)
///           q − q_j − (h²/12) M⁻¹(∇V(q) − ∇V_j) − (h/2) M⁻¹(p + p_j) ] (eq. simpson-hamilton, 2nd)
/// with the Jacobian dF_S printed in the paper (θ = (h/m)V''(q_m), φ = (h/m)V''(q) for d = 1).
template <class System>
class simpson_stepper {
  public:
    static constexpr int dim = System::dim;
    using system_type = System;
    static constexpr std::string_view scheme_name = "simpson-paper";

    simpson_stepper(System sys, double h, const newton_options& opt = {})
        : sys_(std::move(sys)), h_(h), opt_(opt) {}
    [[nodiscard]] double step_size() const { return h_; }
    [[nodiscard]] const System& system() const { return sys_; }

    newton_report step(phase_state<dim>& x) {
        constexpr int Z = blocks(3, dim);
        const int d = static_cast<int>(x.q.size());
        const auto& minv = sys_.inverse_mass();
        const auto& v = sys_.potential();
        const double h = h_;
        const vec<dim> grad_j = v.gradient(x.q);
        newton_options opt = opt_;
        opt.typical = detail::increment_scale(sys_, x, grad_j, h);
        vec<Z> z = vec<Z>::Zero(3 * d);
        const newton_report rep = newton_solve<Z>(
            z,
            [&](const vec<Z>& y, vec<Z>& r, mat<Z>& jac) {
                const vec<dim> dm = block_of<dim>(y, 0, d);
                const vec<dim> dp = block_of<dim>(y, 1, d);
                const vec<dim> dq = block_of<dim>(y, 2, d);
                const vec<dim> gm = v.gradient(x.q + dm);
                const vec<dim> gq = v.gradient(x.q + dq);
                const mat<dim> hm = v.hessian(x.q + dm);
                const mat<dim> hq = v.hessian(x.q + dq);
                // eq. equation-milieu-intervalle: q_m − (q_j + q)/2 = Δm − Δq/2
                block_of<dim>(r, 0, d) = dm - (h * h / 8.0) * minv * gm - 0.5 * dq;
                // eq. simpson-hamilton, first and second lines
                block_of<dim>(r, 1, d) = dp + (h / 6.0) * (grad_j + 4.0 * gm + gq);
                block_of<dim>(r, 2, d) =
                    dq - (h * h / 12.0) * minv * (gq - grad_j) - 0.5 * h * minv * (2.0 * x.p + dp);
                const mat<dim> id = mat<dim>::Identity(d, d);
                const mat<dim> zero = mat<dim>::Zero(d, d);
                block_of<dim>(jac, 0, 0, d) = id - (h * h / 8.0) * minv * hm;  // 1 − hθ/8
                block_of<dim>(jac, 0, 1, d) = zero;                            // 0
                block_of<dim>(jac, 0, 2, d) = -0.5 * id;                       // −1/2
                block_of<dim>(jac, 1, 0, d) = (2.0 / 3.0) * h * hm;            // (2/3) m θ
                block_of<dim>(jac, 1, 1, d) = id;                              // 1
                block_of<dim>(jac, 1, 2, d) = (h / 6.0) * hq;                  // (1/6) m φ
                block_of<dim>(jac, 2, 0, d) = zero;                            // 0
                block_of<dim>(jac, 2, 1, d) = -0.5 * h * minv;                 // −h/(2m)
                block_of<dim>(jac, 2, 2, d) = id - (h * h / 12.0) * minv * hq; // 1 − hφ/12
            },
            opt);
        if (rep.converged) {
            sum_.add_q(x, block_of<dim>(z, 2, d));
            sum_.add_p(x, block_of<dim>(z, 1, d));
        }
        return rep;
    }

  private:
    System sys_;
    double h_;
    newton_options opt_;
    compensated_update<dim> sum_;
};

} // namespace varsym::paper_reference
