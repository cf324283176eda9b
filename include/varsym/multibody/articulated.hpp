// varsym/multibody/articulated.hpp: solves with the joint-space mass matrix, x = M(q)⁻¹τ, in O(n)
// by the articulated-body algorithm with no velocity, gravity or bias (Featherstone, Rigid Body
// Dynamics Algorithms, 2008, §7.3, in world coordinates as the rest of algorithms.hpp): a
// factorisation at q (the articulated inertias, one pass leaves first), then each solve two passes.
// With S_i joint i's world motion subspace, I_i body i's world spatial inertia and λ(i) its parent:
//   factor, leaves first:  I^A_i = I_i + Σ_{c: λ(c) = i} (I^A_c − U_c U_cᵀ / D_c),
//                          U_i = I^A_i S_i,  D_i = S_iᵀ U_i;
//   solve, leaves first:   u_i = τ_i − S_iᵀ p_i,  p_λ(i) += p_i + U_i u_i / D_i  (p starts at 0);
//   then root first:       x_i = (u_i − U_iᵀ a_λ(i)) / D_i,  a_i = a_λ(i) + S_i x_i  (a_root = 0).
// This is forward dynamics (ABA) at q̇ = 0 and zero gravity, where M q̈ = τ; in world coordinates
// no transform is applied between bodies. The general engine's articulated iteration
// (schemes/variational_articulated.hpp) solves with M so, at the step's start (its predictor)
// and midpoint (its updates): O(n) where Cholesky of the dense M is O(n³). Mimic joints couple
// coordinates that the recursion does not see: a tree with them is factorised densely (the
// composite-rigid-body M and Cholesky, O(n³)) by robot_lagrangian.
#pragma once

#include <cmath>
#include <vector>

#include "varsym/multibody/algorithms.hpp"

namespace varsym::multibody {

/// M(q) factorised by the articulated-body algorithm: per body its subspace S_i, U_i, 1/D_i; M's
/// diagonal M_ii = S_iᵀ I^c_i S_i (I^c the composite inertia); and the solves' scratch. One per
/// thread (robot_lagrangian keeps it beside the workspace); no allocation once sized (the solves'
/// scratch by the first solve of as many columns).
struct articulated_factor {
    std::vector<vec6> s, u, p, a;
    std::vector<mat6> inertia, composite; // I^A_i and I^c_i (the factorisation's scratch)
    std::vector<double> inverse_d, rhs;
    Eigen::VectorXd diagonal;

    void resize(int n) {
        const auto k = static_cast<std::size_t>(n);
        s.resize(k);
        u.resize(k);
        inertia.resize(k);
        composite.resize(k);
        inverse_d.resize(k);
        diagonal.resize(n);
    }
};

/// Factorises M(q) of a tree without mimic joints into f (running kinematics in w). False where
/// a D_i is not positive and finite (M not positive definite: a massless end of the tree).
template <class Q>
bool factor_mass(const tree& m, workspace& w, const Eigen::MatrixBase<Q>& q,
                 articulated_factor& f) {
    const int n = m.body_count();
    kinematics(m, w, q);
    f.resize(n);
    for (std::size_t k = 0; k < static_cast<std::size_t>(n); ++k) {
        f.inertia[k] = w.inertia[k];
        f.composite[k] = w.inertia[k];
        f.s[k] = w.s[k];
    }
    for (int i = n - 1; i >= 0; --i) {
        const auto k = static_cast<std::size_t>(i);
        f.u[k].noalias() = f.inertia[k] * f.s[k];
        const double d = f.s[k].dot(f.u[k]);
        if (!(d > 0.0) || !std::isfinite(d)) return false;
        f.inverse_d[k] = 1.0 / d;
        f.diagonal(i) = f.s[k].dot(f.composite[k] * f.s[k]);
        const int parent = m.bodies[k].parent;
        if (parent < 0) continue;
        const auto pk = static_cast<std::size_t>(parent);
        f.inertia[pk] += f.inertia[k];
        f.inertia[pk].noalias() -= f.inverse_d[k] * (f.u[k] * f.u[k].transpose());
        f.composite[pk] += f.composite[k];
    }
    return true;
}

/// x ← M(q)⁻¹x with f from factor_mass at q, for each column of x (O(n) a column; the columns'
/// passes interleaved, body by body, so that their chains of dependent operations overlap; each
/// column's operations are those of a solve of it alone). f's scratch, no workspace.
template <class X>
void solve_mass(const tree& m, articulated_factor& f, Eigen::MatrixBase<X>& x) {
    const int n = m.body_count();
    const auto c = static_cast<std::size_t>(x.cols());
    const std::size_t size = static_cast<std::size_t>(n) * c;
    if (f.p.size() < size) {
        f.p.resize(size);
        f.a.resize(size);
        f.rhs.resize(size);
    }
    for (std::size_t k = 0; k < size; ++k)
        f.p[k].setZero();
    for (int i = n - 1; i >= 0; --i) {
        const auto k = static_cast<std::size_t>(i);
        const int parent = m.bodies[k].parent;
        for (std::size_t j = 0; j < c; ++j) {
            const std::size_t kj = k * c + j;
            f.rhs[kj] = x(i, static_cast<Eigen::Index>(j)) - f.s[k].dot(f.p[kj]);
            if (parent >= 0)
                f.p[static_cast<std::size_t>(parent) * c + j] +=
                    f.p[kj] + (f.rhs[kj] * f.inverse_d[k]) * f.u[k];
        }
    }
    for (int i = 0; i < n; ++i) {
        const auto k = static_cast<std::size_t>(i);
        const int parent = m.bodies[k].parent;
        for (std::size_t j = 0; j < c; ++j) {
            const std::size_t kj = k * c + j;
            const auto col = static_cast<Eigen::Index>(j);
            if (parent < 0) {
                x(i, col) = f.rhs[kj] * f.inverse_d[k];
                f.a[kj] = f.s[k] * x(i, col);
            } else {
                const vec6& above = f.a[static_cast<std::size_t>(parent) * c + j];
                x(i, col) = (f.rhs[kj] - f.u[k].dot(above)) * f.inverse_d[k];
                f.a[kj] = above + f.s[k] * x(i, col);
            }
        }
    }
}

} // namespace varsym::multibody
