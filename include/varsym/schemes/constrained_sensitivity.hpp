// varsym/schemes/constrained_sensitivity.hpp: the Jacobian of the constrained step map
// (constrained.hpp), ∂(q_{j+1}, p_{j+1})/∂(q_j, p_j), by the implicit function theorem, first on
// the saddle-point system in (X, Λ), then on the hidden constraint's projection in (q̇, μ):
//   K dZ = −B dx_j,  B = ∂(F − GᵀΛ, g)/∂(q_j, p_j)   (H_i = Σ_a Λ_ia ∇²g_a(Q_i), ∂Q_i/∂q_j = I);
//   dp̃ = dp_j + h Σ_k w_k (...) − Σ_{i<s} (H_i dQ_i + G_iᵀ dΛ_i);
//   [L_vv  Gᵀ] [dq̇]   [dp̃ − (L_vq + H_μ) dq_{j+1}]
//   [G     0 ] [dμ ] = [−(∂(G q̇)/∂q) dq_{j+1}     ],   dp_{j+1} = dp̃ − H_μ dq_{j+1} − Gᵀ dμ.
// On the constraint manifold's cotangent bundle the map is symplectic (tested).
#pragma once

#include "varsym/schemes/constrained.hpp"

namespace varsym::general {

template <lagrangian L, holonomic_constraint C, class F>
void constrained_stepper<L, C, F>::step_jacobian(const phase_state<dim>& from,
                                                 Eigen::MatrixXd& out) {
    const int s = this->s_, d = this->d_, sd = s * d, n = s * (d + m_), m = m_;
    const auto& X = this->x_;
    const double work = this->work_, now = this->t_;
    this->t_ = this->t_step_; // the forces at the step's own times
    this->evaluate_points(from.q, true);
    this->assemble(from.p, true);
    this->work_ = work;
    this->t_ = now;
    evaluate_constraint(c_, from.q, g_[0], jc_[0]);
    assemble_constrained(from, true); // K at the converged (X, Λ); G(Q_1 … Q_s)
    second_current_ = true;
    Eigen::MatrixXd b = Eigen::MatrixXd::Zero(n, 2 * d);
    this->add_state_derivative(b);
    b.block(0, d, d, d).diagonal().array() += 1.0;
    std::vector<mat<dim>> hi(static_cast<std::size_t>(s)); // H_i(Λ_i), i < s
    for (int i = 0; i < s; ++i) {
        this->qk_ = from.q;
        if (i > 0) this->qk_ += X.col(i - 1);
        hi[static_cast<std::size_t>(i)].setZero(d, d);
        constraint_curvature(c_, this->qk_, vec<count>(lam_.col(i)),
                             hi[static_cast<std::size_t>(i)]);
        b.block(i * d, 0, d, d) -= hi[static_cast<std::size_t>(i)];
    }
    for (int l = 1; l <= s; ++l)
        b.block(sd + (l - 1) * m, 0, m, d) = jc_[static_cast<std::size_t>(l)];
    factorise();
    const Eigen::MatrixXd dz = -klu_.solve(b);
    const Eigen::MatrixXd dx = dz.topRows(sd);
    // dq_{j+1} and dp̃
    Eigen::MatrixXd j = Eigen::MatrixXd::Zero(2 * d, 2 * d);
    j.topLeftCorner(d, d).setIdentity();
    j.topRows(d) += dx.bottomRows(d);
    j.bottomRightCorner(d, d).setIdentity();
    this->add_momentum_derivative(dx, j, true);
    Eigen::MatrixXd dqi = Eigen::MatrixXd::Zero(d, 2 * d);
    for (int i = 0; i < s; ++i) {
        dqi.setZero();
        dqi.leftCols(d).setIdentity();
        if (i > 0) dqi += dx.middleRows((i - 1) * d, d);
        j.bottomRows(d) -=
            hi[static_cast<std::size_t>(i)] * dqi +
            jc_[static_cast<std::size_t>(i)].transpose() * dz.middleRows(sd + i * m, m);
    }
    // The projection at q_{j+1}, with q̇_{j+1} from p_{j+1} = p_j + dp_ (the step's total change).
    const vec<dim> q1 = from.q + X.col(s - 1), p1 = from.p + this->dp_;
    const vec<dim> v1 = this->sys_.velocity(q1, p1, this->t_); // t_ = t_{j+1} after the step
    lagrangian_terms<dim> t;
    evaluate(this->sys_.lagrangian(), q1, v1, this->t_, t);
    const jacobian_type& g1 = jc_[static_cast<std::size_t>(s)];
    mat<dim> hmu(d, d), hv(d, d);
    constraint_curvature(c_, q1, mu_, hmu);
    Eigen::MatrixXd gvq(m, d); // ∂(G q̇)/∂q at fixed q̇: row a = (∇²g_a q̇)ᵀ
    for (int a = 0; a < m; ++a) {
        constraint_curvature(c_, q1, vec<count>(vec<count>::Unit(m_, a)), hv);
        gvq.row(a) = (hv * v1).transpose();
    }
    const Eigen::MatrixXd dq1 = j.topRows(d);
    Eigen::MatrixXd kkt = Eigen::MatrixXd::Zero(d + m, d + m);
    kkt.topLeftCorner(d, d) = t.lvv;
    kkt.topRightCorner(d, m) = g1.transpose();
    kkt.bottomLeftCorner(m, d) = g1;
    Eigen::MatrixXd rhs(d + m, 2 * d);
    rhs.topRows(d) = j.bottomRows(d) - (t.lqv.transpose() + hmu) * dq1;
    rhs.bottomRows(m) = -gvq * dq1;
    const Eigen::MatrixXd sol = kkt.fullPivLu().solve(rhs);
    out = j;
    out.bottomRows(d) -= hmu * dq1 + g1.transpose() * sol.bottomRows(m);
}

/// ∂q_{j+1}/∂p_j: K dZ = −B dp_j with B's momentum columns, I in the first block row alone (the
/// constraint rows and H_i act on dq_j only); dq_{j+1} = dX_s. The projection changes p_{j+1}
/// only.
template <lagrangian L, holonomic_constraint C, class F>
void constrained_stepper<L, C, F>::position_sensitivity(const phase_state<dim>& from,
                                                        Eigen::MatrixXd& out) {
    const double work = this->work_, now = this->t_;
    this->t_ = this->t_step_;
    this->evaluate_points(from.q, true);
    this->assemble(from.p, true);
    this->work_ = work;
    this->t_ = now;
    evaluate_constraint(c_, from.q, g_[0], jc_[0]);
    assemble_constrained(from, true);
    second_current_ = true;
    factorise();
    kept_position_sensitivity(out); // the solve with this K
}

template <lagrangian L, holonomic_constraint C, class F>
void constrained_stepper<L, C, F>::kept_position_sensitivity(Eigen::MatrixXd& out) {
    const int s = this->s_, d = this->d_;
    if (!factorised_) factorise(); // a step that stopped at round-off on a fresh K
    klu_.negated_inverse_rows(d, (s - 1) * d, d, out); // −K⁻¹ (I; 0)'s rows of X_s
}

template <lagrangian L, holonomic_constraint C, class F>
void constrained_stepper<L, C, F>::start_next_near(const vec<dim>& dp) {
    const int s = this->s_, d = this->d_, sd = s * d;
    if (!factorised_) factorise(); // a step that stopped at its first iterate's round-off
    rk_.setZero();
    rk_.head(d) = dp;
    klu_.solve(rk_, dk_); // K⁻¹ (dp, 0): the step's dZ is its negative
    near_x_ = this->x_;
    near_lam_ = lam_;
    for (int l = 0; l < s; ++l)
        near_x_.col(l) -= dk_.segment(l * d, d);
    for (int i = 0; i < s; ++i)
        near_lam_.col(i) -= dk_.segment(sd + i * m_, m_);
    near_move_ = dk_.head(sd).template lpNorm<Eigen::Infinity>();
    near_ = dk_.allFinite();
}

template <lagrangian L, holonomic_constraint C, class F>
void constrained_stepper<L, C, F>::save_kept(std::vector<double>& out) const {
    out.insert(out.end(), k_.data(), k_.data() + k_.size());
    out.insert(out.end(), lam_.data(), lam_.data() + lam_.size());
    const auto n = static_cast<std::size_t>(this->x_.size());
    if (reuse_miss_valid_)
        out.insert(out.end(), reuse_miss_.data(), reuse_miss_.data() + n);
    else
        out.insert(out.end(), n, 0.0);
    out.push_back(reuse_miss_valid_ ? 1.0 : 0.0);
}

/// The LU is computed again from K: the same factors as the saved run's, which were K's.
template <lagrangian L, holonomic_constraint C, class F>
void constrained_stepper<L, C, F>::restore_kept(const double* in) {
    std::copy(in, in + k_.size(), k_.data());
    in += k_.size();
    std::copy(in, in + lam_.size(), lam_.data());
    in += lam_.size();
    reuse_miss_.resize(this->x_.rows(), this->x_.cols());
    std::copy(in, in + reuse_miss_.size(), reuse_miss_.data());
    reuse_miss_valid_ = in[reuse_miss_.size()] != 0.0;
    factorised_ = false;
    assembled_ = true;
}

} // namespace varsym::general
