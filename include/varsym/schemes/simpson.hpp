// varsym/schemes/simpson.hpp: the paper's nonlinear Simpson scheme, P2 interpolation on the
// nodes 0, ½, 1 + Simpson's rule; 4th order.
#pragma once

#include <string_view>

#include "varsym/solvers/compensated.hpp"
#include "varsym/solvers/stage_equation.hpp"
#include "varsym/systems/separable.hpp"

namespace varsym::simpson {

inline constexpr std::string_view name = "simpson";
inline constexpr int order = 4;

/// L_S(q_l, q_m, q_r) = (h/12)(g_lᵀMg_l + 4 g_mᵀMg_m + g_rᵀMg_r) − (h/6)(V_l + 4 V_m + V_r)
/// (paper eq. LLhh, with m → M), where g_l, g_m, g_r are the slopes of eqs. derivees-gear and
/// derivee-centree.
template <class System>
double discrete_lagrangian(const System& sys, double h, const vec<System::dim>& ql,
                           const vec<System::dim>& qm, const vec<System::dim>& qr) {
    const auto& m = sys.mass();
    const auto& v = sys.potential();
    const vec<System::dim> gl = (-3.0 * ql + 4.0 * qm - qr) / h; // eq. derivees-gear
    const vec<System::dim> gr = (ql - 4.0 * qm + 3.0 * qr) / h;  // eq. derivees-gear
    const vec<System::dim> gm = (qr - ql) / h;                   // eq. derivee-centree
    return h / 12.0 * (gl.dot(m * gl) + 4.0 * gm.dot(m * gm) + gr.dot(m * gr)) -
           h / 6.0 * (v.value(ql) + 4.0 * v.value(qm) + v.value(qr));
}

/// y = M⁻¹ g for a separable system, to the last bit that a division or one refinement step
/// gives: a product with the rounded M⁻¹ alone would be the same tilt of every step. `t` is
/// scratch (the refinement's residual).
template <class System>
void solve_mass(const System& sys, const vec<System::dim>& g, vec<System::dim>& y,
                vec<System::dim>& t) {
    if constexpr (scalar_mass<System>) {
        y = g / sys.mass();
    } else {
        y.noalias() = sys.inverse_mass() * g;
        t.noalias() = sys.mass() * y;
        t = g - t;
        y.noalias() += sys.inverse_mass() * t;
    }
}

/// One step of eqs. equation-milieu-intervalle and simpson-hamilton in their reduced form
/// (docs/design.md, "Reduced steps"): one D×D Newton solve for the midpoint q_m = q_{j+½}, then
/// explicit updates. Increments are accumulated with compensated summation
/// (solvers/compensated.hpp); Update = plain_update<D> adds them plainly (the baseline of `make
/// soak`). ∇V(q_{j+1}) of a step is kept as ∇V(q_j) of the next (recomputed if the state was
/// changed).
template <class System, class Update = compensated_update<System::dim>>
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
    /// The internal value q_{j+½} of the last successful step.
    [[nodiscard]] const vec<dim>& last_stage() const { return stage_; }

    newton_report step(phase_state<dim>& x) {
        const auto& minv = sys_.inverse_mass();
        const auto& v = sys_.potential();
        if (!cache_valid_ || cached_q_ != x.q) gradient_into(v, x.q, grad_);
        const double h = h_;
        // Predictor: q_m − q_j ≈ (h/2) M⁻¹p − (h²/8) M⁻¹∇V(q).
        r_ = 0.5 * h * x.p - 0.125 * h * h * grad_;
        delta_.noalias() = minv * r_;
        // M q_m + (h²/24) ∇V(q_m) = M q_j + (h/2) p_j − (h²/12) ∇V(q_j)
        // (eqs. equation-milieu-intervalle + simpson-hamilton, reduced), solved for δ = q_m − q_j.
        // Every later coefficient is derived from c = fl(h²/24) and e = h/2 by operations on the
        // data, never as a separately rounded constant, so that the step is exactly the map of
        // one discrete Lagrangian (docs/design.md, "Round-off that tilts the map"): h²/12 = 2c,
        // h²/4 = 6c, h/6 = 2c/e.
        const double c = h * h / 24.0, e = 0.5 * h;
        r_ = e * x.p - (2.0 * c) * grad_;
        const newton_report rep = solve_stage_increment(sys_, c, x.q, r_, delta_, opt_, stage_ws_);
        if (!rep.converged) return rep;
        stage_ = x.q + delta_;
        gradient_into(v, stage_, grad_m_);
        // q_{j+1} − q_j = 2 δ − (h²/4) M⁻¹ ∇V_m   (eq. simpson-hamilton with the midpoint row)
        r_ = c * grad_m_;
        solve_mass(sys_, r_, inc_, grad_r_);
        inc_ = 2.0 * delta_ - 6.0 * inc_;
        sum_.add_q(x, inc_);
        gradient_into(v, x.q, grad_r_);
        // p_{j+1} = p_j − (h/6) (∇V_j + 4 ∇V_m + ∇V_{j+1})   (eq. simpson-hamilton, 1st line)
        inc_ = -(2.0 * (c * (grad_ + 4.0 * grad_m_ + grad_r_))) / e;
        sum_.add_p(x, inc_);
        grad_.swap(grad_r_);
        cached_q_ = x.q;
        cache_valid_ = true;
        return rep;
    }

