// tests/solvers/test_small_lu.cpp: the unblocked LU of the steppers' Newton matrices
// (solvers/small_lu.hpp). References: Eigen's PartialPivLU of the same matrix (the same
// algorithm: its solution, to the matrix's conditioning), and the backward error of each solve
// against the matrix itself, which LU with partial pivoting keeps to a small multiple of
// n ε ‖A‖ ‖x‖ (Higham, Accuracy and Stability of Numerical Algorithms, 2nd ed., Theorem 9.4).
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "solvers/backward_error.hpp"
#include "varsym/solvers/small_lu.hpp"

namespace {

/// A random n × n matrix whose diagonal does not dominate (so that rows are exchanged).
Eigen::MatrixXd random_matrix(Eigen::Index n, std::mt19937& g) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Eigen::MatrixXd a(n, n);
    for (Eigen::Index j = 0; j < n; ++j)
        for (Eigen::Index i = 0; i < n; ++i)
            a(i, j) = u(g);
    return a;
}

} // namespace

// Every size the steppers meet below the limit and some above: the solves have the backward
// error of a stable LU and agree with Eigen's to the matrix's conditioning.
TEST(SmallLu, SolvesAsEigensPartialPivLuAtEverySize) {
    std::mt19937 g(7);
    constexpr double eps = std::numeric_limits<double>::epsilon();
    varsym::small_lu lu;
    constexpr Eigen::Index limit = varsym::small_lu::unblocked_limit;
    for (Eigen::Index n : {Eigen::Index{1}, Eigen::Index{2}, Eigen::Index{3}, Eigen::Index{6},
                           Eigen::Index{12}, Eigen::Index{17}, Eigen::Index{18}, Eigen::Index{27},
                           limit, limit + 1, Eigen::Index{60}}) {
        const Eigen::MatrixXd a = random_matrix(n, g);
        const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0);
        const Eigen::PartialPivLU<Eigen::MatrixXd> reference(a);
        const Eigen::VectorXd expected = reference.solve(b);
        lu.compute(a);
        Eigen::VectorXd x(n);
        lu.solve(b, x);
        // Growth factors of random matrices stay small; 10 n ε is Higham's bound with room.
        EXPECT_LT(varsym::test::backward_error(a, x, b), 10.0 * static_cast<double>(n) * eps)
            << "n = " << n;
        // Both solutions are within κ(A) times their backward errors of the exact one.
        const double kappa = a.norm() * reference.inverse().norm();
        EXPECT_LT((x - expected).lpNorm<Eigen::Infinity>(),
                  20.0 * static_cast<double>(n) * eps * kappa * expected.lpNorm<Eigen::Infinity>())
            << "n = " << n;
        // A matrix right-hand side: column by column, the same as the vector solve (above the
        // limit Eigen's blocked solve, which may round otherwise).
        Eigen::MatrixXd rhs(n, 3);
        rhs << b, 2.0 * b, Eigen::VectorXd::Ones(n);
        const Eigen::MatrixXd xs = lu.solve(rhs);
        if (n <= limit) {
            EXPECT_EQ(xs.col(0), x) << "n = " << n;
        }
        EXPECT_LT(varsym::test::backward_error(a, xs.col(2), rhs.col(2)),
                  10.0 * static_cast<double>(n) * eps);
        // Solving in place: x and b the same vector.
        Eigen::VectorXd y = b;
        lu.solve(y, y);
        EXPECT_EQ(y, x) << "n = " << n;
    }
}

// The rows are exchanged: a zero on the diagonal needs the pivot from below. Without pivoting
// the first step would divide by zero (the negative control: the matrix's (0, 0) entry is 0).
TEST(SmallLu, PivotsPastAZeroDiagonal) {
    Eigen::MatrixXd a(3, 3);
    a << 0.0, 2.0, 1.0, //
        1.0, 1.0, 0.0,  //
        3.0, 0.0, 1.0;
    ASSERT_EQ(a(0, 0), 0.0);
    const Eigen::Vector3d exact(1.0, -2.0, 0.5); // the solution, chosen: b = a · exact
    const Eigen::VectorXd b = a * exact;
    varsym::small_lu lu(3);
    lu.compute(a);
    Eigen::VectorXd x(3);
    lu.solve(b, x);
    EXPECT_LT((x - exact).lpNorm<Eigen::Infinity>(), 8.0 * std::numeric_limits<double>::epsilon());
}

