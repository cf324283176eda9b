// Tests for varsym/solvers/eigenvalues.hpp: Jacobi's eigenvalues against Eigen's solvers (an
// independent implementation: Householder tridiagonalisation and implicit QL) on random
// symmetric matrices and pencils, and a pencil that is not definite.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "varsym/solvers/eigenvalues.hpp"
#include "varsym/types.hpp"

namespace {

Eigen::MatrixXd random_symmetric(Eigen::Index n, double diagonal_scale) {
    Eigen::MatrixXd a = Eigen::MatrixXd::Random(n, n);
    a = (a + a.transpose()).eval();
    a.diagonal() *= diagonal_scale;
    return a;
}

// Backward-stable solvers agree to a few ulps of the largest eigenvalue times the dimension.
double tolerance(Eigen::Index n) {
    return 1e-15 * static_cast<double>(n) + 1e-15;
}

TEST(Eigenvalues, JacobiMatchesEigenOnSymmetricMatrices) {
    std::srand(7);
    for (Eigen::Index n : {1, 2, 3, 6, 18, 40, 64}) {
        for (double scale : {1.0, 1e6}) {
            const Eigen::MatrixXd a = random_symmetric(n, scale);
            const Eigen::VectorXd ours = varsym::symmetric_eigenvalues<varsym::dynamic>(a);
            const Eigen::VectorXd ref =
                Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(a, Eigen::EigenvaluesOnly)
                    .eigenvalues();
            EXPECT_LE((ours - ref).cwiseAbs().maxCoeff(), tolerance(n) * ref.cwiseAbs().maxCoeff())
                << "n = " << n;
        }
    }
}

TEST(Eigenvalues, GeneralizedMatchesEigenOnDefinitePencils) {
    std::srand(11);
    for (Eigen::Index n : {1, 2, 4, 18, 64}) {
        const Eigen::MatrixXd k = random_symmetric(n, 1.0);
        const Eigen::MatrixXd b = Eigen::MatrixXd::Random(n, n);
        const Eigen::MatrixXd m = b * b.transpose() + Eigen::MatrixXd::Identity(n, n);
        const auto ours = varsym::generalized_eigenvalues<varsym::dynamic>(k, m);
        ASSERT_TRUE(ours.has_value());
        const Eigen::VectorXd ref =
            Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd>(k, m, Eigen::EigenvaluesOnly)
                .eigenvalues();
        EXPECT_LE((*ours - ref).cwiseAbs().maxCoeff(),
                  100 * tolerance(n) * ref.cwiseAbs().maxCoeff())
            << "n = " << n;
    }
}

TEST(Eigenvalues, RefusesAnIndefiniteMassAndFlagsNaN) {
    const Eigen::MatrixXd k = Eigen::MatrixXd::Identity(3, 3);
    Eigen::MatrixXd m = Eigen::MatrixXd::Identity(3, 3);
    m(2, 2) = -1e-3;
    EXPECT_FALSE(varsym::generalized_eigenvalues<3>(k, m).has_value());
    m(2, 2) = 0;
    EXPECT_FALSE(varsym::generalized_eigenvalues<3>(k, m).has_value());
    Eigen::MatrixXd a = Eigen::MatrixXd::Identity(2, 2);
    a(1, 0) = std::numeric_limits<double>::quiet_NaN();
    EXPECT_TRUE(std::isnan(varsym::symmetric_eigenvalues<2>(a)(0)));
}

TEST(Eigenvalues, KnownSpectrum) { // [[2, 1], [1, 2]]: 1 and 3; diag(4, 9) over diag(1, 1): 4, 9
    Eigen::MatrixXd a(2, 2);
    a << 2, 1, 1, 2;
    const Eigen::VectorXd l = varsym::symmetric_eigenvalues<2>(a);
    EXPECT_NEAR(l(0), 1.0, 4e-16);
    EXPECT_NEAR(l(1), 3.0, 8e-16);
    const Eigen::MatrixXd k = Eigen::Vector2d(9, 4).asDiagonal();
    const auto g = varsym::generalized_eigenvalues<2>(k, Eigen::MatrixXd::Identity(2, 2));
    ASSERT_TRUE(g.has_value());
    EXPECT_EQ((*g)(0), 4.0);
    EXPECT_EQ((*g)(1), 9.0);
}

} // namespace
