// varsym/schemes/paper_reference.hpp: the paper's full per-step Newton systems, F_N (2 blocks)
// and F_S (3 blocks) with the Jacobians it prints. Slower than the reduced steppers of
// newmark.hpp and simpson.hpp; kept as the reference those are tested against.
#pragma once

#include <string_view>

#include "varsym/solvers/newton.hpp"
#include "varsym/systems/separable.hpp"

namespace varsym::paper_reference {

/// Newmark: unknowns z = (p_{j+1}, q_{j+1}), started at (p_j, q_j) as in the paper, solving
///   F_N = [ p − p_j + h ∇V((q_j + q)/2) ;  q − q_j − (h/2) M⁻¹ (p + p_j) ] = 0
/// (eq. systeme-dynamique-discret-ordre-2), Jacobian [[I, (h/2)∇²V(q̄)], [−(h/2)M⁻¹, I]].
template <class System>
class newmark_stepper {
public:
    static constexpr int dim = System::dim;
    static constexpr std::string_view scheme_name = "newmark-paper";

    newmark_stepper(System sys, double h, newton_options opt = {})
        : sys_(std::move(sys)), h_(h), opt_(opt) {}
    [[nodiscard]] double step_size() const { return h_; }
    [[nodiscard]] const System& system() const { return sys_; }

    newton_report step(phase_state<dim>& x) {
        constexpr int Z = blocks(2, dim);
        const int d = static_cast<int>(x.q.size());
        const auto& minv = sys_.inverse_mass();
        const auto& v = sys_.potential();
        const double h = h_;
        vec<Z> z(2 * d);
        z << x.p, x.q;
        const newton_report rep = newton_solve<Z>(
            z,
            [&](const vec<Z>& y, vec<Z>& r, mat<Z>& jac) {
                const auto p = y.head(d);
                const auto q = y.tail(d);
                const vec<dim> qbar = 0.5 * (x.q + q);
                r.head(d) = p - x.p + h * v.gradient(qbar);              // eq. systeme-...-ordre-2
                r.tail(d) = q - x.q - 0.5 * h * minv * (p + x.p);        // eq. systeme-...-ordre-2
                jac.setZero();
                jac.topLeftCorner(d, d).setIdentity();
                jac.topRightCorner(d, d) = 0.5 * h * v.hessian(qbar);
                jac.bottomLeftCorner(d, d) = -0.5 * h * minv;
                jac.bottomRightCorner(d, d).setIdentity();
            },
            opt_);
        if (rep.converged) {
            x.p = z.head(d);
            x.q = z.tail(d);
        }
        return rep;
    }

private:
    System sys_;
    double h_;
    newton_options opt_;
};

/// Simpson: unknowns z = (q_m, p_{j+1}, q_{j+1}), started at (q_j, p_j, q_j), solving
///   F_S = [ q_m − (h²/8) M⁻¹∇V(q_m) − (q_j + q)/2 ;                  (eq. equation-milieu-intervalle)
///           p − p_j + (h/6)(∇V_j + 4∇V(q_m) + ∇V(q)) ;                (eq. simpson-hamilton, 1st)
///           q − q_j − (h²/12) M⁻¹(∇V(q) − ∇V_j) − (h/2) M⁻¹(p + p_j) ] (eq. simpson-hamilton, 2nd)
/// with the Jacobian dF_S printed in the paper (θ = (h/m)V''(q_m), φ = (h/m)V''(q) for d = 1).
template <class System>
class simpson_stepper {
public:
    static constexpr int dim = System::dim;
    static constexpr std::string_view scheme_name = "simpson-paper";

    simpson_stepper(System sys, double h, newton_options opt = {})
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
        vec<Z> z(3 * d);
        z << x.q, x.p, x.q;
        const newton_report rep = newton_solve<Z>(
            z,
            [&](const vec<Z>& y, vec<Z>& r, mat<Z>& jac) {
                const vec<dim> qm = y.segment(0, d);
                const vec<dim> p = y.segment(d, d);
                const vec<dim> q = y.segment(2 * d, d);
                const vec<dim> gm = v.gradient(qm);
                const vec<dim> gq = v.gradient(q);
                const mat<dim> hm = v.hessian(qm);
                const mat<dim> hq = v.hessian(q);
                r.segment(0, d) = qm - (h * h / 8.0) * minv * gm - 0.5 * (x.q + q);
                r.segment(d, d) = p - x.p + (h / 6.0) * (grad_j + 4.0 * gm + gq);
                r.segment(2 * d, d) =
                    q - x.q - (h * h / 12.0) * minv * (gq - grad_j) - 0.5 * h * minv * (p + x.p);
                const mat<dim> id = mat<dim>::Identity(d, d);
                jac.setZero();
                jac.block(0, 0, d, d) = id - (h * h / 8.0) * minv * hm; // 1 − hθ/8
                jac.block(0, 2 * d, d, d) = -0.5 * id;                  // −1/2
                jac.block(d, 0, d, d) = (2.0 / 3.0) * h * hm;           // (2/3) m θ
                jac.block(d, d, d, d) = id;                             // 1
                jac.block(d, 2 * d, d, d) = (h / 6.0) * hq;             // (1/6) m φ
                jac.block(2 * d, d, d, d) = -0.5 * h * minv;            // −h/(2m)
                jac.block(2 * d, 2 * d, d, d) = id - (h * h / 12.0) * minv * hq; // 1 − hφ/12
            },
            opt_);
        if (rep.converged) {
            x.p = z.segment(d, d);
            x.q = z.segment(2 * d, d);
        }
        return rep;
    }

private:
    System sys_;
    double h_;
    newton_options opt_;
};

} // namespace varsym::paper_reference
