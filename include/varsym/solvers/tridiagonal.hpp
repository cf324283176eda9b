// varsym/solvers/tridiagonal.hpp: symmetric tridiagonal linear systems in O(n), for Newton on
// systems whose Hessian couples only neighbours (chains).
//
// Written here rather than taken from a library: Eigen has no banded solver (its sparse LDLᵀ
// needs the matrix assembled and analysed, several times the work of this loop), and LAPACK's
// dpttrf/dpttrs would add a Fortran library for the same twelve lines.
#pragma once

#include <cmath>

#include <Eigen/Core>

namespace varsym {

/// Solves T x = b in place (b becomes x) for the symmetric tridiagonal T with diagonal `diag`
/// (n entries, overwritten by the pivots of T = L D Lᵀ) and off-diagonal `off` (n − 1 entries).
/// No pivoting: meant for symmetric positive definite T (M + c ∇²V with a convex V), where it is
/// backward stable. Returns false if a pivot is zero or not finite.
inline bool solve_symmetric_tridiagonal(Eigen::Ref<Eigen::VectorXd> diag,
                                        Eigen::Ref<const Eigen::VectorXd> off,
                                        Eigen::Ref<Eigen::VectorXd> b) {
    const Eigen::Index n = diag.size();
    for (Eigen::Index i = 1; i < n; ++i) {
        const double l = off(i - 1) / diag(i - 1); // L(i, i−1)
        diag(i) -= l * off(i - 1);
        b(i) -= l * b(i - 1);
    }
    for (Eigen::Index i = n - 1; i >= 0; --i) {
        if (!(std::isfinite(diag(i)) && diag(i) != 0.0)) return false;
        const double upper = i + 1 < n ? off(i) * b(i + 1) : 0.0;
        b(i) = (b(i) - upper) / diag(i);
    }
    return true;
}

} // namespace varsym
