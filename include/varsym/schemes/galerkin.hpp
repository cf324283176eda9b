// varsym/schemes/galerkin.hpp: the variational family beyond the paper for separable systems.
// q(t) on a step is a polynomial of degree s through control values Q_0 = q_j, Q_1 … Q_{s−1},
// Q_s = q_{j+1} at the Gauss–Lobatto nodes d_0 = 0 < … < d_s = 1, and the action is integrated by
//   lobatto: the (s+1)-point Gauss–Lobatto rule (s = 1 trapezoidal/Störmer–Verlet, s = 2 the
//            paper's Simpson scheme), or
//   gauss:   the s-point Gauss–Legendre rule (s = 1 the midpoint rule: the paper's Newmark).
// Both have order 2s. For L = ½ q̇ᵀ M q̇ − V(q), with ℓ_i the Lagrange basis on the d_i,
//   L_d = (1/(2h)) Σ_{i,l} A_il Q_iᵀ M Q_l − h Σ_k w_k V(Σ_i ℓ_i(c_k) Q_i),
//   A_il = Σ_k w_k ℓ_i'(c_k) ℓ_l'(c_k)
// (the paper's eq. LLhh is the case lobatto, s = 2; docs/design.md, "The family").
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "varsym/schemes/storage.hpp"
#include "varsym/schemes/tableau.hpp"
#include "varsym/solvers/compensated.hpp"
#include "varsym/solvers/newton.hpp"
#include "varsym/systems/separable.hpp"

namespace varsym::galerkin {

/// One step solves, for the increments X_l = Q_l − q_j (l = 1 … s; X_0 = 0), the s·d equations
///   p_j + (1/h) Σ_l A_0l M X_l − h Σ_k w_k ℓ_0(c_k) ∇V(q_k) = 0     (p_j = −∂L_d/∂Q_0)
///         (1/h) Σ_l A_il M X_l − h Σ_k w_k ℓ_i(c_k) ∇V(q_k) = 0     (∂L_d/∂Q_i = 0, 0 < i < s)
/// with q_k = q_j + Σ_l ℓ_l(c_k) X_l, whose Jacobian is
///   (1/h) A_il M − h Σ_k w_k ℓ_i(c_k) ℓ_l(c_k) ∇²V(q_k).
/// Then q_{j+1} = q_j + X_s and p_{j+1} = ∂L_d/∂Q_s, which (the equations summed over i, with
/// Σ_i A_il = 0 and Σ_i ℓ_i = 1) is p_j − h Σ_k w_k ∇V(q_k).
///
/// The iteration (newton_options::iteration): Newton with that Jacobian at every iterate;
/// simplified Newton, with ∇²V at one point for every q_k, factorised once and kept across steps
/// while the updates contract by contraction_limit or faster; or the fixed point with the free
/// particle's Jacobian (1/h) A ⊗ M (the default), which needs no ∇²V. Its sweeps use the
/// equations in closed form, X = h² M⁻¹ G K + h v cᵀ (tableau::sweep, flight: one s × r
/// product), until the updates' contraction predicts the rest below round-off; one sweep with
/// the tables' low parts then lands on the exact equations' root (K and c rounded to double
/// would leave the same ulp-sized bias at every step). Simplified Newton stops only at the
/// round-off floor. If an update shrinks by less than half (diverging, or too slow), the step is
/// solved again by Newton. The start (newton_options::predictor): Taylor from (q_j, p_j); the
/// previous step's polynomial continued (tableau::extrapolation); or the previous step's
/// gradients at its quadrature points continued to this step's and put through the closed
/// form (tableau::force_extrapolation, HLW §VIII.6.1). The last two are state that
/// save_history hands to a checkpoint.
///
/// Round-off. The step is exactly symplectic only if these equations are exactly the derivatives
/// of one L_d, so the coefficients are tableau::kinetic and tableau::wphi (A_0l and ℓ_0 derived
/// from the other rows in double-double, applied as double + low part) and the weights w_k in the
/// momentum update are applied the same way; the step size enters as h and 1/h, never as a
/// separately rounded h². With plainly rounded tables the identities above miss by an ulp, always
/// the same way, and the energy drifts linearly in time (docs/design.md, "Round-off that tilts the
/// map").
///
/// The rule and degree are chosen at run time, so one compiled stepper serves every member; its
/// storage is bounded by max_degree and sized in the constructor, so a step allocates nothing
/// (for a compile-time d; a run-time d allocates only what the system's own gradient and
/// Hessian return). with_stepper runs lobatto-2 and gauss-1 on the reduced Simpson and Newmark
/// steppers instead, which solve d × d rather than 2d × 2d (always by Newton).
template <separable System>
class stepper {
  public:
    static constexpr int dim = System::dim;
    using system_type = System;

