// varsym/schemes/newmark.hpp: the paper's "Newmark" scheme, P1 interpolation + midpoint rule.
#pragma once

#include <string_view>

#include "varsym/solvers/compensated.hpp"
#include "varsym/solvers/stage_equation.hpp"
#include "varsym/systems/separable.hpp"

namespace varsym::newmark {

inline constexpr std::string_view name = "newmark";
inline constexpr int order = 2;

/// L_N(q_l, q_r) = (h/2) ġᵀ M ġ − h V((q_l + q_r)/2), ġ = (q_r − q_l)/h
/// (paper eq. lagrangien-discret, with m → M).
template <class System>
double discrete_lagrangian(const System& sys, double h, const vec<System::dim>& ql,
                           const vec<System::dim>& qr) {
    const vec<System::dim> g = (qr - ql) / h;
    return 0.5 * h * g.dot(sys.mass() * g) - h * sys.potential().value(0.5 * (ql + qr));
}

/// One step (q_j, p_j) ↦ (q_{j+1}, p_{j+1}) of eq. systeme-dynamique-discret-ordre-2 in its
/// reduced form (docs/design.md, "Reduced steps"): one D×D Newton solve for the midpoint q̄ = (q_j +
/// q_{j+1})/2. The increments are accumulated with compensated summation (solvers/compensated.hpp).
template <class System>
class stepper {
  public:
    static constexpr int dim = System::dim;
    using system_type = System;
    static constexpr std::string_view scheme_name = name;

    stepper(System sys, double h, const newton_options& opt = {})
        : sys_(std::move(sys)), h_(h), opt_(opt) {}

    [[nodiscard]] double step_size() const { return h_; }
    [[nodiscard]] const System& system() const { return sys_; }
    /// The compensated summation of the increments, whose carries a checkpoint keeps.
    [[nodiscard]] auto& summation() { return sum_; }

    newton_report step(phase_state<dim>& x) {
        const auto& minv = sys_.inverse_mass();
        const double h = h_;
        // Predictor: Taylor to second order, q̄ − q_j ≈ (h/2) M⁻¹p − (h²/8) M⁻¹∇V(q).
        gradient_into(sys_.potential(), x.q, grad_);
        r_ = 0.5 * h * x.p - 0.125 * h * h * grad_;
        delta_.noalias() = minv * r_;
        // M q̄ + (h²/4) ∇V(q̄) = M q_j + (h/2) p_j  (eq. systeme-dynamique-discret-ordre-2, reduced),
        // solved for δ = q̄ − q_j:  M δ + (h²/4) ∇V(q_j + δ) = (h/2) p_j
        const double c = 0.25 * h * h;
        r_ = 0.5 * h * x.p;
        const newton_report rep = solve_stage_increment(sys_, c, x.q, r_, delta_, opt_, stage_ws_);
        if (!rep.converged) return rep;
        // q_{j+1} = 2 q̄ − q_j, p_{j+1} = p_j − h ∇V(q̄)  (eq. systeme-dynamique-discret-ordre-2),
        // with h written (c/(h/4)) from the stage equation's own rounded c = fl(h²/4): the step is
        // then exactly the map of one discrete Lagrangian (docs/design.md, "Round-off that tilts
        // the map").
        mid_ = x.q + delta_;
        gradient_into(sys_.potential(), mid_, grad_);
        r_ = 2.0 * delta_;
        sum_.add_q(x, r_);
        r_ = -(c * grad_) / (0.25 * h);
        sum_.add_p(x, r_);
        return rep;
    }

    /// The tangent map ∂(q_{j+1}, p_{j+1})/∂(q_j, p_j) (2d × 2d, (q, p) order) of the step just
    /// taken from `from`: the step's equations differentiated (implicit function theorem), with
    /// the Newton matrix N = M + (h²/4) ∇²V(q̄). Call it after a converged step() with the state
    /// that step started from. Symplectic: Jᵀ Ω J = Ω.
    void step_jacobian(const phase_state<dim>& /*from*/, Eigen::MatrixXd& out) const {
        const int d = sys_.dimension();
        const double c = 0.25 * h_ * h_;
        const mat<dim> hm = sys_.potential().hessian(mid_), id = mat<dim>::Identity(d, d);
        const Eigen::PartialPivLU<mat<dim>> lu(stage_jacobian(sys_, c, hm));
        // N dδ = (h/2) dp_j − c ∇²V(q̄) dq_j;  dq̄ = dq_j + dδ, dq_{j+1} = dq_j + 2 dδ,
        // dp_{j+1} = dp_j − h ∇²V(q̄) dq̄   (eq. systeme-dynamique-discret-ordre-2 differentiated)
        const mat<dim> dd_q = lu.solve(mat<dim>(-c * hm)), dd_p = lu.solve(mat<dim>(0.5 * h_ * id));
        out.resize(2 * d, 2 * d);
        detail::assign_elementwise(out.topLeftCorner(d, d), mat<dim>(id + 2.0 * dd_q));
        detail::assign_elementwise(out.topRightCorner(d, d), mat<dim>(2.0 * dd_p));
        detail::assign_elementwise(out.bottomLeftCorner(d, d), mat<dim>(-h_ * hm * (id + dd_q)));
        detail::assign_elementwise(out.bottomRightCorner(d, d), mat<dim>(id - h_ * hm * dd_p));
    }

    /// The scheme's own interpolating polynomial on the step just taken from `from` (P1) at
    /// τ ∈ [0, 1] (t = t_j + τh): q(τ) = q_j + 2τ (q̄ − q_j) and dq/dτ.
    void dense_output(const phase_state<dim>& from, double tau, vec<dim>& q, vec<dim>& dq) const {
        dq = 2.0 * (mid_ - from.q);
        q = from.q + tau * dq;
    }
    /// The same stepper with another step size (for a step to a section, run/section.hpp).
    [[nodiscard]] stepper with_step_size(double h) const { return stepper(sys_, h, opt_); }

  private:
    System sys_;
    double h_;
    newton_options opt_;
    compensated_update<dim> sum_;
    vec<dim> mid_{}; ///< q̄ of the last successful step
    // The step's scratch, kept so that a step at a run-time d allocates nothing.
    vec<dim> grad_{}, r_{}, delta_{};
    stage_workspace_of<System> stage_ws_{};
};

} // namespace varsym::newmark
