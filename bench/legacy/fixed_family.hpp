// bench/legacy/fixed_family.hpp: the family as it was compiled before the run-time-degree
// stepper (galerkin.hpp): one fixed-size stepper per (rule, degree) and system. Kept only so that
// `make bench` measures the run-time stepper against it in one process; not part of the library.
#pragma once

#include <array>
#include <cmath>

#include "varsym/schemes/tableau.hpp"
#include "varsym/solvers/compensated.hpp"
#include "varsym/solvers/newton.hpp"
#include "varsym/systems/separable.hpp"

namespace varsym::legacy {

using galerkin::rule_kind;
using galerkin::tableau;

template <class System, rule_kind Kind, int S>
class fixed_stepper {
  public:
    static constexpr int dim = System::dim;
    static constexpr int R = galerkin::points(Kind, S);
    static constexpr int N = blocks(S, dim);
    using system_type = System;

    fixed_stepper(System sys, double h, const tableau& t, const newton_options& opt = {});

    [[nodiscard]] double step_size() const { return h_; }
    [[nodiscard]] const System& system() const { return sys_; }
    /// The compensated summation of the increments, whose carries a checkpoint keeps.
    [[nodiscard]] compensated_update<dim>& summation() { return sum_; }

    /// One step (definition below the class).
    newton_report step(phase_state<dim>& x);

