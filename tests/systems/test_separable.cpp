// tests/systems/test_separable.cpp: a separable system refuses a mass matrix that is not
// symmetric positive definite, and its energy is ½pᵀM⁻¹p + V(q).
#include <gtest/gtest.h>

#include "test_support.hpp"
#include "varsym/problems/pendulum.hpp"

using namespace varsym;

TEST(Separable, RefusesBadMassMatrices) {
    mat<2> m;
    m << 1.0, 2.0, 2.0, 1.0; // symmetric, eigenvalues 3 and −1
    EXPECT_THROW((separable_system<2, test::coupled_pendulums>(m, {})), std::invalid_argument);
    m << 1.0, 0.1, 0.0, 1.0; // not symmetric
    EXPECT_THROW((separable_system<2, test::coupled_pendulums>(m, {})), std::invalid_argument);
    m << 1.0, 0.0, 0.0, std::nan("");
    EXPECT_THROW((separable_system<2, test::coupled_pendulums>(m, {})), std::invalid_argument);
    EXPECT_THROW(pendulum::make_system(-1.0, 1.0), std::invalid_argument);
    EXPECT_THROW(pendulum::make_system(1.0, 0.0), std::invalid_argument);
}

TEST(Separable, EnergyIsKineticPlusPotential) {
    const auto sys = test::coupled_system();
    const phase_state<2> x{vec<2>{0.3, -0.2}, vec<2>{1.0, 2.0}};
    // M = [[2, .5], [.5, 1]], M⁻¹ = [[1, −.5], [−.5, 2]] / 1.75; pᵀM⁻¹p = (1 − 2 + 8)/1.75 = 4.
    const double kinetic = 0.5 * 4.0;
    EXPECT_NEAR(sys.energy(x), kinetic + test::coupled_pendulums{}.value(x.q), 1e-15);
}
