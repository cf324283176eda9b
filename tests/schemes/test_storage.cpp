// tests/schemes/test_storage.cpp: detail::times_transpose_compensated, the family's sums over
// its tables (the closing sweep's K, the residual's A and U). It compensates the sum, not the
// products: each high-part product is rounded once, and the sum of those rounded products plus
// the low parts' products must then be correctly rounded. Reference: that sum in long double
// (64-bit, ~1e-19 relative to the terms, ~1e-3 ulp of the result). The tables are gauss-6's,
// whose rows cancel (entries summing to much less than their magnitudes), applied to gradients
// that vary by 1e-3 across the points, as a step's do. Negative control: the plain sums of the
// high and of the low parts, added (what the stepper did before), miss by more than 2 ulps on
// the same data (measured 2.6; the compensated sum 0.500). At d > 1 the stepper sums several
// entries side by side; a second test checks those bits against the sum one entry at a time.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "varsym/schemes/storage.hpp"
#include "varsym/schemes/tableau.hpp"

using namespace varsym;

namespace {

/// Largest error over `trials` random gradient sets, in ulps of each result.
template <class Sum>
double worst_ulps(const galerkin::tableau::split& table, int trials, Sum&& sum) {
    const Eigen::MatrixXd hi = table.hi.transpose(), lo = table.lo.transpose(); // s × r
    const auto r = hi.cols();
    std::mt19937 gen(7);
    std::uniform_real_distribution<double> base(0.5, 2.0), spread(-1e-3, 1e-3);
    double worst = 0.0;
    for (int t = 0; t < trials; ++t) {
        Eigen::Matrix<double, 1, Eigen::Dynamic> g(1, r), out(1, hi.rows());
        const double b = base(gen);
        for (Eigen::Index k = 0; k < r; ++k)
            g(k) = b * (1.0 + spread(gen));
        sum(out, g, hi, lo);
        for (Eigen::Index l = 0; l < hi.rows(); ++l) {
            long double exact = 0.0L;
            for (Eigen::Index k = 0; k < r; ++k)
                exact += static_cast<long double>(hi(l, k) * g(k)) +
                         static_cast<long double>(lo(l, k)) * g(k);
            const double rounded = std::abs(static_cast<double>(exact));
            const double ulp =
                std::nextafter(rounded, std::numeric_limits<double>::infinity()) - rounded;
            worst = std::max(worst, static_cast<double>(std::abs(out(l) - exact) / ulp));
        }
    }
    return worst;
}

} // namespace

TEST(Storage, CompensatedTableSumIsCorrectlyRounded) {
    const auto tab = galerkin::tableau::make(galerkin::rule_kind::gauss, 6);
    const double compensated =
        worst_ulps(tab.sweep, 2000, [](auto& out, const auto& g, const auto& hi, const auto& lo) {
            galerkin::detail::times_transpose_compensated(out, g, hi, lo);
        });
    EXPECT_LE(compensated, 0.51);
    const double plain =
        worst_ulps(tab.sweep, 2000, [](auto& out, const auto& g, const auto& hi, const auto& lo) {
            Eigen::Matrix<double, 1, Eigen::Dynamic> low(1, out.cols());
            galerkin::detail::times_transpose(out, g, hi);
            galerkin::detail::times_transpose(low, g, lo);
            out += low;
        });
    EXPECT_GE(plain, 2.0);
    RecordProperty("compensated_ulps", std::to_string(compensated));
    RecordProperty("plain_ulps", std::to_string(plain));
}

namespace {

/// out = in (C + C_lo)ᵀ summed one entry at a time, as the correctly rounded sum above is
/// written; the stepper's version sums up to eight entries of a column side by side and must
/// give these bits exactly.
Eigen::MatrixXd one_entry_at_a_time(const Eigen::MatrixXd& in, const Eigen::MatrixXd& c,
                                    const Eigen::MatrixXd& lo) {
    Eigen::MatrixXd out(in.rows(), c.rows());
    for (Eigen::Index i = 0; i < c.rows(); ++i)
        for (Eigen::Index a = 0; a < in.rows(); ++a) {
            double sum = 0.0, carry = 0.0;
            for (Eigen::Index l = 0; l < c.cols(); ++l) {
                const double t = c(i, l) * in(a, l);
                const double next = sum + t, v = next - sum;
                carry += ((sum - (next - v)) + (t - v)) + lo(i, l) * in(a, l);
                sum = next;
            }
            out(a, i) = sum + carry;
        }
    return out;
}

/// Entries of `got` that differ from `want` in any bit.
Eigen::Index differing(const Eigen::MatrixXd& got, const Eigen::MatrixXd& want) {
    return (got.array() != want.array()).count();
}

} // namespace

// At the sizes the family steps (d = 2 and 18 at compile time, and run-time sizes that leave a
// partial block), on gauss-6's closing table and gradients that barely vary, as a step's do.
// Negative control: the plain sums of the high and low parts differ from the reference in some
// entries, so the comparison sees a change of the summation.
TEST(Storage, CompensatedSumOfManyRowsIsTheOneEntryAtATimeSumBitForBit) {
    const auto tab = galerkin::tableau::make(galerkin::rule_kind::gauss, 6);
    const Eigen::MatrixXd hi = tab.sweep.hi.transpose(), lo = tab.sweep.lo.transpose(); // s × r
    const auto s = hi.rows(), r = hi.cols();
    std::mt19937 gen(11);
    std::uniform_real_distribution<double> base(0.5, 2.0), spread(-1e-3, 1e-3);
    const auto gradients = [&](Eigen::Index d) {
        Eigen::MatrixXd g(d, r);
        for (Eigen::Index a = 0; a < d; ++a) {
            const double b = base(gen);
            for (Eigen::Index k = 0; k < r; ++k)
                g(a, k) = b * (1.0 + spread(gen));
        }
        return g;
    };
    Eigen::Index plain_differs = 0;
    for (int trial = 0; trial < 50; ++trial) {
        const Eigen::MatrixXd g2 = gradients(2), g18 = gradients(18);
        Eigen::Matrix<double, 2, Eigen::Dynamic, 0, 2, 8> in2 = g2, out2(2, s);
        Eigen::Matrix<double, 18, Eigen::Dynamic, 0, 18, 8> in18 = g18, out18(18, s);
        galerkin::detail::times_transpose_compensated(out2, in2, hi, lo);
        galerkin::detail::times_transpose_compensated(out18, in18, hi, lo);
        EXPECT_EQ(differing(out2, one_entry_at_a_time(g2, hi, lo)), 0);
        EXPECT_EQ(differing(out18, one_entry_at_a_time(g18, hi, lo)), 0);
        for (const Eigen::Index d : {3, 19, 40}) {
            const Eigen::MatrixXd g = gradients(d);
            Eigen::MatrixXd out(d, s), plain(d, s), low(d, s);
            galerkin::detail::times_transpose_compensated(out, g, hi, lo);
            EXPECT_EQ(differing(out, one_entry_at_a_time(g, hi, lo)), 0) << "d = " << d;
            galerkin::detail::times_transpose(plain, g, hi);
            galerkin::detail::times_transpose(low, g, lo);
            plain_differs += differing(plain + low, one_entry_at_a_time(g, hi, lo));
        }
    }
    EXPECT_GT(plain_differs, 0);
}