    stepper(System sys, double h, rule_kind kind, int degree, const newton_options& opt = {})
        : stepper(std::move(sys), h, tableau::make(kind, degree), opt) {}

    /// The member whose tables are `tab` (as tableau::make built them, or altered by a test).
    stepper(System sys, double h, tableau tab, const newton_options& opt = {})
        : sys_(std::move(sys)), h_(h), opt_(opt), tab_(std::move(tab)) {
        const int s = tab_.degree, r = static_cast<int>(tab_.quad.size()), d = sys_.dimension();
        // The default by measurement (docs/performance.md): the fixed point, in closed form,
        // handing a step that does not contract to Newton (against Newton: the pendulum 1.7×
        // faster at gauss-4, Kepler 2×, the outer solar system at d = 18 up to 30×; at gauss-2
        // on the pendulum the two tie).
        if (opt_.iteration == iteration_kind::automatic)
            opt_.iteration = iteration_kind::fixed_point;
        if (opt_.iteration == iteration_kind::articulated)
            throw std::invalid_argument("the articulated iteration is for robots (URDF models); "
                                        "choose newton, simplified or fixed-point");
        s_ = s;
        r_ = r;
        n_ = s * d;
        // In matrix form, with X = [X_1 … X_s] (d × s) and G = [∇V(q_1) … ∇V(q_r)] (d × r):
        //   residual R = (1/h) M X Aᵀ − h G Uᵀ + p_j e_0ᵀ,   points Q = q_j 1ᵀ + X V,
        //   Jacobian J = (1/h) A ⊗ M − h Σ_k (U_k V_kᵀ) ⊗ ∇²V(q_k),
        // with A_il = A(i, l), U_ik = w_k ℓ_i(c_k) (i < s), V_lk = ℓ_l(c_k) (l ≥ 1); A and U are
        // applied as double + low part (tableau::kinetic, tableau::wphi).
        a_ = tab_.kinetic.hi;
        a_lo_ = tab_.kinetic.lo;
        u_ = tab_.wphi.hi;
        u_lo_ = tab_.wphi.lo;
        extrapolation_t_ = tab_.extrapolation.transpose();
        sweep_t_ = tab_.sweep.hi.transpose();
        sweep_lo_t_ = tab_.sweep.lo.transpose();
        force_extrapolation_t_ = tab_.force_extrapolation.transpose();
        v_.resize(s, r);
        for (int k = 0; k < r; ++k) {
            for (int l = 0; l < s; ++l)
                v_(l, k) = tab_.phi(l + 1, k);
            // Newton evaluates ∇V and ∇²V only where a point enters the solved equations
            // (U_k ≠ 0) and moves with the unknowns (V_k ≠ 0). For Lobatto, c_0 = 0 is q_j
            // itself (its ∇V is cached) and c_s = 1 enters only p_{j+1}.
            if (u_.col(k).cwiseAbs().maxCoeff() > 0.0 && v_.col(k).cwiseAbs().maxCoeff() > 0.0)
                active_[n_active_++] = k;
            at_start_[k] = tab_.quad.nodes[k] == 0.0;
            at_end_[k] = tab_.quad.nodes[k] == 1.0;
            weight_[k] = tab_.quad.weights[k];
            weight_lo_[k] = tab_.weights_lo[static_cast<std::size_t>(k)];
        }
        for (int l = 0; l < s; ++l) {
            control_[l] = tab_.control[l + 1];
            flight_[l] = tab_.flight.hi(0, l);
            flight_lo_[l] = tab_.flight.lo(0, l);
        }
        for (auto* m : {&xm_, &mx_, &gu_, &previous_})
            m->setZero(d, s);
        for (auto* m : {&grads_, &points_, &batch_})
            m->setZero(d, r);
        previous_grads_.setZero(d, tab_.force_extrapolation.rows());
        hess_.assign(static_cast<std::size_t>(r), mat<dim>::Zero(d, d));
        curvature_.setZero(r);
        for (auto* v : {&grad_j_, &cached_q_, &q_j_, &qk_, &vel_, &acc_, &dp_, &q_bar_, &gk_})
            v->setZero(d);
        res_.setZero(n_);
        delta_.setZero(n_);
        jac_.setZero(n_, n_);
        if (opt_.iteration == iteration_kind::simplified) jinv_.setZero(n_, n_);
        if constexpr (!scalar_mass<System>) {
            const auto& m = sys_.mass();
            diagonal_mass_ = m.isDiagonal(0.0);
            mass_diagonal_ = m.diagonal();
            inverse_mass_diagonal_ = sys_.inverse_mass().diagonal();
        }
        lu_ = Eigen::PartialPivLU<jacobian_type>(n_);
    }

