// tests/solvers/test_tridiagonal.cpp: the O(n) symmetric tridiagonal solve against Eigen's
// dense LU on the same matrix.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "varsym/solvers/tridiagonal.hpp"

TEST(Tridiagonal, MatchesDenseSolve) {
    const int n = 40;
    Eigen::VectorXd d(n), o(n - 1), b(n);
    Eigen::MatrixXd t = Eigen::MatrixXd::Zero(n, n);
    for (int i = 0; i < n; ++i) {
        d(i) = 2.5 + 0.1 * i;
        b(i) = std::sin(0.3 * i);
        t(i, i) = d(i);
        if (i + 1 < n) {
            o(i) = -1.0 - 0.01 * i;
            t(i, i + 1) = t(i + 1, i) = o(i);
        }
    }
    const Eigen::VectorXd expected = t.partialPivLu().solve(b);
    ASSERT_TRUE(varsym::solve_symmetric_tridiagonal(d, o, b));
    // Well-conditioned SPD matrix (condition number ~10): both solves are accurate to ~1e-15.
    EXPECT_LT((b - expected).lpNorm<Eigen::Infinity>(), 1e-13);
}

TEST(Tridiagonal, ReportsZeroPivot) {
    Eigen::VectorXd d(2), o(1), b(2);
    d << 1.0, 1.0;
    o << 1.0; // [[1, 1], [1, 1]] is singular
    b << 1.0, 2.0;
    EXPECT_FALSE(varsym::solve_symmetric_tridiagonal(d, o, b));
}
