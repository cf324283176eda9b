// tests/autodiff/test_blocked_hessian.cpp: the Hessian computed a few columns per pass (the
// large-d path of automatic differentiation) equals the one-pass nested computation, and the
// choice of columns per pass keeps the scalars below Eigen's fixed-size limit.
#include <gtest/gtest.h>

#include <cmath>

#include "varsym/systems/lagrangian.hpp"

using namespace varsym;

namespace {
/// A non-separable Lagrangian in d = 3 with q–q̇ coupling (a charged particle in a rotating,
/// anharmonic well): every block of the Hessian is non-zero.
struct coupled {
    static constexpr int dim = 3;
    template <class T>
    T operator()(const tvec<T, 3>& q, const tvec<T, 3>& v) const {
        using std::cos, std::exp;
        const T kinetic =
            0.5 * (v(0) * v(0) + 2.0 * v(1) * v(1) + v(2) * v(2)) + 0.3 * cos(q(2)) * v(0) * v(1);
        const T magnetic = 0.7 * (q(0) * v(1) - q(1) * v(0)) + 0.2 * q(2) * q(2) * v(2);
        const T potential = exp(0.1 * q(0)) + q(1) * q(1) * q(2) + 0.25 * q(0) * q(0) * q(0) * q(0);
        return kinetic + magnetic - potential;
    }
};

template <int B>
double largest_difference(const vec<3>& q, const vec<3>& v) {
    lagrangian_terms<3> once, blocks;
    varsym::detail::differentiate_at_once(coupled{}, q, v, once);
    varsym::detail::differentiate_in_blocks<B>(coupled{}, q, v, blocks);
    double d = std::abs(once.value - blocks.value);
    for (const auto& [a, b] : {std::pair{once.lq, blocks.lq}, std::pair{once.lv, blocks.lv}})
        d = std::max(d, (a - b).template lpNorm<Eigen::Infinity>());
    for (const auto& [a, b] : {std::pair{once.lqq, blocks.lqq}, std::pair{once.lqv, blocks.lqv},
                               std::pair{once.lvv, blocks.lvv}})
        d = std::max(d, (a - b).template lpNorm<Eigen::Infinity>());
    return d;
}
} // namespace

TEST(BlockedHessian, EqualsTheOnePassHessian) {
    const vec<3> q{0.4, -1.3, 0.8}, v{1.1, 0.2, -0.6};
    // The same arithmetic on the same numbers in another grouping: equal to a few ulps of the
    // entries (all of order 1 here).
    EXPECT_LE(largest_difference<1>(q, v), 1e-14);
    EXPECT_LE(largest_difference<2>(q, v), 1e-14);
    EXPECT_LE(largest_difference<4>(q, v), 1e-14); // 6 columns in passes of 4 and 2
    EXPECT_LE(largest_difference<6>(q, v), 1e-14);
}

TEST(BlockedHessian, NegativeControlAWrongPointDiffers) {
    // The comparison can fail: derivatives at another velocity are far off.
    lagrangian_terms<3> a, b;
    varsym::detail::differentiate_at_once(coupled{}, vec<3>{0.4, -1.3, 0.8}, vec<3>{1.1, 0.2, -0.6},
                                          a);
    varsym::detail::differentiate_in_blocks<2>(coupled{}, vec<3>{0.4, -1.3, 0.8},
                                               vec<3>{1.1, 0.2, 0.6}, b);
    EXPECT_GT((a.lq - b.lq).lpNorm<Eigen::Infinity>(), 1e-3);
}

TEST(BlockedHessian, ColumnsPerPassFitEigensLimit) {
    static_assert(ad::hessian_columns_per_pass<2>() == 4); // small d: one pass
    static_assert(ad::hessian_columns_per_pass<12>() == 24);
    static_assert(ad::hessian_columns_per_pass<18>() == 11); // 18·12·37·8 B = 63.9 KiB
    static_assert(ad::hessian_columns_per_pass<60>() == 1);  // 60·2·121·8 B = 113 KiB
    static_assert(ad::hessian_columns_per_pass<70>() == 0);  // too large: by hand
    for (int d : {18, 60})
        EXPECT_LE(d * 2 * (2 * d + 1) * 8, 128 * 1024) << "d = " << d;
}
