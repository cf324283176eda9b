// varsym/schemes/variational_articulated.hpp: the general engine's articulated iteration
// (iteration_kind::articulated), for an L that solves with its mass matrix (a robot:
// lagrangian_with_mass_solves, multibody/articulated.hpp), and the robot predictors' increments.
//
// Each iterate evaluates L's first derivatives at the quadrature points (O(n) for a robot) and
// updates the increments with Newton's Jacobian (variational.hpp) reduced to its ∂²L/∂q̇² term
// taken at the predicted midpoint q̄ = q(t_j + h/2) of the step,
//   J ≈ (1/h) A ⊗ M(q̄),  A_il = Σ_k w_k ψ_ik ψ_lk,  so  δ_i = h Σ_l (A⁻¹)_il M(q̄)⁻¹ F_l:
// s solves with M(q̄), each O(n) by the articulated-body algorithm, where a Newton iterate costs
// O(n²) second derivatives and an O((s n)³) LU. What it leaves out (L_qq, L_qv and
// M(q_k) − M(q̄)) is O(h |q̇|) of what it keeps for a robot moving at |q̇|, so the updates shrink
// about that much each where Newton's shrink quadratically (docs/robots.md has the updates a
// step). The predictor is predict_dynamics' (q̇_j = M⁻¹p_j, q̈_j = M⁻¹(f − b), the jerk and the
// last step's miss where the step continues the last one) with M(q_j) factorised the same way.
// The iteration stops as Newton's chord updates do (newton_monitor), by an update's own
// contraction once within round-off's range, and where the residual is round-off of its own
// terms (at_round_off, scaled by the factorisation's diagonal of M); a step whose updates shrink
// by less than half twice in a row, or that runs out of iterations, goes to Newton (step()). The
// momentum is evaluated at the converged increments (momentum_change). A step depends on nothing
// that Newton's does not: the checkpoint history is Newton's (followed, under the automatic
// choice between the two, by the choice's state). docs/design.md, "The general engine".
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "varsym/schemes/variational.hpp"

