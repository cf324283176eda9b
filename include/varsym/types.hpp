// varsym/types.hpp: vector, matrix and phase-space state types shared by the whole library.
#pragma once

#include <cmath>
#include <utility>

#include <Eigen/Dense>

namespace varsym {

/// Dimension of the configuration space: a positive compile-time size, or Eigen::Dynamic.
inline constexpr int dynamic = Eigen::Dynamic;

/// Size of a block of `k` copies of a `d`-vector, staying Dynamic when d is.
constexpr int blocks(int k, int d) {
    return d == dynamic ? dynamic : k * d;
}

template <int D>
using vec = Eigen::Matrix<double, D, 1>;

template <int D>
using mat = Eigen::Matrix<double, D, D>;

/// A point (q, p) of phase space: configuration q and conjugate momentum p = ∂L/∂q̇.
template <int D>
struct phase_state {
    vec<D> q;
    vec<D> p;
};

/// The k-th block of D entries of a stacked vector (compile-time sized when D is fixed).
template <int D, class V>
auto block_of(V& v, int k, int d) {
    if constexpr (D == dynamic)
        return v.segment(k * d, d);
    else
        return v.template segment<D>(k * D);
}

/// The (i, j) block of D×D entries of a block matrix (compile-time sized when D is fixed).
template <int D, class M>
auto block_of(M& m, int i, int j, int d) {
    if constexpr (D == dynamic)
        return m.block(i * d, j * d, d, d);
    else
        return m.template block<D, D>(i * D, j * D);
}

/// Solves A x = b for a small dense A: a division when D == 1, LU with partial pivoting else.
template <int N>
vec<N> solve_dense(const mat<N>& a, const vec<N>& b) {
    if constexpr (N == 1) {
        return vec<N>{b(0) / a(0, 0)};
    } else {
        return a.partialPivLu().solve(b);
    }
}

/// Solves A x = b where the symmetric A is positive definite, by one LDLᵀ into `f` (a division
/// when N == 1), and returns true; returns false, x unchanged, where A is not (a pivot ≤ 0). The
/// caller keeps `f`, so that at a run-time N its storage is allocated once.
template <int N>
bool solve_positive_definite(Eigen::LDLT<mat<N>>& f, const mat<N>& a, const vec<N>& b, vec<N>& x) {
    if constexpr (N == 1) {
        if (!(a(0, 0) > 0.0)) return false;
        x = vec<N>{b(0) / a(0, 0)};
    } else {
        f.compute(a);
        if (f.info() != Eigen::Success || !(f.vectorD().array() > 0.0).all()) return false;
        x = f.solve(b);
    }
    return true;
}

/// Solves A x = b again, for another b, with the factorisation of A that solve_symmetric left
/// in `f` (a division when N == 1): A must be the same matrix, unchanged since.
template <int N>
void solve_symmetric_again(const Eigen::LDLT<mat<N>>& f, const mat<N>& a, const vec<N>& b,
                           vec<N>& x) {
    if constexpr (N == 1)
        x = vec<N>{b(0) / a(0, 0)};
    else
        x = f.solve(b);
}

/// Solves A x = b for a small symmetric A (a mass matrix): a division when N == 1, LDLᵀ into the
/// caller's `f` else.
template <int N>
void solve_symmetric(Eigen::LDLT<mat<N>>& f, const mat<N>& a, const vec<N>& b, vec<N>& x) {
    if constexpr (N != 1) f.compute(a);
    solve_symmetric_again<N>(f, a, b, x);
}

} // namespace varsym

namespace varsym::detail {

/// x = A⁻¹ b by an Eigen decomposition `f` of A, where x may be b itself (Eigen's solve into
/// its own right-hand side is not guaranteed: a copy then).
template <class Decomposition>
void solve_into(const Decomposition& f, const Eigen::VectorXd& b, Eigen::VectorXd& x) {
    if (&x == &b) {
        const Eigen::VectorXd y = f.solve(b);
        x = y;
    } else {
        x.noalias() = f.solve(b);
    }
}

/// The largest n that solve_small handles.
inline constexpr int small_solve_limit = 8;

/// Solves A x = b for n ≤ small_solve_limit (A column-major with leading dimension lda) by
/// Gaussian elimination with partial pivoting, the algorithm of Eigen's PartialPivLU, written
/// out for small n; returns false (x untouched) for larger n, which the caller solves with
/// Eigen's run-time-sized LU. Why not Eigen here: its run-time-sized LU costs 1.5–2.5× more at
/// n ≤ 8, and its fixed-size LU at the seven sizes costs every source that steps the family
/// 15 s of compilation at -O3 (docs/performance.md). This loop matches the fixed-size LU's
/// speed and compiles in no time.
inline bool solve_small(Eigen::Index n, const double* a, Eigen::Index lda, const double* b,
                        double* x) {
    if (n > small_solve_limit) return false;
    double m[small_solve_limit][small_solve_limit]; // m[col][row]
    double y[small_solve_limit];
    for (Eigen::Index j = 0; j < n; ++j) {
        for (Eigen::Index i = 0; i < n; ++i)
            m[j][i] = a[j * lda + i];
        y[j] = b[j];
    }
    for (Eigen::Index k = 0; k < n; ++k) {
        Eigen::Index p = k; // pivot: the largest entry of column k at or below the diagonal
        for (Eigen::Index i = k + 1; i < n; ++i)
            if (std::abs(m[k][i]) > std::abs(m[k][p])) p = i;
        if (p != k) {
            for (Eigen::Index j = k; j < n; ++j)
                std::swap(m[j][k], m[j][p]);
            std::swap(y[k], y[p]);
        }
        const double inv = 1.0 / m[k][k]; // a zero pivot gives inf/NaN, which Newton reports
        for (Eigen::Index i = k + 1; i < n; ++i) {
            const double l = m[k][i] * inv;
            for (Eigen::Index j = k + 1; j < n; ++j)
                m[j][i] -= l * m[j][k];
            y[i] -= l * y[k];
        }
    }
    for (Eigen::Index i = n - 1; i >= 0; --i) {
        double s = y[i];
        for (Eigen::Index j = i + 1; j < n; ++j)
            s -= m[j][i] * x[j];
        x[i] = s / m[i][i];
    }
    return true;
}

/// dst = src element by element: a fixed 1 × 1 (or 1-element) source copied into a dynamic
/// block through Eigen's packet path trips GCC 12's -Warray-bounds (a false positive).
template <class Dst, class Src>
void assign_elementwise(Dst&& dst, const Src& src) {
    for (Eigen::Index c = 0; c < src.cols(); ++c)
        for (Eigen::Index r = 0; r < src.rows(); ++r)
            dst(r, c) = src(r, c);
}

} // namespace varsym::detail
