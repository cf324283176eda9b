// varsym/types.hpp: vector, matrix and phase-space state types shared by the whole library.
#pragma once

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

/// Solves A x = b for a small symmetric A (a mass matrix): a division when N == 1, LDLᵀ else.
template <int N>
vec<N> solve_symmetric(const mat<N>& a, const vec<N>& b) {
    if constexpr (N == 1) {
        return vec<N>{b(0) / a(0, 0)};
    } else {
        return a.ldlt().solve(b);
    }
}

} // namespace varsym

namespace varsym::detail {

/// x = A⁻¹ b for a small dense A (n × n, column-major with leading dimension lda) by Eigen's LU
/// with partial pivoting at the compile-time size N = n, whose unrolled kernels are 1.5–2.5×
/// faster than the run-time-sized LU for n ≤ 8 (bench/bench_family.cpp). Depends on n only, not
/// on a system, so it is compiled once per program whatever the systems stepped.
template <int N>
void solve_fixed_size(const double* a, Eigen::Index lda, const double* b, double* x) {
    const Eigen::Map<const Eigen::Matrix<double, N, N>, 0, Eigen::OuterStride<>> am(
        a, N, N, Eigen::OuterStride<>(lda));
    const Eigen::Map<const Eigen::Matrix<double, N, 1>> bm(b);
    Eigen::Map<Eigen::Matrix<double, N, 1>> xm(x);
    xm = Eigen::Matrix<double, N, N>(am).partialPivLu().solve(bm);
}

/// The largest n that solve_small handles at a fixed size.
inline constexpr int small_solve_limit = 8;

/// Solves A x = b at a fixed size when n ≤ small_solve_limit; returns false (x untouched) for
/// larger n, which the caller solves with a run-time-sized LU.
inline bool solve_small(Eigen::Index n, const double* a, Eigen::Index lda, const double* b,
                        double* x) {
    switch (n) {
    case 1:
        x[0] = b[0] / a[0];
        return true;
    case 2:
        solve_fixed_size<2>(a, lda, b, x);
        return true;
    case 3:
        solve_fixed_size<3>(a, lda, b, x);
        return true;
    case 4:
        solve_fixed_size<4>(a, lda, b, x);
        return true;
    case 5:
        solve_fixed_size<5>(a, lda, b, x);
        return true;
    case 6:
        solve_fixed_size<6>(a, lda, b, x);
        return true;
    case 7:
        solve_fixed_size<7>(a, lda, b, x);
        return true;
    case 8:
        solve_fixed_size<8>(a, lda, b, x);
        return true;
    default:
        return false;
    }
}

} // namespace varsym::detail
