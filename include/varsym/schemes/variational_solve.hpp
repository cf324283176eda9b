// varsym/schemes/variational_solve.hpp: the general engine's iterations, predictors and momentum
// (variational.hpp): Newton with chord updates, and the linear iterations:
//
// simplified: the Jacobian of the step's equations (variational.hpp) with L's second
// derivatives at one point (q̄, v̄) = (q_j, the predicted q̇_j) in every quadrature term;
// fixed_point: only its ∂²L/∂q̇² term, (1/h) A ⊗ L_vv(q̄, v̄), the free particle's. Either is
// inverted once and kept across steps while each update shrinks at least 1/contraction_limit
// times; the sweeps evaluate L's first derivatives only. They stop at the same round-off floor
// as Newton (newton_monitor, linear), and hand the step to Newton when an update shrinks by less
// than half even with a fresh Jacobian. Newton also stops, before an update, where the residual
// is round-off of its own terms (at_round_off). docs/design.md, "The general engine".
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "varsym/schemes/variational.hpp"

namespace varsym::general {

template <lagrangian L, class F>
newton_report stepper<L, F>::solve_linear(const phase_state<dim>& x) {
    bool fresh = false;
    if (kept_) {
        predict_kept(x);
    } else {
        predict(x); // the full Taylor predictor leaves the derivatives at (q̄, v̄) in terms_[0]
        refresh(terms_[0]);
        fresh = true;
    }
    newton_report rep = iterate(x, false);
    if (!rep.converged && !fresh) {
        const int spent = rep.iterations;
        predict(x);
        refresh(terms_[0]);
        rep = iterate(x, false);
        rep.iterations += spent;
    }
    kept_ = rep.converged && rate_ <= opt_.contraction_limit;
    return rep;
}

/// Newton or a linear iteration (the kept inverse, first derivatives only), from the predicted
/// increments. Newton takes the Jacobian from every point's second derivatives, and keeps it
/// for the next iterate (a chord update: first derivatives and a solve with the same LU) once
/// an update is below newton_options::chord_start of the increments, while the chord updates
/// shrink at least 1/min(contraction_limit, chord_rate_limit) times; one that does not is dropped,
/// and the solve goes on as full Newton from the same iterate. From the Taylor predictor at small
/// steps (a robot at 1 ms) the first Newton update already lands within round-off: the residual
/// there, first derivatives alone, is then round-off of its own terms (at_round_off) and ends the
/// solve, or the second update, which only confirms it, costs a solve with the same LU. Each
/// Newton iterate is checked so before its update, the predictor's included. (Not the linear
/// iterations: their ∂²L/∂q̇², which the check scales by, may be another step's, and their runs
/// must repeat to the bit across a checkpoint.)
template <lagrangian L, class F>
newton_report stepper<L, F>::iterate(const phase_state<dim>& x, bool newton) {
    newton_options opt = opt_;
    opt.typical = x_.template lpNorm<Eigen::Infinity>();
    opt.reference = x.q.template lpNorm<Eigen::Infinity>();
    newton_monitor monitor(opt, !newton);
    chord_policy chords(opt); // Newton's
    newton_report rep;
    rate_ = 0.0;
    linearised_ = false;
    while (true) {
        const bool chord = newton && chords.chord(); // this iterate keeps the last Jacobian
        evaluate_points(x.q, newton && !chord);
        assemble(x.p, newton && !chord);
        rep.residual = res_.template lpNorm<Eigen::Infinity>();
        if (newton && at_round_off(res_, x.p, false, terms_[0].lvv.diagonal())) {
            // The residual is round-off of its own terms: no update could be told from noise.
            // The momentum then comes from this iterate's L_q as evaluated (no update to correct
            // for: momentum_change_linearised with δ = 0).
            delta_.setZero();
            linearised_ = true;
            rep.iterations = monitor.iterations();
            rep.converged = true;
            return rep;
        }
        if (monitor.exhausted()) return rep;
        if (newton) {
            if (!chord) lu_.compute(jac_);
            lu_.solve(res_, delta_);
        } else {
            delta_.noalias() = jinv_ * res_;
        }
        const double step = delta_.template lpNorm<Eigen::Infinity>();
        rep.iterations = monitor.iterations() + 1;
        if (!std::isfinite(rep.residual)) return rep;
        if (chord && !(chords.contracts(step) || chords.at_noise(step))) {
            // A chord update that does not contract fast enough is not taken: this iterate is
            // Newton's after all, and the rest of the solve too (full Newton's iterates).
            chords.drop();
            continue;
        }
        if (!std::isfinite(step)) return rep;
        for (int l = 0; l < s_; ++l)
            x_.col(l) -= block_of<dim>(delta_, l, d_);
        const double size = x_.template lpNorm<Eigen::Infinity>();
        if (monitor.converged(step, size, chord)) {
            // The momentum from this iterate (momentum_change_linearised) where what its
            // linearisation leaves is below ε (chord_policy::linearisable).
            linearised_ = newton && chords.linearisable(step, size);
            break;
        }
        if (newton) {
            chords.taken(step, size);
            continue;
        }
        if (monitor.iterations() > 1) {
            rate_ = std::max(rate_, monitor.rate());
            if (monitor.rate() > 0.5) return rep; // diverging, or slower than Newton
        }
    }
    rep.converged = true;
    return rep;
}

/// Point k's terms in block (i, l) of the step's Jacobian, ∂F_i/∂X_l (assemble()):
///   h φ̂_ik φ_lk L_qq + φ̂_ik ψ_lk L_qv + ψ̂_ik φ_lk L_qvᵀ + ψ̂_ik ψ_lk / h L_vv (+ the force's),
/// φ̂, ψ̂ the tables' wphi and wdphi, φ, ψ at the control points; L_qvᵀ from lqvt_, so that one
/// pass reads every matrix contiguously. (Eigen's two block expressions took 5 % more of a
/// 9-joint robot's gauss-2 step, and 6 % more of its Simpson step: docs/performance.md.)
template <lagrangian L, class F>
void stepper<L, F>::add_jacobian_block(int k, int i, int l) {
    const auto kk = static_cast<std::size_t>(k);
    const lagrangian_terms<dim>& t = terms_[kk];
    const double fi = tab_.wphi.hi(i, k), gi = tab_.wdphi.hi(i, k);
    const double fl = tab_.phi(l + 1, k), gl = tab_.dphi(l + 1, k);
    const double a = h_ * fi * fl, b = fi * gl, c = gi * fl, e = gi * gl / h_;
    const Eigen::Index n = jac_.rows(), d = d_;
    double* out = jac_.data() + i * d + l * d * n;
    const double *qq = t.lqq.data(), *qv = t.lqv.data(), *vq = lqvt_.data(), *vv = t.lvv.data();
    for (Eigen::Index col = 0; col < d; ++col, out += n)
        for (Eigen::Index r = 0, x = col * d; r < d; ++r, ++x)
            out[r] += a * qq[x] + b * qv[x] + c * vq[x] + e * vv[x];
    if constexpr (forced) {
        const force_terms<dim>& f = fterms_[kk];
        block_of<dim>(jac_, i, l, d_) += a * f.fq + b * f.fv;
    }
}

/// delta_ = the round-off of each entry of the step's residual (assemble), 2ε times the terms
/// summed into it: for coordinate j of equation i,
///   δ_i0 |p_j| + Σ_k (h |w_k φ_ik| (|L_q(k)_j| + |f_k,j|) + |w_k ψ_ik| |L_v(k)_j|),
/// with φ, ψ as in variational.hpp's equations (the tables' wphi and wdphi)
/// (L_q and f apart, as a force holding a robot cancels L_q).
template <lagrangian L, class F>
void stepper<L, F>::residual_resolution(const vec<dim>& p) {
    const auto &u = tab_.wphi, &g = tab_.wdphi;
    delta_.setZero();
    block_of<dim>(delta_, 0, d_) = p.cwiseAbs();
    for (int k = 0; k < r_; ++k) {
        const lagrangian_terms<dim>& t = terms_[static_cast<std::size_t>(k)];
        acc_ = t.lq.cwiseAbs(); // |L_q(k)| + |f_k|
        if constexpr (forced) {
            const vec<dim>& f = fterms_[static_cast<std::size_t>(k)].f;
            acc_ = (t.lq - f).cwiseAbs() + f.cwiseAbs();
        }
        rhs_ = t.lv.cwiseAbs();
        for (int i = 0; i < s_; ++i)
            block_of<dim>(delta_, i, d_) +=
                (h_ * std::abs(u.hi(i, k))) * acc_ + std::abs(g.hi(i, k)) * rhs_;
    }
    delta_ *= 2.0 * std::numeric_limits<double>::epsilon();
}

/// Whether the residual `res` (the step's equations, or the momentum rows of the constrained
/// stepper's, with their further round-off already in delta_ when `resolved`) is round-off of
/// its own terms, in the units of the increments: max_ij |res_ij| / m_j ≤ max_ij δ_ij / m_j,
/// m_j = |∂²L/∂q̇_j²| at the first point, or the diagonal of the mass matrix the articulated
/// iteration solves with (δ: residual_resolution), so that the correction an
/// update would make to any coordinate is below the round-off of the largest increment, the
/// scale at which Newton's own stop (newton_monitor) measures every update. Then no update could
/// be told from noise. That is where a robot held at rest stops: its increments are round-off of
/// the held forces, and Newton's updates would only trade one rounding for another (the iiwa
/// held upright at q = 0 took 12 updates a step, and its step 9773 failed after 25, without
/// this stop). Entry by entry would be too strict there: a joint the others' noise reaches
/// through M(q) never meets its own round-off. Not where a diagonal of ∂²L/∂q̇² is not positive.
template <lagrangian L, class F>
template <class Diagonal>
bool stepper<L, F>::at_round_off(Eigen::Ref<const Eigen::VectorXd> res, const vec<dim>& p,
                                 bool resolved, const Diagonal& m) {
    if (!res.allFinite()) return false;
    if (!resolved) residual_resolution(p);
    double worst = 0.0, floor = 0.0;
    for (int j = 0; j < d_; ++j) {
        const double mj = std::abs(m(j));
        if (!(mj > 0.0) || !std::isfinite(mj)) return false;
        for (int i = 0; i < s_; ++i) {
            worst = std::max(worst, std::abs(res(i * d_ + j)) / mj);
            floor = std::max(floor, delta_(i * d_ + j) / mj);
        }
    }
    return worst <= floor;
}

/// dp_ = p_{j+1} − p_j as momentum_change gives it, without evaluating L again: from the
/// derivatives of Newton's last iterate X + δ (X the converged increments, δ = delta_ the
/// update taken from it), L_q(k) + f_k there less their change to first order,
///   (L_qq + f_q)(k) Δq_k + (L_qv + f_v)(k) Δv_k,  Δq_k = Σ_l φ_lk δ_l,  Δv_k = Σ_l ψ_lk δ_l / h,
/// and the forces' work from f_k corrected the same way, at X's velocities. The second
/// derivatives are those of the iterate whose Jacobian was built (a chord update keeps them):
/// what is left is about ρ |δ| of the increments, ρ the relative error of those second
/// derivatives; iterate() allows this path only where that is below ε (else momentum_change
/// evaluates again). A coordinate L does not depend on has zero rows in L_q, L_qq and L_qv, so
/// its momentum stays exact. Saves the momentum's r gradient evaluations (2 tree
/// passes of a robot's gauss-2 step).
template <lagrangian L, class F>
bool stepper<L, F>::momentum_change_linearised(const phase_state<dim>& x) {
    dp_.setZero();
    if constexpr (forced) work_ = 0.0;
    for (int k = 0; k < r_; ++k) {
        const auto kk = static_cast<std::size_t>(k);
        acc_.setZero(); // Δq_k
        rhs_.setZero(); // Δv_k
        for (int l = 0; l < s_; ++l) {
            acc_ += tab_.phi(l + 1, k) * block_of<dim>(delta_, l, d_);
            rhs_ += tab_.dphi(l + 1, k) * block_of<dim>(delta_, l, d_);
        }
        rhs_ /= h_;
        const lagrangian_terms<dim>& t = terms_[kk];
        lq0_ = t.lq;
        lq0_.noalias() -= t.lqq * acc_;
        lq0_.noalias() -= t.lqv * rhs_;
        if constexpr (forced) {
            const force_terms<dim>& f = fterms_[kk];
            lv0_ = f.f; // f_k at X
            lv0_.noalias() -= f.fq * acc_;
            lv0_.noalias() -= f.fv * rhs_;
            lq0_ += lv0_ - f.f;
            set_point(x.q, k);
            work_ += tab_.quad.weights[kk] * lv0_.dot(vk_);
        }
        dp_ += tab_.quad.weights[kk] * lq0_;
        dp_ += tab_.weights_lo[kk] * lq0_;
    }
    dp_ *= h_;
    add_time_work(x);
    return dp_.allFinite();
}

/// The predictors' increments X_l = τ_l v + ½ τ_l² a (+ ⅙ τ_l³ j with a jerk j), τ_l = d_l h
/// (zero if not finite: the iteration then starts from rest, and a failing step is diagnosed
/// from there).
template <lagrangian L, class F>
void stepper<L, F>::taylor_increments(const vec<dim>& v, const vec<dim>& a, const vec<dim>* j) {
    for (int l = 0; l < s_; ++l) {
        const double tau = tab_.control[l + 1] * h_;
        x_.col(l) = tau * v + (0.5 * tau * tau) * a;
        if (j) x_.col(l) += (tau * tau * tau / 6.0) * *j;
    }
    if (!x_.allFinite()) x_.setZero();
}

/// The Taylor predictor X_l ≈ τ_l v + ½ τ_l² a, τ_l = d_l h, with v from ∂L/∂q̇(q, v) = p and
/// a from the Euler–Lagrange equations L_vv a = L_q − L_vq v at (q_j, v). v: two Newton
/// iterations from q̇ = 0, or from q̇ = p where ∂²L/∂q̇² is singular at 0 (L = q̇⁴/4); for L
/// with a mass matrix by hand (lagrangian_with_mass_matrix) the first is M(q)⁻¹p.
template <lagrangian L, class F>
void stepper<L, F>::predict(const phase_state<dim>& x) {
    lagrangian_terms<dim>& t = terms_[0];
    v_bar_ = x.p; // from p where ∂²L/∂q̇² is not positive definite at q̇ = 0
    if constexpr (lagrangian_with_mass_matrix<L>) {
        sys_.lagrangian().mass_matrix(x.q, t.lvv);
        solve_positive_definite<dim>(ldlt_, t.lvv, x.p, v_bar_);
    } else {
        vk_.setZero();
        evaluate(sys_.lagrangian(), x.q, vk_, t_, t);
        rhs_ = x.p - t.lv;
        solve_positive_definite<dim>(ldlt_, t.lvv, rhs_, v_bar_);
    }
    evaluate(sys_.lagrangian(), x.q, v_bar_, t_, t);
    if constexpr (forced) add_force(0, x.q, v_bar_, t_, true);
    q_bar_ = x.q; // terms_[0] (and fterms_[0]) now hold the derivatives at (q̄, v̄)
    t_bar_ = t_;
    rhs_ = x.p - t.lv;
    solve_symmetric<dim>(ldlt_, t.lvv, rhs_, dq_);
    const vec<dim>& v = dq_ += v_bar_; // one Newton step on ∂L/∂q̇(q, v) = p
    rhs_ = t.lq;
    rhs_.noalias() -= t.lqv.transpose() * v;
    solve_symmetric_again<dim>(ldlt_, t.lvv, rhs_, acc_); // the same L_vv as v's correction
    taylor_increments(v, acc_);
}

/// Newton's Taylor predictor (predict()) for an L with its mass matrix and bias forces by hand
/// (lagrangian_with_bias_forces: a robot): q̇_j = M(q_j)⁻¹p_j, exact for p = M(q)q̇, and
/// q̈_j = M(q_j)⁻¹(f − b(q_j, q̇_j)), the Euler–Lagrange equations M q̈ + b = f: a
/// composite-rigid-body and a Newton–Euler pass (one kinematics pass for both where L keeps it:
/// bias_forces_after_mass_matrix), where predict() evaluates second derivatives
/// (O(n²)). It leaves no derivatives for a kept Jacobian, so the linear iterations do not use it;
/// Newton's first iterate evaluates its own. Where the step continues the last one (it starts
/// exactly where that one ended; the time is not compared: a clock set by hand, or a force
/// changed between steps, costs the start, not the answer), the increments take a third Taylor term
/// with the jerk (a_j − a_{j−1})/h, a = M⁻¹(f − b): the start's error falls from O(h³) to O(h⁴),
/// and the Panda's gauss-2 steps at 1 ms take 2.13 iterations instead of 2.63 (docs/robots.md).
/// Where the last step took the jerk too, they add its miss, its converged increments less its
/// Taylor increments: a smooth function of time, which changes by O(h) of itself from one step to
/// the next (taylor_from_dynamics). a_{j−1}, the miss and the end state are history. That is
/// without a force, or with one continuous in time (force_continuous_in_time: damping, a PD
/// controller, expressions); a control held over each step jumps between steps, its jump over h is
/// no jerk, and its steps keep the second-order start. The force is evaluated after the bias
/// forces, whose pass keeps M's kinematics. The constrained stepper takes it for a free base
/// (lagrangian_with_bias_after_mass_matrix: its bias forces after M at q_j, no jerk history),
/// the quaternion's constraint force left out as predict() leaves it (constrained.hpp).
template <lagrangian L, class F>
void stepper<L, F>::predict_dynamics(const phase_state<dim>& x) {
    lagrangian_terms<dim>& t = terms_[0];
    const auto& lag = sys_.lagrangian();
    lag.mass_matrix(x.q, t.lvv);
    if (!solve_positive_definite<dim>(mass_, t.lvv, x.p, vk_)) {
        predict(x); // it starts from q̇ = p, and diagnose() names the cause if the step fails
        return;
    }
    dynamics_rhs(x); // M(q_j)'s kinematics kept
    solve_symmetric_again<dim>(mass_, t.lvv, rhs_, acc_);
    taylor_from_dynamics(x);
}

/// Builds and inverts the kept Jacobian from the second derivatives in t (taken at (q̄, v̄)).
template <lagrangian L, class F>
void stepper<L, F>::refresh(const lagrangian_terms<dim>& t) {
    const bool free = opt_.iteration == iteration_kind::fixed_point;
    for (auto& point : terms_) {
        if (&point == &t) continue;
        point.lvv = t.lvv;
        point.lqq = t.lqq;
        point.lqv = t.lqv;
    }
    if (free) {
        for (auto& point : terms_) {
            point.lqq.setZero();
            point.lqv.setZero();
        }
    }
    if constexpr (forced) { // the force's Jacobians at (q̄, v̄), in fterms_[0] (predict)
        for (auto& point : fterms_) {
            if (free) {
                point.fq.setZero();
                point.fv.setZero();
            } else if (&point != &fterms_[0]) {
                point.fq = fterms_[0].fq;
                point.fv = fterms_[0].fv;
            }
        }
    }
    mbar_.compute(t.lvv);
    // assemble() also writes a residual; only its Jacobian is used here.
    rhs_.setZero();
    assemble(rhs_, true);
    lu_.compute(jac_);
    // Column by column through the work vectors: an inverse() would allocate a temporary.
    for (Eigen::Index c = 0; c < res_.size(); ++c) {
        res_.setZero();
        res_(c) = 1.0;
        lu_.solve(res_, delta_);
        jinv_.col(c) = delta_;
    }
    kept_ = true;
}

/// The Taylor predictor of variational.hpp with the kept ∂²L/∂q̇² (of q̄, v̄), M̄, in place of the
/// one at q_j: q̇ from ∂L/∂q̇(q_j, q̇) = p_j by the iteration q̇ += M̄⁻¹(p_j − ∂L/∂q̇) (one
/// evaluation where M̄ is exact, as for a constant mass matrix; up to four where it has moved),
/// and L_vq q̇ by a forward difference of L_v along q̇: first derivatives only. (A start to the
/// iteration: its accuracy changes the sweeps, not the step.)
template <lagrangian L, class F>
void stepper<L, F>::predict_kept(const phase_state<dim>& x) {
    lagrangian_terms<dim>& t = terms_[0];
    const auto& lag = sys_.lagrangian();
    vk_.setZero();
    evaluate_gradient(lag, x.q, vk_, t_, t);
    vk_ = mbar_.solve(x.p - t.lv);
    for (int it = 0; it < 4; ++it) {
        evaluate_gradient(lag, x.q, vk_, t_, t);
        if constexpr (forced) add_force(0, x.q, vk_, t_, false);
        lq0_ = t.lq;
        lv0_ = t.lv;
        dq_ = vk_; // the q̇ of this evaluation
        acc_ = mbar_.solve(x.p - lv0_);
        vk_ += acc_;
        if (!(acc_.template lpNorm<Eigen::Infinity>() >
              1e-8 * vk_.template lpNorm<Eigen::Infinity>()))
            break;
    }
    acc_ = lq0_; // L_vv a = L_q − L_vq q̇ (the Euler–Lagrange equations)
    const double speed = dq_.template lpNorm<Eigen::Infinity>();
    if (speed > 0.0) {
        const double eta = 1.5e-8 * std::max(1.0, x.q.template lpNorm<Eigen::Infinity>()) / speed;
        qk_ = x.q + eta * dq_;
        evaluate_gradient(lag, qk_, dq_, t_, t);
        acc_ -= (t.lv - lv0_) / eta;
    }
    acc_ = mbar_.solve(acc_);
    taylor_increments(vk_, acc_);
}

} // namespace varsym::general