  private:
    using stage_matrix = Eigen::Matrix<double, dim, S>;
    System sys_;
    double h_;
    newton_options opt_;
    Eigen::Matrix<double, S, S> a_;
    Eigen::Matrix<double, S, R> u_, v_;
    std::array<double, R> w_{};
    std::array<double, S> control_{};
    std::array<int, R> active_{};
    int n_active_ = 0;
    std::array<bool, R> at_start_{}, at_end_{};
    stage_matrix xm_;
    Eigen::Matrix<double, dim, R> grads_;
    std::array<mat<dim>, R> hess_;
    vec<dim> grad_j_{}, cached_q_{};
    bool cache_valid_ = false;
    compensated_update<dim> sum_;
};

template <class System, rule_kind Kind, int S>
fixed_stepper<System, Kind, S>::fixed_stepper(System sys, double h, const tableau& t,
                                              const newton_options& opt)
    : sys_(std::move(sys)), h_(h), opt_(opt) {
    if (t.degree != S || t.kind != Kind) throw std::logic_error("galerkin tableau does not match");
    // In matrix form, with X = [X_1 … X_s] (d × s) and G = [∇V(q_1) … ∇V(q_r)] (d × r):
    //   residual R = M X Aᵀ − h² G Uᵀ + h p_j e_0ᵀ,   points Q = q_j 1ᵀ + X V,
    //   Jacobian J = A ⊗ M − h² Σ_k (U_k V_kᵀ) ⊗ ∇²V(q_k),
    // with A_il = A(i, l), U_ik = w_k ℓ_i(c_k) (i < s), V_lk = ℓ_l(c_k) (l ≥ 1).
    a_ = t.stiffness.block(0, 1, S, S);
    for (int k = 0; k < R; ++k) {
        for (int i = 0; i < S; ++i)
            u_(i, k) = t.quad.weights[k] * t.phi(i, k);
        for (int l = 0; l < S; ++l)
            v_(l, k) = t.phi(l + 1, k);
        w_[k] = t.quad.weights[k];
        // Newton evaluates ∇V and ∇²V only where a point enters the solved equations
        // (U_k ≠ 0) and moves with the unknowns (V_k ≠ 0). For Lobatto, c_0 = 0 is q_j
        // itself (its ∇V is cached) and c_s = 1 enters only p_{j+1}.
        if (u_.col(k).cwiseAbs().maxCoeff() > 0.0 && v_.col(k).cwiseAbs().maxCoeff() > 0.0)
            active_[n_active_++] = k;
        at_start_[k] = t.quad.nodes[k] == 0.0;
        at_end_[k] = t.quad.nodes[k] == 1.0;
    }
    for (int l = 0; l < S; ++l)
        control_[l] = t.control[l + 1];
    const int d = sys_.dimension();
    xm_.resize(d, S);
    grads_.resize(d, R);
    grad_j_ = vec<dim>::Zero(d);
    hess_.fill(mat<dim>::Zero(d, d));
}

template <class System, rule_kind Kind, int S>
newton_report fixed_stepper<System, Kind, S>::step(phase_state<dim>& x) {
    const int d = static_cast<int>(x.q.size());
    const auto& m = sys_.mass();
    const auto& minv = sys_.inverse_mass();
    const auto& v = sys_.potential();
    const double h = h_, h2 = h * h;
    if (!cache_valid_ || cached_q_ != x.q) grad_j_ = v.gradient(x.q);
    // Predictor: Taylor to second order, X_l ≈ d_l h M⁻¹p − (d_l h)²/2 M⁻¹∇V(q_j).
    const vec<dim> vel = minv * x.p, acc = -(minv * grad_j_);
    for (int l = 0; l < S; ++l) {
        const double tl = control_[l] * h;
        xm_.col(l) = tl * vel + 0.5 * tl * tl * acc;
    }
    newton_options opt = opt_;
    opt.typical = xm_.template lpNorm<Eigen::Infinity>();
    opt.reference = x.q.template lpNorm<Eigen::Infinity>();
    newton_monitor monitor(opt);
    newton_report rep;
    vec<N> r(S * d), delta(S * d);
    mat<N> jac(S * d, S * d);
    while (true) {
        // Residual R = M X Aᵀ − h² G Uᵀ + h p_j e_0ᵀ and its Jacobian at X.
        for (int k = 0; k < R; ++k)
            grads_.col(k) = at_start_[k] ? grad_j_ : vec<dim>::Zero(d);
        for (int a = 0; a < n_active_; ++a) {
            const int k = active_[a];
            const vec<dim> q = x.q + xm_ * v_.col(k);
            grads_.col(k) = v.gradient(q);
            hess_[k] = v.hessian(q);
        }
        Eigen::Map<typename stage_matrix::PlainObject> rm(r.data(), d, S);
        rm.noalias() = m * xm_ * a_.transpose();
        rm.noalias() -= h2 * grads_ * u_.transpose();
        rm.col(0) += h * x.p;
        if constexpr (dim == 1) {
            // d = 1: J = m A − h² U diag(∇²V(q_k)) Vᵀ as one fixed-size product.
            Eigen::Matrix<double, R, 1> curvature = Eigen::Matrix<double, R, 1>::Zero();
            for (int a = 0; a < n_active_; ++a)
                curvature(active_[a]) = hess_[active_[a]](0, 0);
            jac.noalias() = m(0, 0) * a_;
            jac.noalias() -= h2 * (u_ * curvature.asDiagonal() * v_.transpose());
        } else {
            for (int i = 0; i < S; ++i)
                for (int l = 0; l < S; ++l) {
                    mat<dim> block = a_(i, l) * m;
                    for (int a = 0; a < n_active_; ++a) {
                        const int k = active_[a];
                        const double c = h2 * u_(i, k) * v_(l, k);
                        if (c != 0.0) block -= c * hess_[k];
                    }
                    block_of<dim>(jac, i, l, d) = block;
                }
        }
        rep.residual = r.template lpNorm<Eigen::Infinity>();
        if (monitor.exhausted()) return rep;
        delta = solve_dense<N>(jac, r);
        const double step = delta.template lpNorm<Eigen::Infinity>();
        rep.iterations = monitor.iterations() + 1;
        if (!std::isfinite(step) || !std::isfinite(rep.residual)) return rep;
        xm_ -= Eigen::Map<const typename stage_matrix::PlainObject>(delta.data(), d, S);
        if (monitor.converged(step, xm_.template lpNorm<Eigen::Infinity>())) break;
    }
    rep.converged = true;
    // p_{j+1} − p_j = −h Σ_k w_k ∇V(q_k) at the converged points. A point at c_k = 1 is the
    // new x.q, whose ∇V is kept as the next step's ∇V(q_j); a point at c_k = 0 is q_j.
    const vec<dim> q_j = x.q, grad_j = grad_j_;
    sum_.add_q(x, xm_.col(S - 1));
    vec<dim> dp = vec<dim>::Zero(d);
    cache_valid_ = false;
    for (int k = 0; k < R; ++k) {
        vec<dim> g;
        if (at_end_[k]) {
            g = grad_j_ = v.gradient(x.q);
            cache_valid_ = true;
        } else if (at_start_[k]) {
            g = grad_j;
        } else {
            g = v.gradient(vec<dim>(q_j + xm_ * v_.col(k)));
        }
        dp -= (h * w_[k]) * g;
    }
    sum_.add_p(x, dp);
    cached_q_ = x.q;
    return rep;
}

} // namespace varsym::legacy