// A singular matrix gives a non-finite solution, which the steppers' checks catch (a step that
// fails), as Eigen's factors do.
TEST(SmallLu, SingularMatrixGivesANonFiniteSolution) {
    Eigen::MatrixXd a(3, 3);
    a << 1.0, 2.0, 3.0, //
        2.0, 4.0, 6.0,  //
        0.0, 1.0, 1.0;  // rows 0 and 1 dependent
    varsym::small_lu lu;
    lu.compute(a);
    Eigen::VectorXd x(3);
    lu.solve(Eigen::Vector3d(1.0, 1.0, 1.0), x);
    EXPECT_FALSE(x.allFinite());
    // The negative control: the same matrix with the dependence broken solves.
    a(1, 2) = 7.0;
    lu.compute(a);
    lu.solve(Eigen::Vector3d(1.0, 1.0, 1.0), x);
    EXPECT_TRUE(x.allFinite());
}

// One object factors matrices of changing sizes in turn, across the limit where it hands the
// matrix to Eigen, whatever size it was reserved for.
TEST(SmallLu, RefactorsAtAnotherSize) {
    std::mt19937 g(3);
    constexpr Eigen::Index limit = varsym::small_lu::unblocked_limit;
    varsym::small_lu lu(limit + 10);
    for (Eigen::Index n : {Eigen::Index{18}, Eigen::Index{6}, limit + 10, Eigen::Index{18},
                           limit + 1, limit, Eigen::Index{1}}) {
        const Eigen::MatrixXd a = random_matrix(n, g);
        const Eigen::VectorXd b = Eigen::VectorXd::Ones(n);
        lu.compute(a);
        EXPECT_EQ(lu.rows(), n);
        Eigen::VectorXd x(n);
        lu.solve(b, x);
        EXPECT_LT(varsym::test::backward_error(a, x, b),
                  10.0 * static_cast<double>(n) * std::numeric_limits<double>::epsilon())
            << "n = " << n;
    }
}

// negated_inverse_rows (a step's sensitivity ∂q_{j+1}/∂p_j) skips the forward substitution's
// leading zeros and the back substitution's rows above `first`: its rows are the full solve's
// of [I_k; 0], negated, bit for bit, below the limit (above it, Eigen's solve of the same), for
// row ranges at the top, in the middle (the constrained step's X_s, with multipliers below) and
// at the bottom. The same where a factor is not finite (a singular matrix, or a NaN in the
// matrix: the full solve's NaN and infinities).
TEST(SmallLu, InverseRowsAreTheFullSolvesRows) {
    std::mt19937 g(11);
    constexpr Eigen::Index limit = varsym::small_lu::unblocked_limit;
    varsym::small_lu lu;
    const auto expect_rows = [&lu](Eigen::Index k, Eigen::Index first, Eigen::Index count,
                                   const char* what) {
        const Eigen::Index n = lu.rows();
        Eigen::MatrixXd b = Eigen::MatrixXd::Zero(n, k);
        b.topRows(k).setIdentity();
        const Eigen::MatrixXd full = -lu.solve(b).middleRows(first, count);
        Eigen::MatrixXd rows;
        lu.negated_inverse_rows(k, first, count, rows);
        ASSERT_EQ(rows.rows(), count);
        ASSERT_EQ(rows.cols(), k);
        for (Eigen::Index j = 0; j < k; ++j)
            for (Eigen::Index i = 0; i < count; ++i) {
                const double e = full(i, j), r = rows(i, j);
                EXPECT_TRUE(e == r || (std::isnan(e) && std::isnan(r)))
                    << what << ", n = " << n << ", (" << i << ", " << j << "): " << r << " for "
                    << e;
            }
    };
    for (const Eigen::Index d : {Eigen::Index{1}, Eigen::Index{7}, Eigen::Index{19}}) {
        const Eigen::Index n = 2 * d + 2; // the constrained gauss-2 step: 2 d + 2 m, m = 1
        if (n > limit) continue;
        lu.compute(random_matrix(n, g));
        expect_rows(d, d, d, "X_s with multipliers below");
        expect_rows(d, 0, d, "the top rows");
        expect_rows(d, n - d, d, "the bottom rows");
        lu.compute(random_matrix(2 * d, g)); // the unconstrained step: X_s the bottom rows
        expect_rows(d, d, d, "the unconstrained X_s");
    }
    lu.compute(random_matrix(limit + 4, g)); // Eigen's factors
    expect_rows(10, 20, 10, "above the limit");
    Eigen::MatrixXd singular = random_matrix(12, g);
    singular.col(3).setZero(); // an exact zero pivot: 1/0 among the reciprocal pivots
    lu.compute(singular);
    expect_rows(5, 1, 5, "a singular matrix");
    Eigen::MatrixXd rows; // rows 1 to 5: row 3's unknown is multiplied by 1/0
    lu.negated_inverse_rows(5, 1, 5, rows);
    EXPECT_FALSE(rows.allFinite()); // the negative control of the comparison's NaN branch
    Eigen::MatrixXd nan = random_matrix(12, g);
    nan(7, 2) = std::numeric_limits<double>::quiet_NaN(); // a NaN among L's factors
    lu.compute(nan);
    expect_rows(5, 5, 5, "a NaN in the matrix");
}