namespace varsym::general {

/// The automatic iteration of a robot chooses, step by step, between Newton and the articulated
/// iteration where the break-even (the articulated updates a step at which the two cost the
/// same; the model in choose_iteration) is at least this: from 10 links of a chain on with
/// gauss-2 and Simpson (arms of 6 to 9 joints keep Newton), from 8 and 6 links with gauss-3 and
/// gauss-4 (and the UR5, iiwa and Panda with gauss-4, the Panda with gauss-3: 0.72–0.96 times
/// Newton's step, measured).
inline constexpr double choice_threshold = 3.0;
/// The same for one increment a step (gauss-1, lobatto-1), whose articulated updates shrink
/// more slowly (3.7–5.3 a step from rest on chains of 10 to 30 links): from 36 links of a chain
/// with gauss-1 and 40 with lobatto-1 (measured: the articulated iteration alone 0.97 and 0.85
/// times Newton's step at 40 and 50 links with gauss-1, the choice 0.99 and 0.94 with
/// lobatto-1; at 15 to 30 links its windows cost 2–5 %).
inline constexpr double choice_threshold_one_increment = 5.5;

/// h A⁻¹ into ainv_; throws std::invalid_argument for an L without mass solves.
template <lagrangian L, class F>
void stepper<L, F>::articulated_setup() {
    if constexpr (!lagrangian_with_mass_solves<L>) {
        throw std::invalid_argument("the articulated iteration is for robots (URDF models with a "
                                    "fixed or planar base); choose newton, simplified or "
                                    "fixed-point");
    } else {
        Eigen::MatrixXd a = Eigen::MatrixXd::Zero(s_, s_);
        for (int k = 0; k < r_; ++k)
            for (int i = 0; i < s_; ++i)
                for (int l = 0; l < s_; ++l)
                    a(i, l) += tab_.wdphi.hi(i, k) * tab_.dphi(l + 1, k);
        ainv_ = h_ * a.partialPivLu().inverse();
    }
}

/// The automatic iteration of a robot without mimic joints (mass solves in O(n)): Newton and
/// the articulated iteration chosen step by step (iteration_choice) where a model of their costs
/// puts the break-even at choice_threshold articulated updates a step or more
/// (choice_threshold_one_increment with one increment a step), Newton otherwise.
/// The model, of n coordinates, P ancestor pairs (Σ over the bodies of their ancestors: n(n − 1)/2
/// for a chain), r quadrature points and s increments, in ns measured on this project's machine
/// (clang 14 -O3; only their ratios matter): first derivatives T1 = 75 n a point, second
/// T2 = 140 n + 8.3 P, a mass solve T_s = 12 n, the Newton matrix's LU 0.05 N³ + 1.4 N²
/// (N = s n); an articulated update C_u = r T1 + s T_s; Newton's step 1.23 (r T2 + LU) + 2.4 C_u,
/// the articulated step (2.5 + u) C_u (its predictor, midpoint factorisation and momentum, then
/// u updates), both fitted to the steps of chains of 7 to 100 links and of the UR5, iiwa and
/// Panda within 10 %. They cost the same at u = 1.23 (r T2 + LU) / C_u − 0.1: with gauss-2 2.5 on
/// the UR5, 2.6 on the iiwa, 2.9 on the Panda, 3.1 at 10 links, 4.9 at 20, 13.8 at 50 and 40 at
/// 100 (docs/robots.md).
template <lagrangian L, class F>
void stepper<L, F>::choose_iteration() {
    if constexpr (lagrangian_with_mass_solves<L> && requires(const L& l) { l.robot().mimics; }) {
        const auto& t = sys_.lagrangian().robot();
        if (!t.mimics.empty()) return;
        double pairs = 0.0;
        for (const auto& b : t.bodies)
            for (int p = b.parent; p >= 0; p = t.bodies[static_cast<std::size_t>(p)].parent)
                pairs += 1.0;
        const double n = d_, N = s_ * d_;
        const double update = r_ * 75.0 * n + s_ * 12.0 * n;
        const double newton = r_ * (140.0 * n + 8.3 * pairs) + 0.05 * N * N * N + 1.4 * N * N;
        // Newton's step 1.23 newton + 2.4 update against the articulated (F + u) update, the
        // step's fixed part F = 2.5 updates being the choice's `handed`.
        const double break_even =
            (1.23 * newton + 2.4 * update) / update - iteration_choice::handed;
        if (break_even < (s_ == 1 ? choice_threshold_one_increment : choice_threshold)) return;
        choice_ = iteration_choice(break_even);
        opt_.iteration = iteration_kind::articulated;
    }
}

/// The articulated iteration from predict_articulated's increments (not converged: step() hands
/// the step to Newton).
template <lagrangian L, class F>
newton_report stepper<L, F>::solve_articulated(const phase_state<dim>& x) {
    newton_report rep;
    if constexpr (lagrangian_with_mass_solves<L>) {
        const auto& lag = sys_.lagrangian();
        if (!predict_articulated(x)) return rep; // Newton's predictor diagnoses it
        // M at the predicted midpoint: the Jacobian's Σ_k w_k ψ_ik ψ_lk M(q_k) less A_il M there
        // is still O(h |q̇|), but without the part common to every point that M(q_j) leaves.
        tab_.polynomial(x.q, x_, 0.5, qk_, vk_);
        if (!lag.factor_mass(qk_)) return rep;
        newton_options opt = opt_;
        opt.typical = x_.template lpNorm<Eigen::Infinity>();
        opt.reference = x.q.template lpNorm<Eigen::Infinity>();
        newton_monitor monitor(opt);
        linearised_ = false;
        constexpr double eps = std::numeric_limits<double>::epsilon();
        double last_theta = 0.0;
        while (true) {
            evaluate_points(x.q, false);
            assemble(x.p, false);
            rep.residual = res_.template lpNorm<Eigen::Infinity>();
            if (at_round_off(res_, x.p, false, lag.mass_diagonal())) {
                rep.iterations = monitor.iterations();
                rep.converged = true;
                return rep;
            }
            if (monitor.exhausted()) return rep;
            // M(q̄)⁻¹ F_l: the s blocks as the columns of one solve where L takes several (a
            // robot's passes then overlap: 13 % of the 100-link chain's step), else one by one.
            Eigen::Map<Eigen::MatrixXd> blocks(res_.data(), d_, s_);
            if constexpr (requires { lag.solve_mass(blocks); }) {
                lag.solve_mass(blocks);
            } else {
                for (int l = 0; l < s_; ++l) {
                    acc_ = block_of<dim>(res_, l, d_);
                    lag.solve_mass(acc_);
                    block_of<dim>(res_, l, d_) = acc_;
                }
            }
            for (int i = 0; i < s_; ++i) {
                auto update = block_of<dim>(delta_, i, d_);
                update.setZero();
                for (int l = 0; l < s_; ++l)
                    update += ainv_(i, l) * block_of<dim>(res_, l, d_);
            }
            const double step = delta_.template lpNorm<Eigen::Infinity>();
            rep.iterations = monitor.iterations() + 1;
            if (!std::isfinite(step)) return rep;
            for (int l = 0; l < s_; ++l)
                x_.col(l) -= block_of<dim>(delta_, l, d_);
            const double size = x_.template lpNorm<Eigen::Infinity>();
            const double theta = step / monitor.last_step(); // this update's contraction
            // From the second update on, stopped as a chord update (its observed rate).
            if (monitor.converged(step, size, monitor.iterations() > 0)) break;
            // Or, an update already within 64 ulp of q (where newton_monitor measures no rate), by
            // its own contraction θ from the last (from the second update on): what the next
            // would correct, θ/(1 − θ) |δ_k| with θ ≤ chord_rate_limit, is below an ulp of q, the
            // floor of a residual evaluated at q_j + X. It saves the updates that would only show
            // the floor is reached.
            const double ulp = eps * std::max({size, opt.typical, opt.reference});
            if (monitor.iterations() > 1 && step <= 64.0 * ulp && theta <= chord_rate_limit &&
                theta * step <= (1.0 - theta) * ulp)
                break;
            // Too slow, two updates in a row: Newton takes the step. Not one: a start as close
            // as the last step's miss makes it (1e-11 to 1e-12 of the 100-link chain's 1.9e-3)
            // leaves an error that the mass matrix alone corrects by half, then 100 times.
            if (theta > 0.5 && last_theta > 0.5) return rep;
            last_theta = theta;
        }
        rep.converged = true;
    }
    return rep;
}

/// predict_dynamics' increments with M(q_j) factorised by the articulated-body algorithm:
/// q̇_j = M⁻¹p_j, q̈_j = M⁻¹(f − b(q_j, q̇_j)). False where M(q_j) is not positive definite.
template <lagrangian L, class F>
bool stepper<L, F>::predict_articulated(const phase_state<dim>& x) {
    if constexpr (lagrangian_with_mass_solves<L>) {
        const auto& lag = sys_.lagrangian();
        if (!lag.factor_mass(x.q)) return false;
        vk_ = x.p;
        lag.solve_mass(vk_);
        dynamics_rhs(x); // factor_mass's kinematics kept
        acc_ = rhs_;
        lag.solve_mass(acc_);
        taylor_from_dynamics(x);
        return true;
    }
    return false;
}

/// rhs_ = f(q_j, q̇_j, t_j) − b(q_j, q̇_j) with q̇_j = vk_, the bias forces b after the mass
/// matrix's pass at q_j where L keeps its kinematics (predict_dynamics, predict_articulated).
template <lagrangian L, class F>
void stepper<L, F>::dynamics_rhs(const phase_state<dim>& x) {
    const auto& lag = sys_.lagrangian();
    if constexpr (requires { lag.bias_forces_after_mass_matrix(vk_, rhs_); })
        lag.bias_forces_after_mass_matrix(vk_, rhs_);
    else if constexpr (lagrangian_with_bias_after_mass_matrix<L>) // a free base's
        lag.bias_forces_after_mass_matrix(x.q, vk_, rhs_);
    else
        lag.bias_forces(x.q, vk_, rhs_);
    rhs_ = -rhs_;
    if constexpr (forced) {
        evaluate_force(force_, x.q, vk_, t_, fterms_[0], false);
        rhs_ += fterms_[0].f;
    }
}

/// The increments from q̇_j = vk_ and q̈_j = acc_ (predict_dynamics, predict_articulated), with
/// the jerk (a_j − a_{j−1})/h where the step continues the last one (a_{j−1} = a0_, which only
/// commit() replaces: a step that fails keeps it, for a retry from the same state), and the last
/// step's miss x_miss_ where that step took the jerk as well (commit() sets it; the Taylor
/// increments are kept in x_taylor_ for it). The miss (the local error of a third-order Taylor
/// series, and the scheme's own) changes by O(h) of itself between steps: the 100-link chain's
/// articulated iteration starts 60 times closer (its first update 1.5e-11 instead of 9e-10, of
/// increments 1.9e-3 at 1 ms).
template <lagrangian L, class F>
void stepper<L, F>::taylor_from_dynamics(const phase_state<dim>& x) {
    if constexpr (jerk_history) {
        const bool continues = continues_ && !second_order_ && x.q == q_end_ && x.p == p_end_;
        if (continues) dq_ = (acc_ - a0_) / h_; // the jerk, to O(h)
        a_next_ = acc_; // a0_ at commit(): a step predicted again (by Newton) takes the same jerk
        a0_taken_ = true;
        taylor_increments(vk_, acc_, continues ? &dq_ : nullptr);
        x_taylor_ = x_;
        jerk_taken_ = continues;
        if (continues && miss_valid_) x_ += x_miss_;
    } else {
        (void)x;
        taylor_increments(vk_, acc_);
    }
}

} // namespace varsym::general
