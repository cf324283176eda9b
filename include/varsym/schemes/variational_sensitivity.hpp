// varsym/schemes/variational_sensitivity.hpp: the Jacobian of the general engine's step map,
// ∂(q_{j+1}, p_{j+1})/∂(q_j, p_j), by the implicit function theorem on the step's equations
// (variational.hpp), forces included: what trajectory optimization, LQR and tangent maps need.
//
// With R(X; q_j, p_j) = 0 the step's equations in the increments X (Jacobian J = ∂R/∂X, the one
// Newton uses), q_k = q_j + Σ_l φ_lk X_l and v_k = (1/h) Σ_l ψ_lk X_l:
//   ∂R_i/∂q_j = Σ_k (h w_k φ_ik (L_qq + f_q)(k) + w_k ψ_ik L_vq(k)),   ∂R_0/∂p_j = I,
//   dX = −J⁻¹ (∂R/∂q_j dq_j + ∂R/∂p_j dp_j),   dq_{j+1} = dq_j + dX_s,
//   dp_{j+1} = dp_j + h Σ_k w_k ((L_qq + f_q)(k) dq_k + (L_qv + f_v)(k) dv_k).
#pragma once

#include "varsym/schemes/variational.hpp"

namespace varsym::general {

template <lagrangian L, class F>
void stepper<L, F>::step_jacobian(const phase_state<dim>& from, Eigen::MatrixXd& out,
                                  Eigen::MatrixXd* controls) {
    const int d = d_, s = s_, sd = s * d;
    const double work = work_, now = t_;
    t_ = t_step_;                  // the forces at the step's own times
    evaluate_points(from.q, true); // second derivatives at the converged increments
    assemble(from.p, true);
    work_ = work; // evaluate_points recomputed it unscaled
    Eigen::MatrixXd b = Eigen::MatrixXd::Zero(sd, 2 * d);
    add_state_derivative(b);
    b.block(0, d, d, d).diagonal().array() += 1.0; // ∂R_0/∂p_j
    lu_.compute(jac_);
    const Eigen::MatrixXd dx = -lu_.solve(b);
    out.setZero(2 * d, 2 * d);
    out.topLeftCorner(d, d).setIdentity();
    out.topRows(d) += dx.bottomRows(d); // X_s
    out.bottomRightCorner(d, d).setIdentity();
    add_momentum_derivative(dx, out, true);
    if constexpr (force_with_input<F>) {
        if (controls) control_jacobian(from, *controls);
    }
    t_ = now;
}

/// ∂q_{j+1}/∂p_j = dX_s/dp_j = −(J⁻¹)_{s,0}: ∂R/∂p_j is I in the first block row alone.
template <lagrangian L, class F>
void stepper<L, F>::position_sensitivity(const phase_state<dim>& from, Eigen::MatrixXd& out) {
    const int d = d_, sd = s_ * d;
    const double work = work_, now = t_;
    t_ = t_step_;
    evaluate_points(from.q, true);
    assemble(from.p, true);
    work_ = work;
    t_ = now;
    lu_.compute(jac_);
    lu_.negated_inverse_rows(d, sd - d, d, out); // ∂R_0/∂p_j = (I; 0), X_s's rows
}

/// ∂(q_{j+1}, p_{j+1})/∂u_j: ∂R_i/∂u = h Σ_k w_k φ_ik B_k (B_k = ∂f/∂u at point k), dX = −J⁻¹
/// ∂R/∂u, dq_{j+1} = dX_s, dp_{j+1} = h Σ_k w_k (B_k + (L_qq + f_q) dq_k + (L_qv + f_v) dv_k),
/// with the terms of the step's converged point (left by step_jacobian, lu_ factorised).
template <lagrangian L, class F>
void stepper<L, F>::control_jacobian(const phase_state<dim>& from, Eigen::MatrixXd& out) {
    constexpr int m = F::controls;
    const int d = d_, s = s_;
    Eigen::MatrixXd b = Eigen::MatrixXd::Zero(s * d, m), direct = Eigen::MatrixXd::Zero(d, m);
    Eigen::Matrix<double, dim, m> bk(d, m);
    for (int k = 0; k < r_; ++k) {
        const auto ks = static_cast<std::size_t>(k);
        qk_ = from.q;
        vk_.setZero();
        for (int l = 0; l < s; ++l) {
            qk_ += tab_.phi(l + 1, k) * x_.col(l);
            vk_ += (tab_.dphi(l + 1, k) / h_) * x_.col(l);
        }
        force_.input_jacobian(qk_, vk_, t_step_ + tab_.quad.nodes[ks] * h_, bk);
        for (int i = 0; i < s; ++i)
            b.middleRows(i * d, d) += (h_ * tab_.wphi.hi(i, k)) * bk;
        direct += (h_ * tab_.quad.weights[ks]) * bk;
    }
    const Eigen::MatrixXd dx = -lu_.solve(b);
    out.setZero(2 * d, m);
    out.topRows(d) = dx.bottomRows(d);
    out.bottomRows(d) = direct;
    add_momentum_derivative(dx, out, false);
}

/// Adds ∂R_i/∂q_j (the first d columns of b, rows i d … i d + d − 1) at the current terms.
template <lagrangian L, class F>
void stepper<L, F>::add_state_derivative(Eigen::MatrixXd& b) const {
    const int d = d_;
    for (int k = 0; k < r_; ++k) {
        const lagrangian_terms<dim>& t = terms_[static_cast<std::size_t>(k)];
        for (int i = 0; i < s_; ++i) {
            auto block = b.block(i * d, 0, d, d);
            block += (h_ * tab_.wphi.hi(i, k)) * t.lqq + tab_.wdphi.hi(i, k) * t.lqv.transpose();
            if constexpr (forced)
                block += (h_ * tab_.wphi.hi(i, k)) * fterms_[static_cast<std::size_t>(k)].fq;
        }
    }
}

/// Adds h Σ_k w_k ((L_qq + f_q) dq_k + (L_qv + f_v) dv_k) to the last d rows of out, with
/// dq_k = Σ_l φ_lk dX_l (+ [I 0] for dq_j when `state`) and dv_k = (1/h) Σ_l ψ_lk dX_l.
template <lagrangian L, class F>
void stepper<L, F>::add_momentum_derivative(const Eigen::MatrixXd& dx, Eigen::MatrixXd& out,
                                            bool state) const {
    const int d = d_;
    const auto n = dx.cols();
    Eigen::MatrixXd dq(d, n), dv(d, n);
    for (int k = 0; k < r_; ++k) {
        const auto ks = static_cast<std::size_t>(k);
        dq.setZero();
        if (state) dq.leftCols(d).setIdentity();
        dv.setZero();
        for (int l = 0; l < s_; ++l) {
            dq += tab_.phi(l + 1, k) * dx.middleRows(l * d, d);
            dv += (tab_.dphi(l + 1, k) / h_) * dx.middleRows(l * d, d);
        }
        Eigen::MatrixXd mq = terms_[ks].lqq, mv = terms_[ks].lqv;
        if constexpr (forced) {
            mq += fterms_[ks].fq;
            mv += fterms_[ks].fv;
        }
        out.bottomRows(d) += (h_ * tab_.quad.weights[ks]) * (mq * dq + mv * dv);
    }
}

} // namespace varsym::general
