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
