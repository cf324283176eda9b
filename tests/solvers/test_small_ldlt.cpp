// tests/solvers/test_small_ldlt.cpp: the LDLᵀ factorisation of a robot's mass matrix in the
// general engine's predictor (solvers/small_ldlt.hpp). References: Eigen's LDLT of the same
// matrix (its solution, to the matrix's conditioning), and the backward error of each solve
// against the matrix itself, which LDLᵀ of a positive definite matrix keeps to a small multiple
// of n ε ‖A‖ ‖x‖ without pivoting (Higham, Accuracy and Stability of Numerical Algorithms,
// 2nd ed., §10.1, for Cholesky, whose factor is L D^½).
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "solvers/backward_error.hpp"
#include "varsym/solvers/small_ldlt.hpp"

namespace {

/// A random positive definite n × n matrix B Bᵀ + I/n with entries of both signs off the
/// diagonal (κ up to about n², as a robot's M(q) with light distal links).
Eigen::MatrixXd random_positive_definite(Eigen::Index n, std::mt19937& g) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Eigen::MatrixXd b(n, n);
    for (Eigen::Index j = 0; j < n; ++j)
        for (Eigen::Index i = 0; i < n; ++i)
            b(i, j) = u(g);
    return b * b.transpose() +
           Eigen::MatrixXd::Identity(n, n) / static_cast<double>(std::max<Eigen::Index>(n, 1));
}

} // namespace

// Sizes of robots' mass matrices, below the limit and above it (Eigen's LDLT there): the solves
// have a stable factorisation's backward error and agree with Eigen's to the conditioning.
TEST(SmallLdlt, SolvesAsEigensLdltAtEverySize) {
    std::mt19937 g(11);
    constexpr double eps = std::numeric_limits<double>::epsilon();
    constexpr Eigen::Index limit = varsym::small_ldlt::unblocked_limit;
    varsym::small_ldlt f;
    for (Eigen::Index n : {Eigen::Index{1}, Eigen::Index{2}, Eigen::Index{6}, Eigen::Index{7},
                           Eigen::Index{9}, Eigen::Index{18}, limit, limit + 1, Eigen::Index{60}}) {
        const Eigen::MatrixXd a = random_positive_definite(n, g);
        const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0);
        const Eigen::LDLT<Eigen::MatrixXd> reference(a);
        const Eigen::VectorXd expected = reference.solve(b);
        ASSERT_TRUE(f.compute(a)) << "n = " << n;
        EXPECT_EQ(f.rows(), n);
        Eigen::VectorXd x(n);
        f.solve(b, x);
        EXPECT_LT(varsym::test::backward_error(a, x, b), 10.0 * static_cast<double>(n) * eps)
            << "n = " << n;
        const double kappa = a.norm() * reference.solve(Eigen::MatrixXd::Identity(n, n)).norm();
        EXPECT_LT((x - expected).lpNorm<Eigen::Infinity>(),
                  20.0 * static_cast<double>(n) * eps * kappa * expected.lpNorm<Eigen::Infinity>())
            << "n = " << n;
        // A second right-hand side with the same factors, and a solve in place.
        const Eigen::VectorXd c = Eigen::VectorXd::Ones(n);
        Eigen::VectorXd z(n);
        f.solve(c, z);
        EXPECT_LT(varsym::test::backward_error(a, z, c), 10.0 * static_cast<double>(n) * eps);
        Eigen::VectorXd y = b;
        f.solve(y, y);
        EXPECT_EQ(y, x) << "n = " << n;
    }
}

// Only the lower triangle is read, below the limit and above it: the predictor's M(q) is
// symmetric, and the upper triangle may hold anything (here garbage, which must change
// nothing).
TEST(SmallLdlt, ReadsTheLowerTriangleOnly) {
    std::mt19937 g(5);
    for (Eigen::Index n : {Eigen::Index{9}, varsym::small_ldlt::unblocked_limit + 4}) {
        const Eigen::MatrixXd a = random_positive_definite(n, g);
        Eigen::MatrixXd lower = a;
        lower.triangularView<Eigen::StrictlyUpper>().setConstant(1e30);
        const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, 1.0, 3.0);
        varsym::small_ldlt f, h;
        ASSERT_TRUE(f.compute(a));
        ASSERT_TRUE(h.compute(lower));
        Eigen::VectorXd x(n), y(n);
        f.solve(b, x);
        h.solve(b, y);
        EXPECT_EQ(x, y) << "n = " << n;
    }
}

// A matrix that is not positive definite is reported (the predictor then falls back), below and
// above the limit: a negative diagonal entry, a zero row and column, a NaN. The negative
// control: the positive definite matrix each was made from passes.
TEST(SmallLdlt, ReportsAMatrixThatIsNotPositiveDefinite) {
    constexpr Eigen::Index limit = varsym::small_ldlt::unblocked_limit;
    varsym::small_ldlt f;
    for (Eigen::Index n : {Eigen::Index{3}, Eigen::Index{9}, limit + 4}) {
        std::mt19937 g(static_cast<unsigned>(n));
        const Eigen::MatrixXd a = random_positive_definite(n, g);
        const double shift = 1.0 + a.diagonal().maxCoeff();
        Eigen::MatrixXd indefinite = a;
        indefinite(n - 1, n - 1) -= 2.0 * shift * static_cast<double>(n); // a negative direction
        EXPECT_FALSE(f.compute(indefinite)) << "n = " << n;
        Eigen::MatrixXd semidefinite = a;
        semidefinite.row(n - 1).setZero(); // singular: a zero pivot
        semidefinite.col(n - 1).setZero();
        EXPECT_FALSE(f.compute(semidefinite)) << "n = " << n;
        Eigen::MatrixXd nan = a;
        nan(1, 1) = std::numeric_limits<double>::quiet_NaN();
        EXPECT_FALSE(f.compute(nan)) << "n = " << n;
        EXPECT_TRUE(f.compute(a)) << "n = " << n;
    }
}