    [[nodiscard]] double step_size() const { return h_; }
    [[nodiscard]] const System& system() const { return sys_; }
    [[nodiscard]] const tableau& table() const { return tab_; }
    /// The compensated summation of the increments, whose carries a checkpoint keeps.
    [[nodiscard]] compensated_update<dim>& summation() { return sum_; }

    /// What the next step depends on beyond (q, p) and the carries: with predictor `previous`,
    /// whether a previous step is there to continue and its increments X (d·s numbers); with
    /// predictor `forces`, that flag, the gradients at its points (d·r) and the fixed point's
    /// last contraction rate; with iteration `simplified`, whether a Jacobian is kept and the point
    /// q̄ it was taken at (d). Empty with the default options. run_state::history keeps it for a
    /// checkpoint.
    void save_history(std::vector<double>& out) const {
        out.clear();
        if (opt_.predictor == predictor_kind::previous) {
            out.push_back(continuable_ ? 1.0 : 0.0);
            out.insert(out.end(), previous_.data(), previous_.data() + previous_.size());
        } else if (opt_.predictor == predictor_kind::forces) {
            out.push_back(continuable_ ? 1.0 : 0.0);
            out.insert(out.end(), previous_grads_.data(), previous_grads_.data() + kept_grads());
            out.push_back(carried_rate_);
        }
        if (opt_.iteration == iteration_kind::simplified) {
            out.push_back(jac_kept_ ? 1.0 : 0.0);
            out.insert(out.end(), q_bar_.data(), q_bar_.data() + q_bar_.size());
        }
    }
    /// Puts back what save_history gave after the step that ended at x: the next step from x is
    /// then the one that run would have taken; an empty history starts afresh. Throws
    /// std::invalid_argument on another wrong length.
    void restore_history(const phase_state<dim>& x, const std::vector<double>& in) {
        continuable_ = jac_kept_ = false;
        carried_rate_ = 0.0;
        if (in.empty()) return;
        const bool forces = opt_.predictor == predictor_kind::forces;
        const auto ps = static_cast<std::size_t>(forces ? kept_grads() : previous_.size());
        const auto d = static_cast<std::size_t>(sys_.dimension());
        const bool prev = opt_.predictor != predictor_kind::taylor;
        const bool simp = opt_.iteration == iteration_kind::simplified;
        const std::size_t want = (prev ? 1 + ps : 0) + (forces ? 1 : 0) + (simp ? 1 + d : 0);
        if (in.size() != want)
            throw std::invalid_argument("the saved history has " + std::to_string(in.size()) +
                                        " numbers where this stepper's options keep " +
                                        std::to_string(want));
        std::size_t at = 0;
        if (prev) {
            continuable_ = in[at++] != 0.0;
            double* kept = forces ? previous_grads_.data() : previous_.data();
            std::copy(in.begin() + static_cast<std::ptrdiff_t>(at),
                      in.begin() + static_cast<std::ptrdiff_t>(at + ps), kept);
            at += ps;
            if (forces) carried_rate_ = in[at++];
        }
        if (simp) {
            const bool kept = in[at++] != 0.0;
            std::copy(in.begin() + static_cast<std::ptrdiff_t>(at), in.end(), q_bar_.data());
            jac_kept_ = false;
            if (kept) factor(q_bar_);
        }
        cached_q_ = x.q;
        cache_valid_ = false;
    }

