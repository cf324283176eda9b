// tests/quadrature/test_rules.cpp: Gauss–Legendre and Gauss–Lobatto rules against published
// tables (Abramowitz & Stegun 25.4.29 and 25.4.32, mapped from [−1, 1] to [0, 1]) and against
// their exactness degree.
#include <gtest/gtest.h>

#include <cmath>

#include "varsym/quadrature/rules.hpp"

using namespace varsym::quadrature;

namespace {

// Checks a rule against symmetric nodes ±x_i and weights w_i given on [−1, 1] (x_i ≥ 0).
void expect_table(const rule& r, std::vector<std::pair<double, double>> half, bool has_zero) {
    std::vector<double> x, w;
    for (auto it = half.rbegin(); it != half.rend(); ++it) {
        x.push_back(-it->first);
        w.push_back(it->second);
    }
    const std::size_t start = has_zero ? 1 : 0;
    for (std::size_t i = start; i < half.size(); ++i) {
        x.push_back(half[i].first);
        w.push_back(half[i].second);
    }
    ASSERT_EQ(r.size(), x.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
        EXPECT_NEAR(r.nodes[i], 0.5 * (x[i] + 1.0), 2e-16) << "node " << i;
        EXPECT_NEAR(r.weights[i], 0.5 * w[i], 2e-16) << "weight " << i;
    }
}

double monomial_error(const rule& r, int k) {
    double sum = 0;
    for (std::size_t i = 0; i < r.size(); ++i)
        sum += r.weights[i] * std::pow(r.nodes[i], k);
    return std::abs(sum - 1.0 / (k + 1)); // ∫₀¹ x^k dx = 1/(k+1)
}

} // namespace

TEST(Quadrature, GaussLegendreTables) {
    expect_table(gauss_legendre(1), {{0.0, 2.0}}, true);
    expect_table(gauss_legendre(2), {{1 / std::sqrt(3.0), 1.0}}, false);
    expect_table(gauss_legendre(3), {{0.0, 8.0 / 9}, {std::sqrt(0.6), 5.0 / 9}}, true);
    expect_table(
        gauss_legendre(4),
        {{0.33998104358485626, 0.65214515486254614}, {0.86113631159405258, 0.34785484513745386}},
        false);
    expect_table(gauss_legendre(5),
                 {{0.0, 128.0 / 225},
                  {0.53846931010568309, 0.47862867049936647},
                  {0.90617984593866399, 0.23692688505618909}},
                 true);
}

TEST(Quadrature, GaussLobattoTables) {
    expect_table(gauss_lobatto(2), {{1.0, 1.0}}, false);
    expect_table(gauss_lobatto(3), {{0.0, 4.0 / 3}, {1.0, 1.0 / 3}}, true);
    expect_table(gauss_lobatto(4), {{1 / std::sqrt(5.0), 5.0 / 6}, {1.0, 1.0 / 6}}, false);
    expect_table(gauss_lobatto(5), {{0.0, 32.0 / 45}, {std::sqrt(3.0 / 7), 49.0 / 90}, {1.0, 0.1}},
                 true);
    expect_table(gauss_lobatto(6),
                 {{0.28523151648064510, 0.55485837703548635},
                  {0.76505532392946469, 0.37847495629784698},
                  {1.0, 1.0 / 15}},
                 false);
}

TEST(Quadrature, ExactUpToTheirDegreeAndNotBeyond) {
    // n-point Gauss: exact through degree 2n − 1; n-point Lobatto: through 2n − 3. One degree
    // more is not exact: checked for n ≤ 8, where that error (which decays like (n!)⁴/(2n)!³)
    // is still far above round-off.
    for (int n = 1; n <= 13; ++n) {
        const auto g = gauss_legendre(n);
        for (int k = 0; k <= 2 * n - 1; ++k)
            EXPECT_LT(monomial_error(g, k), 1e-15) << "gauss " << n << " x^" << k;
        if (n <= 8) {
            EXPECT_GT(monomial_error(g, 2 * n), 1e-12) << "gauss " << n;
        }
    }
    for (int n = 2; n <= 13; ++n) {
        const auto l = gauss_lobatto(n);
        for (int k = 0; k <= 2 * n - 3; ++k)
            EXPECT_LT(monomial_error(l, k), 1e-15) << "lobatto " << n << " x^" << k;
        if (n <= 8) {
            EXPECT_GT(monomial_error(l, 2 * n - 2), 1e-12) << "lobatto " << n;
        }
    }
}

TEST(Quadrature, RefusesTooFewPoints) {
    EXPECT_THROW(gauss_legendre(0), std::invalid_argument);
    EXPECT_THROW(gauss_lobatto(1), std::invalid_argument);
}
