// varsym/schemes/storage.hpp: the bounded matrices the family stepper keeps its tables and
// iterates in, sized once by its constructor so that a step allocates nothing.
#pragma once

#include <type_traits>

#include "varsym/types.hpp"

namespace varsym::galerkin::detail {

/// A run-time-sized matrix bounded by MaxR × MaxC: stored inside the object (Eigen's fixed
/// maximum sizes) when both bounds are known and the block is small, else on the heap, sized
/// once by the stepper's constructor. Either way a step allocates nothing.
template <int MaxR, int MaxC>
constexpr bool inline_storage = MaxR != dynamic&& MaxC != dynamic&& MaxR* MaxC <= 1024;
template <int MaxR, int MaxC>
using bounded_matrix = std::conditional_t<
    inline_storage<MaxR, MaxC>,
    Eigen::Matrix<double, dynamic, dynamic,
                  (MaxR == 1 && MaxC != 1) ? Eigen::RowMajor : Eigen::ColMajor, MaxR, MaxC>,
    Eigen::MatrixXd>;
template <int MaxN>
using bounded_vector =
    std::conditional_t<inline_storage<MaxN, 1>, Eigen::Matrix<double, dynamic, 1, 0, MaxN, 1>,
                       Eigen::VectorXd>;
/// d × k blocks of k ≤ MaxK columns (stage increments, gradients at the quadrature points).
template <int D, int MaxK>
using columns = Eigen::Matrix<double, D, dynamic, D == 1 ? Eigen::RowMajor : Eigen::ColMajor, D,
                              D == dynamic ? dynamic : MaxK>;

/// out = in Cᵀ, that is out.col(i) = Σ_l C(i, l) in.col(l), column by column: for the stepper's
/// d × k blocks (k ≤ max_degree + 1) these contiguous axpys cost about half of Eigen's lazy
/// product, which strides across the columns for each coefficient (callgrind, d = 18).
template <class Out, class In, class C>
void times_transpose(Out&& out, const In& in, const C& c) {
    for (Eigen::Index i = 0; i < c.rows(); ++i) {
        out.col(i) = c(i, 0) * in.col(0);
        for (Eigen::Index l = 1; l < c.cols(); ++l)
            out.col(i) += c(i, l) * in.col(l);
    }
}

/// out = base + in c (a combination of in's columns).
template <class Out, class Base, class In, class C>
void add_combination(Out&& out, const Base& base, const In& in, const C& c) {
    out = base;
    for (Eigen::Index l = 0; l < c.size(); ++l)
        out += c(l) * in.col(l);
}

} // namespace varsym::galerkin::detail