    newton_report step(phase_state<dim>& x) {
        const auto& v = sys_.potential();
        const double h = h_;
        const int s = s_;
        const bool continues = continuable_ && cached_q_ == x.q;
        if (!cache_valid_ || cached_q_ != x.q) gradient_into(v, x.q, grad_j_);
        newton_report rep = solve(x, opt_.iteration, continues);
        if (!rep.converged && opt_.iteration != iteration_kind::newton) {
            const int spent = rep.iterations;
            rep = solve(x, iteration_kind::newton, false);
            rep.iterations += spent;
        }
        continuable_ = false;
        if (!rep.converged) return rep;
        // p_{j+1} − p_j = −h Σ_k w_k ∇V(q_k) at the converged points. A point at c_k = 1 is the
        // new x.q, whose ∇V is kept as the next step's ∇V(q_j); a point at c_k = 0 is q_j.
        q_j_ = x.q;
        sum_.add_q(x, xm_.col(s - 1));
        // Σ_k w_k ∇V(q_k) with w_k as double + low part, then times −h.
        dp_.setZero();
        const bool has_end = converged_gradients(x);
        for (int k = 0; k < r_; ++k)
            add_weighted(k, previous_grads_.col(k));
        dp_ *= -h;
        if (has_end) grad_j_ = previous_grads_.col(r_ - 1);
        cache_valid_ = has_end;
        sum_.add_p(x, dp_);
        cached_q_ = x.q;
        if (opt_.predictor == predictor_kind::previous) previous_ = xm_;
        continuable_ = opt_.predictor != predictor_kind::taylor;
        return rep;
    }

    /// The tangent map ∂(q_{j+1}, p_{j+1})/∂(q_j, p_j) (2d × 2d, (q, p) order) of the step just
    /// taken from `from`, by the implicit function theorem on the step's equations above with
    /// their Newton Jacobian at the converged increments (galerkin_sensitivity.hpp). Call it
    /// after a converged step() with the state that step started from. Symplectic: Jᵀ Ω J = Ω.
    void step_jacobian(const phase_state<dim>& from, Eigen::MatrixXd& out) const;

    /// The step's own polynomial of degree s through its control values (q_j + X_l at d_l) on
    /// the step just taken from `from`, at τ ∈ [0, 1] (t = t_j + τh): q(τ) and dq/dτ.
    void dense_output(const phase_state<dim>& from, double tau, vec<dim>& q, vec<dim>& dq) const {
        tab_.polynomial(from.q, xm_, tau, q, dq);
    }
    /// The same stepper with another step size (for a step to a section, run/section.hpp).
    [[nodiscard]] stepper with_step_size(double h) const { return stepper(sys_, h, tab_, opt_); }

  private:
    template <class G>
    void add_weighted(int k, const Eigen::MatrixBase<G>& g) {
        dp_ += weight_[k] * g;
        dp_ += weight_lo_[k] * g;
    }

