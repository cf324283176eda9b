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

#include <array>
#include <cmath>
#include <type_traits>
#include <utility>
#include <vector>

#include "varsym/schemes/tableau.hpp"
#include "varsym/solvers/compensated.hpp"
#include "varsym/solvers/newton.hpp"
#include "varsym/systems/separable.hpp"

namespace varsym::galerkin {

namespace detail {
/// A run-time-sized matrix bounded by MaxR × MaxC: stored inside the object (Eigen's fixed
/// maximum sizes) when both bounds are known and the block is small, else on the heap, sized
/// once by the stepper's constructor. Either way a step allocates nothing.
template <int MaxR, int MaxC>
constexpr bool inline_storage = MaxR != dynamic&& MaxC != dynamic&& MaxR* MaxC <= 1024;
template <int MaxR, int MaxC>
using bounded_matrix = std::conditional_t<
    inline_storage<MaxR, MaxC>,
    Eigen::Matrix<double, dynamic, dynamic,
                  (MaxR == 1 && MaxC != 1) ? Eigen::RowMajor : Eigen::ColMajor, MaxR, MaxC>,
    Eigen::MatrixXd>;
template <int MaxN>
using bounded_vector =
    std::conditional_t<inline_storage<MaxN, 1>, Eigen::Matrix<double, dynamic, 1, 0, MaxN, 1>,
                       Eigen::VectorXd>;
/// d × k blocks of k ≤ MaxK columns (stage increments, gradients at the quadrature points).
template <int D, int MaxK>
using columns = Eigen::Matrix<double, D, dynamic, D == 1 ? Eigen::RowMajor : Eigen::ColMajor, D,
                              D == dynamic ? dynamic : MaxK>;
} // namespace detail

/// One step solves, for the increments X_l = Q_l − q_j (l = 1 … s; X_0 = 0), the s·d equations
///   p_j + (1/h) Σ_l A_0l M X_l − h Σ_k w_k ℓ_0(c_k) ∇V(q_k) = 0     (p_j = −∂L_d/∂Q_0)
///         (1/h) Σ_l A_il M X_l − h Σ_k w_k ℓ_i(c_k) ∇V(q_k) = 0     (∂L_d/∂Q_i = 0, 0 < i < s)
/// with q_k = q_j + Σ_l ℓ_l(c_k) X_l, by Newton with the exact Jacobian
///   (1/h) A_il M − h Σ_k w_k ℓ_i(c_k) ℓ_l(c_k) ∇²V(q_k).
/// Then q_{j+1} = q_j + X_s and p_{j+1} = ∂L_d/∂Q_s, which (the equations summed over i, with
/// Σ_i A_il = 0 and Σ_i ℓ_i = 1) is p_j − h Σ_k w_k ∇V(q_k).
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
/// steppers instead, which solve d × d rather than 2d × 2d.
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
        for (int l = 0; l < s; ++l)
            control_[l] = tab_.control[l + 1];
        xm_.setZero(d, s);
        mx_.setZero(d, s);
        gu_.setZero(d, s);
        grads_.setZero(d, r);
        hess_.assign(static_cast<std::size_t>(r), mat<dim>::Zero(d, d));
        curvature_.setZero(r);
        for (auto* v : {&grad_j_, &cached_q_, &q_j_, &qk_, &vel_, &acc_, &dp_})
            v->setZero(d);
        res_.setZero(n_);
        delta_.setZero(n_);
        jac_.setZero(n_, n_);
        lu_ = Eigen::PartialPivLU<jacobian_type>(n_);
    }

    [[nodiscard]] double step_size() const { return h_; }
    [[nodiscard]] const System& system() const { return sys_; }
    [[nodiscard]] const tableau& table() const { return tab_; }
    /// The compensated summation of the increments, whose carries a checkpoint keeps.
    [[nodiscard]] compensated_update<dim>& summation() { return sum_; }

    newton_report step(phase_state<dim>& x) {
        const auto& v = sys_.potential();
        const double h = h_;
        const int s = s_, d = sys_.dimension();
        if (!cache_valid_ || cached_q_ != x.q) grad_j_ = v.gradient(x.q);
        // Predictor: Taylor to second order, X_l ≈ d_l h M⁻¹p − (d_l h)²/2 M⁻¹∇V(q_j).
        vel_.noalias() = sys_.inverse_mass() * x.p;
        acc_.noalias() = sys_.inverse_mass() * grad_j_;
        for (int l = 0; l < s; ++l) {
            const double tl = control_[l] * h;
            xm_.col(l) = tl * vel_ - (0.5 * tl * tl) * acc_;
        }
        newton_options opt = opt_;
        opt.typical = xm_.template lpNorm<Eigen::Infinity>();
        opt.reference = x.q.template lpNorm<Eigen::Infinity>();
        newton_monitor monitor(opt);
        newton_report rep;
        while (true) {
            assemble(x);
            rep.residual = res_.template lpNorm<Eigen::Infinity>();
            if (monitor.exhausted()) return rep;
            [[maybe_unused]] const bool small = varsym::detail::solve_small(
                n_, jac_.data(), jac_.outerStride(), res_.data(), delta_.data());
            // Eigen's LU only where n can exceed the small solve's limit (not compiled for d = 1).
            if constexpr (max_unknowns == dynamic || max_unknowns > detail_small_limit) {
                if (!small) {
                    lu_.compute(jac_);
                    delta_.noalias() = lu_.solve(res_);
                }
            }
            const double step = delta_.template lpNorm<Eigen::Infinity>();
            rep.iterations = monitor.iterations() + 1;
            if (!std::isfinite(step) || !std::isfinite(rep.residual)) return rep;
            xm_ -= Eigen::Map<const stage_matrix>(delta_.data(), d, s);
            if (monitor.converged(step, xm_.template lpNorm<Eigen::Infinity>())) break;
        }
        rep.converged = true;
        // p_{j+1} − p_j = −h Σ_k w_k ∇V(q_k) at the converged points. A point at c_k = 1 is the
        // new x.q, whose ∇V is kept as the next step's ∇V(q_j); a point at c_k = 0 is q_j.
        q_j_ = x.q;
        sum_.add_q(x, xm_.col(s - 1));
        // Σ_k w_k ∇V(q_k) with w_k as double + low part, then times −h.
        dp_.setZero();
        bool has_end = false;
        for (int k = 0; k < r_; ++k) {
            if (at_end_[k]) {
                acc_ = v.gradient(x.q); // ∇V(q_{j+1}); acc_ is free until the next predictor
                add_weighted(k, acc_);
                has_end = true;
            } else if (at_start_[k]) {
                add_weighted(k, grad_j_);
            } else {
                qk_ = q_j_;
                qk_.noalias() += xm_.lazyProduct(v_.col(k));
                add_weighted(k, v.gradient(qk_));
            }
        }
        dp_ *= -h;
        if (has_end) grad_j_ = acc_;
        cache_valid_ = has_end;
        sum_.add_p(x, dp_);
        cached_q_ = x.q;
        return rep;
    }

  private:
    void add_weighted(int k, const vec<dim>& g) {
        dp_ += weight_[k] * g;
        dp_ += weight_lo_[k] * g;
    }

    static constexpr int max_unknowns = dim == dynamic ? dynamic : dim * max_degree;
    static constexpr int max_points = max_degree + 1;
    static constexpr int detail_small_limit = varsym::detail::small_solve_limit;
    using jacobian_type = detail::bounded_matrix<max_unknowns, max_unknowns>;
    using stage_matrix = detail::columns<dim, max_degree>;
    using point_matrix = detail::columns<dim, max_points>;

    /// The residual R = (1/h) M X Aᵀ − h G Uᵀ + p_j e_0ᵀ and its Jacobian at the current X.
    void assemble(const phase_state<dim>& x) {
        const auto& v = sys_.potential();
        const int s = s_, d = sys_.dimension();
        for (int k = 0; k < r_; ++k) {
            if (at_start_[k])
                grads_.col(k) = grad_j_;
            else
                grads_.col(k).setZero();
        }
        for (int a = 0; a < n_active_; ++a) {
            const int k = active_[a];
            qk_ = x.q;
            qk_.noalias() += xm_.lazyProduct(v_.col(k));
            grads_.col(k) = v.gradient(qk_);
            hess_[k] = v.hessian(qk_);
        }
        Eigen::Map<stage_matrix> rm(res_.data(), d, s);
        if constexpr (scalar_mass<System>)
            mx_ = sys_.mass() * xm_;
        else
            mx_.noalias() = sys_.mass() * xm_;
        // Coefficient-based (lazy) products: these blocks have at most max_degree + 1 columns,
        // where Eigen's run-time choice of a blocked product costs more than the product.
        rm.noalias() = mx_.lazyProduct(a_.transpose());
        rm.noalias() += mx_.lazyProduct(a_lo_.transpose());
        rm *= hinv_;
        gu_.noalias() = grads_.lazyProduct(u_.transpose());
        gu_.noalias() += grads_.lazyProduct(u_lo_.transpose());
        rm.noalias() -= h_ * gu_;
        rm.col(0) += x.p;
        if (d == 1) {
            // d = 1: J = (m/h) A − h U diag(∇²V(q_k)) Vᵀ.
            curvature_.setZero();
            for (int a = 0; a < n_active_; ++a)
                curvature_(active_[a]) = hess_[active_[a]](0, 0);
            for (int i = 0; i < s; ++i)
                for (int l = 0; l < s; ++l) {
                    double c = 0.0;
                    for (int a = 0; a < n_active_; ++a)
                        c += u_(i, active_[a]) * curvature_(active_[a]) * v_(l, active_[a]);
                    jac_(i, l) = hinv_ * mass_entry() * a_(i, l) - h_ * c;
                }
            return;
        }
        for (int i = 0; i < s; ++i)
            for (int l = 0; l < s; ++l) {
                auto block = block_of<dim>(jac_, i, l, d);
                if constexpr (scalar_mass<System>) {
                    block.setZero();
                    block.diagonal().setConstant(hinv_ * a_(i, l) * sys_.mass());
                } else {
                    block = (hinv_ * a_(i, l)) * sys_.mass();
                }
                for (int a = 0; a < n_active_; ++a) {
                    const int k = active_[a];
                    const double c = h_ * u_(i, k) * v_(l, k);
                    if (c != 0.0) block -= c * hess_[k];
                }
            }
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
    detail::bounded_matrix<max_degree, max_degree> a_, a_lo_;
    detail::bounded_matrix<max_degree, max_points> u_, u_lo_, v_;
    std::array<int, max_points> active_{};
    int n_active_ = 0;
    std::array<bool, max_points> at_start_{}, at_end_{};
    std::array<double, max_points> weight_{}, weight_lo_{};
    std::array<double, max_degree> control_{};
    stage_matrix xm_, mx_, gu_;
    point_matrix grads_;
    std::vector<mat<dim>> hess_;
    detail::bounded_vector<max_points> curvature_;
    vec<dim> grad_j_, cached_q_, q_j_, qk_, vel_, acc_, dp_;
    bool cache_valid_ = false;
    detail::bounded_vector<max_unknowns> res_, delta_;
    jacobian_type jac_;
    Eigen::PartialPivLU<jacobian_type> lu_;
    compensated_update<dim> sum_;
};

} // namespace varsym::galerkin
