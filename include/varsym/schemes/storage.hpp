// varsym/schemes/storage.hpp: the bounded matrices the family stepper keeps its tables and
// iterates in, sized once by its constructor so that a step allocates nothing.
#pragma once

#include <algorithm>
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

/// The column stride of the stepper's d × k blocks: d, for column-major blocks of d rows and for
/// the row-major 1 × k blocks of d = 1 alike, so column l starts at data() + l d.
template <class M>
constexpr Eigen::Index rows_at_compile_time = std::remove_cvref_t<M>::RowsAtCompileTime;

/// out = in Cᵀ, that is out.col(i) = Σ_l C(i, l) in.col(l), as axpys on raw columns mapped at
/// the block's compile-time height: for the stepper's d × k blocks (k ≤ max_degree + 1) this
/// took a gauss-6 step of the solar system (d = 18) from 184 000 to 119 000 instructions
/// against Eigen's lazy product (callgrind), and a gauss-4 pendulum step (d = 1) from 9 900 to
/// 9 500, where Eigen's expressions on one-entry blocks cost more than the arithmetic.
template <class Out, class In, class C>
void times_transpose(Out&& out, const In& in, const C& c) {
    constexpr int rows = static_cast<int>(rows_at_compile_time<In>);
    using column = Eigen::Matrix<double, rows, 1>;
    const Eigen::Index d = in.rows();
    for (Eigen::Index i = 0; i < c.rows(); ++i) {
        Eigen::Map<column> oi(out.data() + i * d, d);
        oi = c(i, 0) * Eigen::Map<const column>(in.data(), d);
        for (Eigen::Index l = 1; l < c.cols(); ++l)
            oi += c(i, l) * Eigen::Map<const column>(in.data() + l * d, d);
    }
}

/// out = in (C + C_lo)ᵀ for a table held as double C plus the low part C_lo that rounding left
/// out: each entry of out is summed with Neumaier's compensation (two_sum), the low part's
/// products and the carries added once at the end, so that the sum of the products (each
/// rounded once) is correctly rounded (tests/schemes/test_storage.cpp). For the family's tables
/// (the closing sweep's K, the residual's A and U), whose rows have entries of both signs that
/// largely cancel against increments and gradients changing little across a step: a plain sum's
/// rounding then depends smoothly on the state, does not average out over a run, and tilts the
/// energy linearly (docs/performance.md, "Where the drift comes from", has what compensating it
/// bought). Up to eight of a column's entries are summed side by side (each with the same
/// operations in the same order as alone): their chains of dependent additions then overlap and
/// the compiler packs them, where one entry at a time left the solar system's closing sweep
/// (d = 18) waiting on each addition (docs/performance.md).
template <class Out, class In, class C>
void times_transpose_compensated(Out&& out, const In& in, const C& c, const C& c_lo) {
    constexpr int rows = static_cast<int>(rows_at_compile_time<In>);
    constexpr bool one_block = rows > 0 && rows <= 8; // a fixed d ≤ 8: the block is the column
    constexpr Eigen::Index block = one_block ? rows : 8;
    const Eigen::Index d = in.rows();
    const double* x = in.data();
    for (Eigen::Index i = 0; i < c.rows(); ++i) {
        double* o = out.data() + i * d;
        for (Eigen::Index first = 0; first < d; first += block) {
            const Eigen::Index n = one_block ? block : std::min(block, d - first);
            double sum[block] = {}, carry[block] = {};
            for (Eigen::Index l = 0; l < c.cols(); ++l) {
                const double cl = c(i, l), lo = c_lo(i, l);
                const double* xl = x + l * d + first;
                for (Eigen::Index a = 0; a < n; ++a) {
                    const double t = cl * xl[a];
                    const double next = sum[a] + t, v = next - sum[a];
                    carry[a] += ((sum[a] - (next - v)) + (t - v)) + lo * xl[a];
                    sum[a] = next;
                }
            }
            for (Eigen::Index a = 0; a < n; ++a)
                o[first + a] = sum[a] + carry[a];
        }
    }
}

/// out = base + in c (a combination of in's columns), as above.
template <class Out, class Base, class In, class C>
void add_combination(Out&& out, const Base& base, const In& in, const C& c) {
    constexpr int rows = static_cast<int>(rows_at_compile_time<In>);
    using column = Eigen::Matrix<double, rows, 1>;
    const Eigen::Index d = in.rows();
    Eigen::Map<column> o(out.data(), d);
    o = Eigen::Map<const column>(base.data(), d);
    for (Eigen::Index l = 0; l < c.size(); ++l)
        o += c(l) * Eigen::Map<const column>(in.data() + l * d, d);
}

} // namespace varsym::galerkin::detail
