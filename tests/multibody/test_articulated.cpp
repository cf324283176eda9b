// The O(n) mass-matrix solve (multibody/articulated.hpp) against the composite-rigid-body M(q)
// (algorithms.hpp) solved densely: an independent algorithm for the same matrix; several columns
// at once against the solves of each alone.
#include <gtest/gtest.h>

#include <random>

#include "multibody/random_tree.hpp"
#include "varsym/multibody/lagrangian.hpp"

namespace {

using namespace varsym;

/// max |M x − τ| / max |τ| for x from robot_lagrangian's solve_mass, M by the CRBA.
double solve_error(const multibody::tree& m, unsigned seed) {
    const multibody::robot_lagrangian lag(std::make_shared<const multibody::tree>(m));
    const int n = lag.dimension();
    std::mt19937 g(seed);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    Eigen::VectorXd q(n), tau(n);
    for (int i = 0; i < n; ++i) {
        q(i) = u(g);
        tau(i) = u(g);
    }
    Eigen::MatrixXd mass;
    lag.mass_matrix(q, mass);
    EXPECT_TRUE(lag.factor_mass(q));
    EXPECT_LT((lag.mass_diagonal() - mass.diagonal()).lpNorm<Eigen::Infinity>(),
              1e-13 * mass.diagonal().lpNorm<Eigen::Infinity>());
    Eigen::VectorXd x = tau;
    lag.solve_mass(x);
    // Three columns at once (the articulated iteration's blocks): each the solve of it alone,
    // to the bit without mimic joints (the same operations, interleaved); within 1e-12 of it
    // with them (the dense LLT's blocked solves round differently).
    Eigen::MatrixXd b(n, 3), xs;
    b << tau, tau.reverse(), Eigen::VectorXd::LinSpaced(n, -1.0, 2.0);
    xs = b;
    lag.solve_mass(xs);
    for (int j = 0; j < 3; ++j) {
        Eigen::VectorXd alone = b.col(j);
        lag.solve_mass(alone);
        if (m.mimics.empty())
            EXPECT_EQ(xs.col(j), alone) << "column " << j;
        else
            EXPECT_LT((xs.col(j) - alone).lpNorm<Eigen::Infinity>(),
                      1e-12 * alone.lpNorm<Eigen::Infinity>());
    }
    return (mass * x - tau).lpNorm<Eigen::Infinity>() / tau.lpNorm<Eigen::Infinity>();
}

// The residual of the solve is round-off of M's entries times x, amplified by M's conditioning
// (random placements, axes and inertias; prismatic and revolute joints mixed): 1e-12 of τ leaves
// room for the articulated inertias' rounding and fails a wrong recursion by orders of magnitude
// (checked: dropping the U Uᵀ/D term from the parent's articulated inertia fails every case).
TEST(ArticulatedBody, SolvesWithTheMassMatrixOfABranchedTree) {
    for (unsigned seed = 1; seed <= 20; ++seed)
        EXPECT_LT(solve_error(test::random_tree(seed), 100 + seed), 1e-12) << "seed " << seed;
}

TEST(ArticulatedBody, SolvesWithTheMassMatrixOfALongChain) {
    multibody::tree m;
    std::mt19937 g(5);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int i = 0; i < 60; ++i) {
        multibody::body b;
        b.name = "j" + std::to_string(i);
        b.link = "l" + std::to_string(i);
        b.placement.origin = multibody::vec3(0.0, 0.0, 0.3);
        b.axis = multibody::vec3(u(g), u(g), u(g)).normalized();
        b.mass = 1.0;
        b.com = multibody::vec3(0.0, 0.0, 0.15);
        b.inertia = test::random_inertia(g);
        m.add_body(i - 1, b);
    }
    EXPECT_LT(solve_error(m, 7), 1e-11);
}

// Mimic joints couple coordinates: the dense factorisation takes over, with the same contract
// (its diagonal is the composite-rigid-body M's own, so solve_error's diagonal check is trivial
// here; the solve is not).
TEST(ArticulatedBody, MimicJointsFactoriseDensely) {
    EXPECT_LT(solve_error(test::mimic_tree(true), 3), 1e-12);
}

// A massless end body leaves M singular: the factorisation says so instead of dividing by zero.
TEST(ArticulatedBody, RefusesASingularMassMatrix) {
    multibody::tree m = test::random_tree(4);
    m.bodies.back().mass = 0.0;
    m.bodies.back().inertia.setZero();
    const multibody::robot_lagrangian lag(std::make_shared<const multibody::tree>(m));
    EXPECT_FALSE(lag.factor_mass(Eigen::VectorXd::Zero(lag.dimension())));
}

} // namespace