    /// Whether the potential evaluates ∇V at several points in one call (points_ → batch_).
    static constexpr bool batched =
        batch_potential<std::remove_cvref_t<decltype(std::declval<const System&>().potential())>>;
    static constexpr int max_unknowns = dim == dynamic ? dynamic : dim * max_degree;
    static constexpr int max_points = max_degree + 1;
    static constexpr bool needs_lu =
        max_unknowns == dynamic || max_unknowns > varsym::detail::small_solve_limit;
    using jacobian_type = detail::bounded_matrix<max_unknowns, max_unknowns>;
    using stage_matrix = detail::columns<dim, max_degree>;
    using point_matrix = detail::columns<dim, max_points>;
    using kept_matrix = detail::columns<dim, max_points + 1>;

    /// The starting guess: the previous step's polynomial continued, or Taylor to second order,
    /// X_l ≈ d_l h M⁻¹p − (d_l h)²/2 M⁻¹∇V(q_j).
    void predict(const phase_state<dim>& x, bool continues) {
        apply_mass<true>(vel_, x.p);
        if (continues && opt_.predictor == predictor_kind::forces) {
            if (tab_.kind == rule_kind::gauss) previous_grads_.col(r_) = grad_j_;
            detail::times_transpose(grads_, previous_grads_, force_extrapolation_t_);
            for (int k = 0; k < r_; ++k)
                if (at_start_[k]) grads_.col(k) = grad_j_;
            closed_form(xm_, false);
            return;
        }
        if (continues) {
            detail::times_transpose(xm_, previous_, extrapolation_t_);
            return;
        }
        apply_mass<true>(acc_, grad_j_);
        for (int l = 0; l < s_; ++l) {
            const double tl = control_[l] * h_;
            xm_.col(l) = tl * vel_ - (0.5 * tl * tl) * acc_;
        }
    }

    /// out = h² M⁻¹ G K + h v cᵀ for the gradients G in grads_ and v = M⁻¹ p_j in vel_: the
    /// increments whose equations the gradients G satisfy (tableau::sweep, flight); with
    /// `exact`, K and c as double + low part and G K summed with compensation
    /// (detail::times_transpose_compensated). h multiplies the values, not the constants, so
    /// that no rounded h² or h c_l biases every step alike.
    template <class Out>
    void closed_form(Out&& out, bool exact) {
        if (exact)
            detail::times_transpose_compensated(gu_, grads_, sweep_t_, sweep_lo_t_);
        else
            detail::times_transpose(gu_, grads_, sweep_t_);
        apply_mass<true>(out, h_ * (h_ * gu_));
        acc_ = h_ * vel_; // acc_ is free here: h v
        for (int l = 0; l < s_; ++l) {
            out.col(l) += flight_[l] * acc_;
            if (exact) out.col(l) += flight_lo_[l] * acc_;
        }
    }
    /// Numbers kept for predictor `forces`: the previous step's d × r gradients.
    [[nodiscard]] Eigen::Index kept_grads() const { return sys_.dimension() * r_; }
    /// ∇V at the quadrature points that move with the increments, into grads_.
    void gradients(const phase_state<dim>& x, bool hessians);
    /// A batch_potential's ∇V at the moving points, which are in points_'s first n_active_
    /// columns, into their columns of grads_.
    void active_gradients();
    /// ∇V at every quadrature point of the step just solved (q_j in q_j_, q_{j+1} in x), into
    /// previous_grads_; whether a point is at c = 1 (its ∇V is the next step's ∇V(q_j)).
    bool converged_gradients(const phase_state<dim>& x);
    /// One sweep of the fixed point (not the closing one) at d = 1: xm_ updated in place; returns
    /// the update's largest entry (NaN if not finite) and sets `size` to xm_'s.
    double scalar_sweep(const phase_state<dim>& x, double& size);

