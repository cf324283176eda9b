// varsym/solvers/eigenvalues.hpp: eigenvalues of the symmetric matrices that varsym checks once
// per run (a mass matrix's definiteness, the highest linear frequency). Up to 64 × 64 by cyclic
// Jacobi rotations: Eigen's SelfAdjointEigenSolver, whose instantiation (tridiagonalisation,
// Householder sequences) costs every translation unit that steps a system about 6 s of compile
// time, is compiled only where the dimension is not fixed at most 64 (docs/development.md).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

namespace varsym {

namespace detail {

/// The eigenvalues of the symmetric matrix `a` (its lower triangle is read as the upper), in
/// ascending order: cyclic Jacobi sweeps until the off-diagonal part is below 1e-17 of the
/// Frobenius norm (at most 60 sweeps; all NaN for a matrix that is not finite; they converge
/// quadratically, in 6 to 10 for d ≤ 100).
inline Eigen::VectorXd jacobi_eigenvalues(Eigen::MatrixXd a) {
    const Eigen::Index n = a.rows();
    if (!a.allFinite())
        return Eigen::VectorXd::Constant(n, std::numeric_limits<double>::quiet_NaN());
    a.triangularView<Eigen::StrictlyUpper>() = a.transpose();
    const double norm2 = a.squaredNorm();
    for (int sweep = 0; sweep < 60; ++sweep) {
        double off = 0;
        for (Eigen::Index q = 1; q < n; ++q)
            for (Eigen::Index p = 0; p < q; ++p)
                off += 2 * a(p, q) * a(p, q);
        if (!(off > 1e-34 * norm2)) break;
        for (Eigen::Index q = 1; q < n; ++q)
            for (Eigen::Index p = 0; p < q; ++p) {
                const double apq = a(p, q);
                if (apq == 0) continue;
                // The rotation (c, s) in the (p, q) plane that zeroes a(p, q) (Rutishauser; the
                // smaller of the two angles, t = tan of it).
                const double theta = (a(q, q) - a(p, p)) / (2 * apq);
                const double t =
                    std::copysign(1.0, theta) / (std::abs(theta) + std::sqrt(theta * theta + 1));
                const double c = 1 / std::sqrt(t * t + 1), s = t * c;
                for (Eigen::Index k = 0; k < n; ++k) { // a ← a P
                    const double akp = a(k, p), akq = a(k, q);
                    a(k, p) = c * akp - s * akq;
                    a(k, q) = s * akp + c * akq;
                }
                for (Eigen::Index k = 0; k < n; ++k) { // a ← Pᵀ a
                    const double apk = a(p, k), aqk = a(q, k);
                    a(p, k) = c * apk - s * aqk;
                    a(q, k) = s * apk + c * aqk;
                }
                a(p, q) = a(q, p) = 0;
            }
    }
    Eigen::VectorXd values = a.diagonal();
    std::sort(values.data(), values.data() + n);
    return values;
}

/// The eigenvalues λ of K x = λ M x (K symmetric, M symmetric positive definite), ascending: those
/// of L⁻¹ K L⁻ᵀ for M = L Lᵀ. Nothing where M is not positive definite or not finite.
inline std::optional<Eigen::VectorXd> jacobi_generalized_eigenvalues(const Eigen::MatrixXd& k,
                                                                     const Eigen::MatrixXd& m) {
    const Eigen::Index n = m.rows();
    Eigen::MatrixXd l = Eigen::MatrixXd::Zero(n, n); // Cholesky–Banachiewicz
    for (Eigen::Index j = 0; j < n; ++j) {
        double d = m(j, j);
        for (Eigen::Index c = 0; c < j; ++c)
            d -= l(j, c) * l(j, c);
        if (!(d > 0) || !std::isfinite(d)) return std::nullopt;
        l(j, j) = std::sqrt(d);
        for (Eigen::Index i = j + 1; i < n; ++i) {
            double v = m(i, j);
            for (Eigen::Index c = 0; c < j; ++c)
                v -= l(i, c) * l(j, c);
            l(i, j) = v / l(j, j);
        }
    }
    // Y = L⁻¹ K, then L⁻¹ Yᵀ = L⁻¹ K L⁻ᵀ (K symmetric), each by forward substitution.
    const auto forward = [&](Eigen::MatrixXd b) {
        for (Eigen::Index col = 0; col < n; ++col)
            for (Eigen::Index i = 0; i < n; ++i) {
                double v = b(i, col);
                for (Eigen::Index c = 0; c < i; ++c)
                    v -= l(i, c) * b(c, col);
                b(i, col) = v / l(i, i);
            }
        return b;
    };
    const Eigen::MatrixXd y = forward(k);
    const Eigen::MatrixXd c = forward(y.transpose());
    return jacobi_eigenvalues(0.5 * (c + c.transpose()));
}

} // namespace detail

/// Largest dimension solved by Jacobi rotations (d = 18: 0.14 ms; d = 64: 6 ms; d = 300: 0.74 s,
/// where Eigen takes 0.011 s).
inline constexpr int jacobi_limit = 64;

/// The eigenvalues of the symmetric matrix `a`, ascending, to about 1e-14 of the largest. D:
/// the caller's compile-time dimension; where it is fixed and at most jacobi_limit, Eigen's
/// solver is not compiled in.
template <int D>
Eigen::VectorXd symmetric_eigenvalues(const Eigen::MatrixXd& a) {
    if constexpr (D == Eigen::Dynamic || D > jacobi_limit)
        if (a.rows() > jacobi_limit)
            return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(a, Eigen::EigenvaluesOnly)
                .eigenvalues();
    return detail::jacobi_eigenvalues(a);
}

/// The eigenvalues λ of K x = λ M x (K symmetric, M symmetric positive definite), ascending;
/// nothing where M is not positive definite. D as above.
template <int D>
std::optional<Eigen::VectorXd> generalized_eigenvalues(const Eigen::MatrixXd& k,
                                                       const Eigen::MatrixXd& m) {
    if constexpr (D == Eigen::Dynamic || D > jacobi_limit)
        if (m.rows() > jacobi_limit) {
            const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(
                k, m, Eigen::EigenvaluesOnly);
            if (eig.info() != Eigen::Success) return std::nullopt;
            return eig.eigenvalues();
        }
    return detail::jacobi_generalized_eigenvalues(k, m);
}

} // namespace varsym
