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