    /// Solves the step's equations by `kind` from the predictor. A simplified Newton whose kept
    /// Jacobian fails is refreshed at q_j and restarted once; one that contracted slower than
    /// contraction_limit is refreshed at the next step.
    newton_report solve(const phase_state<dim>& x, iteration_kind kind, bool continues);
    newton_report iterate(const phase_state<dim>& x, iteration_kind kind, bool continues);
    /// delta = J⁻¹ res, J in jac_: the small solve, or Eigen's LU where n can exceed its limit
    /// (not compiled for d = 1).
    void linear_solve();
    /// The simplified Newton's Jacobian, with ∇²V(q̄) at every point, inverted once.
    void factor(const vec<dim>& q_bar);
    /// The residual R = (1/h) M X Aᵀ − h G Uᵀ + p_j e_0ᵀ at the current X; with `hessians`, also
    /// ∇²V at the moving points for jacobian().
    void residual(const phase_state<dim>& x, bool hessians);
    /// J = (1/h) A ⊗ M − h Σ_k (U_k V_kᵀ) ⊗ hess_[k] into jac_.
    void jacobian();

    /// out = M in, or M⁻¹ in: a diagonal M (an N-body system's) as its diagonal, not a d × d
    /// product.
    template <bool inverse, class Out, class In>
    void apply_mass(Out&& out, const In& in) const {
        if constexpr (scalar_mass<System>)
            out = (inverse ? sys_.inverse_mass() : sys_.mass()) * in;
        else if (diagonal_mass_)
            out.noalias() = (inverse ? inverse_mass_diagonal_ : mass_diagonal_).asDiagonal() * in;
        else
            out.noalias() = (inverse ? sys_.inverse_mass() : sys_.mass()) * in;
    }

    [[nodiscard]] double mass_entry() const {
        if constexpr (scalar_mass<System>)
            return sys_.mass();
        else
            return sys_.mass()(0, 0);
    }

    System sys_;
    double h_, hinv_ = 1.0 / h_;
    newton_options opt_;
    tableau tab_;
    int s_ = 0, r_ = 0, n_ = 0;
    detail::bounded_matrix<max_degree, max_degree> a_, a_lo_, extrapolation_t_;
    detail::bounded_matrix<max_degree, max_points> u_, u_lo_, v_, sweep_t_, sweep_lo_t_;
    detail::bounded_matrix<max_points, max_points + 1> force_extrapolation_t_;
    std::array<int, max_points> active_{};
    int n_active_ = 0;
    std::array<bool, max_points> at_start_{}, at_end_{};
    std::array<double, max_points> weight_{}, weight_lo_{};
    std::array<double, max_degree> control_{}, flight_{}, flight_lo_{};
    stage_matrix xm_, mx_, gu_, previous_;
    point_matrix grads_, points_, batch_; ///< points_, batch_: a batch_potential's q and ∇V
    kept_matrix previous_grads_; ///< ∇V at the last step's points (and ∇V(q_j), Gauss)
    std::vector<mat<dim>> hess_;
    detail::bounded_vector<max_points> curvature_;
    vec<dim> grad_j_, cached_q_, q_j_, qk_, vel_, acc_, dp_, q_bar_, gk_; ///< gk_: ∇V(qk_)
    bool diagonal_mass_ = false;
    vec<dim> mass_diagonal_, inverse_mass_diagonal_;
    bool cache_valid_ = false;
    bool continuable_ =
        false;              ///< previous_ holds the increments of the step that ended at cached_q_
    bool jac_kept_ = false; ///< jinv_ holds the simplified Jacobian at q_bar_, inverted
    double rate_ = 0.0;     ///< the largest contraction rate of the last linear iteration
    double carried_rate_ = 0.0; ///< the fixed point's last measured rate (predictor forces)
    detail::bounded_vector<max_unknowns> res_, delta_;
    jacobian_type jac_, jinv_;
    Eigen::PartialPivLU<jacobian_type> lu_;
    compensated_update<dim> sum_;
};

} // namespace varsym::galerkin

#include "varsym/schemes/galerkin_sensitivity.hpp"
#include "varsym/schemes/galerkin_solve.hpp"
