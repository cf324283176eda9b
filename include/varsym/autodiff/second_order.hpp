// varsym/autodiff/second_order.hpp: value, gradient and Hessian of a scalar function in one pass
// of forward-mode automatic differentiation, with Eigen's AutoDiffScalar nested in itself
// (unsupported/Eigen/AutoDiff, shipped with libeigen3-dev).
//
// Chosen over a dual-number type of our own after measuring both on the same Lagrangians
// (docs/autodiff.md): ours was no faster (283 vs 282 ns on the double pendulum, 767 vs 625 ns on
// the heavy top), so the well-kept library wins. Fixed derivative sizes: nothing is allocated.
#pragma once

#include <Eigen/Core> // before unsupported/Eigen/AutoDiff, which needs it
#include <unsupported/Eigen/AutoDiff>

namespace varsym::ad {

/// First derivatives with respect to N variables.
template <int N>
using first_order = Eigen::AutoDiffScalar<Eigen::Matrix<double, N, 1>>;

/// Second derivatives: the derivatives of a first_order scalar are first_order scalars.
template <int N>
using second_order = Eigen::AutoDiffScalar<Eigen::Matrix<first_order<N>, N, 1>>;

/// The i-th of N independent variables with value x: gradient e_i, Hessian 0.
template <int N>
second_order<N> variable(double x, int i) {
    second_order<N> r;
    r.value() = first_order<N>(x, N, i);
    r.derivatives() = Eigen::Matrix<first_order<N>, N, 1>::Unit(N, i);
    for (int j = 0; j < N; ++j)
        r.derivatives()(j).derivatives().setZero();
    return r;
}

/// Splits r into its value, gradient g (N) and Hessian h (N × N).
template <int N>
double unpack(const second_order<N>& r, Eigen::Matrix<double, N, 1>& g,
              Eigen::Matrix<double, N, N>& h) {
    for (int i = 0; i < N; ++i) {
        g(i) = r.derivatives()(i).value();
        h.row(i) = r.derivatives()(i).derivatives().transpose();
    }
    return r.value().value();
}

} // namespace varsym::ad

namespace varsym::ad {

/// Second derivatives B Hessian columns at a time: the value and gradient in N variables (the
/// inner first_order<N>) and their derivatives along B seeded directions. N/B passes give the
/// whole Hessian with scalars of (B+1)(N+1) doubles instead of second_order<N>'s (N+1)², which
/// keeps a vector of them below Eigen's fixed-size limit (128 KiB) when N is large.
template <int N, int B>
using directional = Eigen::AutoDiffScalar<Eigen::Matrix<first_order<N>, B, 1>>;

/// The i-th of N variables with value x, its outer derivatives seeded along the directions
/// first … first + B − 1 (e_i's component there: 1 if i is one of them).
template <int N, int B>
directional<N, B> seeded_variable(double x, int i, int first) {
    directional<N, B> r;
    r.value() = first_order<N>(x, N, i);
    for (int j = 0; j < B; ++j)
        r.derivatives()(j) = first_order<N>(first + j == i ? 1.0 : 0.0);
    return r;
}

/// Hessian columns per pass for a function of two D-vectors (N = 2D variables): all N (one
/// pass of second_order<N>) while a D-vector of those scalars takes at most 64 KiB, else the
/// largest B that fits that budget, else 1 while a D-vector fits 120 KiB; 0 beyond (too large
/// for automatic derivatives: give them by hand).
template <int D>
constexpr int hessian_columns_per_pass() {
    constexpr long n = 2L * D;
    auto bytes = [](long b) { return long{D} * (b + 1) * (n + 1) * long{sizeof(double)}; };
    if (bytes(n) <= 64 * 1024) return static_cast<int>(n);
    for (long b = n - 1; b >= 1; --b)
        if (bytes(b) <= 64 * 1024) return static_cast<int>(b);
    return bytes(1) <= 120 * 1024 ? 1 : 0;
}

} // namespace varsym::ad