    /// The tangent map ∂(q_{j+1}, p_{j+1})/∂(q_j, p_j) (2d × 2d, (q, p) order) of the step just
    /// taken from `from`: the step's equations above differentiated (implicit function theorem),
    /// with the Newton matrix N = M + c ∇²V(q_m) of the midpoint equation. Call it after a
    /// converged step() with the state that step started from. Symplectic: Jᵀ Ω J = Ω.
    void step_jacobian(const phase_state<dim>& from, Eigen::MatrixXd& out) const {
        const int d = sys_.dimension();
        const auto& v = sys_.potential();
        const double c = h_ * h_ / 24.0, e = 0.5 * h_;
        const mat<dim> hj = v.hessian(from.q), hm = v.hessian(stage_), hr = v.hessian(cached_q_);
        const mat<dim> id = mat<dim>::Identity(d, d);
        const Eigen::PartialPivLU<mat<dim>> lu(stage_jacobian(sys_, c, hm));
        // N dδ = e dp_j − c (2 ∇²V_j + ∇²V_m) dq_j   (the midpoint equation differentiated)
        const mat<dim> dq_m_q = id + lu.solve(mat<dim>(-c * (2.0 * hj + hm)));
        const mat<dim> dq_m_p = lu.solve(mat<dim>(e * id));
        // dq_{j+1} = dq_j + 2 dδ − 6c M⁻¹ ∇²V_m dq_m   (eq. simpson-hamilton, midpoint row)
        const mat<dim> mh = sys_.inverse_mass() * (6.0 * c * hm);
        const mat<dim> dq_q = 2.0 * dq_m_q - id - mh * dq_m_q;
        const mat<dim> dq_p = 2.0 * dq_m_p - mh * dq_m_p;
        // dp_{j+1} = dp_j − (h/6)(∇²V_j dq_j + 4 ∇²V_m dq_m + ∇²V_{j+1} dq_{j+1})
        // (eq. simpson-hamilton, 1st line)
        const double k = 2.0 * c / e;
        out.resize(2 * d, 2 * d);
        detail::assign_elementwise(out.topLeftCorner(d, d), dq_q);
        detail::assign_elementwise(out.topRightCorner(d, d), dq_p);
        detail::assign_elementwise(out.bottomLeftCorner(d, d),
                                   mat<dim>(-k * (hj + 4.0 * hm * dq_m_q + hr * dq_q)));
        detail::assign_elementwise(out.bottomRightCorner(d, d),
                                   mat<dim>(id - k * (4.0 * hm * dq_m_p + hr * dq_p)));
    }

    /// The scheme's own interpolating polynomial on the step just taken from `from` (paper: P2
    /// through q_j, q_{j+½}, q_{j+1}) at τ ∈ [0, 1] (t = t_j + τh): q(τ) and dq/dτ.
    void dense_output(const phase_state<dim>& from, double tau, vec<dim>& q, vec<dim>& dq) const {
        const double l0 = (2.0 * tau - 1.0) * (tau - 1.0), lm = 4.0 * tau * (1.0 - tau),
                     l1 = tau * (2.0 * tau - 1.0);
        q = l0 * from.q + lm * stage_ + l1 * cached_q_;
        dq =
            (4.0 * tau - 3.0) * from.q + (4.0 - 8.0 * tau) * stage_ + (4.0 * tau - 1.0) * cached_q_;
    }
    /// The same stepper with another step size (for a step to a section, run/section.hpp).
    [[nodiscard]] stepper with_step_size(double h) const { return stepper(sys_, h, opt_); }

  private:
    System sys_;
    double h_;
    newton_options opt_;
    vec<dim> grad_{};
    vec<dim> stage_{};
    // The step's scratch, kept so that a step at a run-time d allocates nothing: the predictor's
    // and right-hand side's r, δ, ∇V at the midpoint and at the end, an increment.
    vec<dim> r_{}, delta_{}, grad_m_{}, grad_r_{}, inc_{};
    stage_workspace_of<System> stage_ws_{};
    Update sum_;
    vec<dim> cached_q_{};
    bool cache_valid_ = false;
};

} // namespace varsym::simpson
