// varsym/schemes/galerkin_sensitivity.hpp: the tangent map of the family stepper for separable
// systems (galerkin.hpp), by the implicit function theorem on its step's equations
//   R_i(X; q_j, p_j) = (1/h) Σ_l A_il M X_l − h Σ_k U_ik ∇V(q_k) + δ_i0 p_j = 0,
//   q_k = q_j + Σ_l V_lk X_l:
//   J = ∂R/∂X = (1/h) A ⊗ M − h Σ_k (U_k V_kᵀ) ⊗ ∇²V(q_k),
//   ∂R_i/∂q_j = −h Σ_k U_ik ∇²V(q_k),   ∂R_i/∂p_j = δ_i0 I,
//   dX = −J⁻¹ (∂R/∂q_j dq_j + ∂R/∂p_j dp_j),   dq_{j+1} = dq_j + dX_s,
//   dp_{j+1} = dp_j − h Σ_k w_k ∇²V(q_k) (dq_j + Σ_l V_lk dX_l).
#pragma once

#include "varsym/schemes/galerkin.hpp"

namespace varsym::galerkin {

template <separable System>
void stepper<System>::step_jacobian(const phase_state<dim>& from, Eigen::MatrixXd& out) const {
    const int s = s_, d = sys_.dimension(), n = n_;
    const auto& v = sys_.potential();
    Eigen::MatrixXd m = Eigen::MatrixXd::Identity(d, d);
    if constexpr (scalar_mass<System>)
        m *= sys_.mass();
    else
        m = sys_.mass();
    Eigen::MatrixXd jac(n, n), b = Eigen::MatrixXd::Zero(n, 2 * d);
    for (int i = 0; i < s; ++i)
        for (int l = 0; l < s; ++l)
            jac.block(i * d, l * d, d, d) = (hinv_ * a_(i, l)) * m;
    std::vector<Eigen::MatrixXd> hess(static_cast<std::size_t>(r_));
    vec<dim> qk(d);
    for (int k = 0; k < r_; ++k) {
        qk = from.q;
        for (int l = 0; l < s; ++l)
            qk += v_(l, k) * xm_.col(l);
        hess[static_cast<std::size_t>(k)].resize(d, d);
        varsym::detail::assign_elementwise(hess[static_cast<std::size_t>(k)], v.hessian(qk));
        const Eigen::MatrixXd& hk = hess[static_cast<std::size_t>(k)];
        for (int i = 0; i < s; ++i) {
            b.block(i * d, 0, d, d) -= (h_ * u_(i, k)) * hk;
            for (int l = 0; l < s; ++l)
                jac.block(i * d, l * d, d, d) -= (h_ * u_(i, k) * v_(l, k)) * hk;
        }
    }
    b.block(0, d, d, d).diagonal().array() += 1.0;
    const Eigen::MatrixXd dx = -Eigen::PartialPivLU<Eigen::MatrixXd>(jac).solve(b);
    out = Eigen::MatrixXd::Identity(2 * d, 2 * d);
    out.topRows(d) += dx.bottomRows(d);
    Eigen::MatrixXd dq(d, 2 * d);
    for (int k = 0; k < r_; ++k) {
        dq.setZero();
        dq.leftCols(d).setIdentity();
        for (int l = 0; l < s; ++l)
            dq += v_(l, k) * dx.middleRows(l * d, d);
        out.bottomRows(d) -= (h_ * weight_[k]) * hess[static_cast<std::size_t>(k)] * dq;
    }
}

} // namespace varsym::galerkin
