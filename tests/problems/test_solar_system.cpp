// tests/problems/test_solar_system.cpp: the outer solar system (problems/solar_system.hpp) as
// HLW §I.2.4 give it, integrated by two independent implementations that must agree, with its
// conservation laws.
#include <gtest/gtest.h>

#include "schemes/nbody.hpp"
#include "varsym/integrate.hpp"
#include "varsym/problems/solar_system.hpp"
#include "varsym/schemes/composition.hpp"
#include "varsym/schemes/galerkin.hpp"

using namespace varsym;

namespace {

const solar_system::system sys = solar_system::make_system();

} // namespace

TEST(SolarSystem, DataAsPublished) {
    const auto x = solar_system::initial_state();
    EXPECT_EQ(solar_system::dim, 18);
    // Jupiter's first coordinate and momentum, Pluto's mass (HLW Table I.2.1).
    EXPECT_EQ(x.q(3), -3.5023653);
    EXPECT_DOUBLE_EQ(x.p(3), 0.000954786104043 * 0.00565429);
    EXPECT_DOUBLE_EQ(solar_system::bodies[5].mass, 1.0 / 1.3e8);
    // Bound: the energy is negative, and Jupiter's potential term dominates the Sun's.
    EXPECT_LT(sys.energy(x), 0.0);
}

// The family (gauss-4, Newton) and Kahan–Li's explicit order-8 composition share no code but the
// potential; over 20 000 days (4.6 Jupiter periods) their positions agree to 2.6e-14 AU
// (measured), far below gauss-4's own error at a coarser step (h = 200 days: 9.5e-9 AU; at 100
// days 3.7e-11, the ratio 254 ≈ 2⁸ of order 8), so each checks the other.
TEST(SolarSystem, FamilyAndCompositionAgree) {
    const double days = 20000;
    galerkin::stepper family(sys, 20.0, galerkin::rule_kind::gauss, 4);
    composition::stepper explicit_(sys, 5.0, composition::method::kahan_li8);
    auto x = solar_system::initial_state(), y = x;
    integrate(family, x, 0.0, static_cast<std::size_t>(days / 20.0), [](auto, auto, auto&) {});
    integrate(explicit_, y, 0.0, static_cast<std::size_t>(days / 5.0), [](auto, auto, auto&) {});
    EXPECT_LT((x.q - y.q).lpNorm<Eigen::Infinity>(), 1e-12);
    // Negative control: a step 10x coarser moves the family's answer by far more than that.
    galerkin::stepper coarse(sys, 200.0, galerkin::rule_kind::gauss, 4);
    auto z = solar_system::initial_state();
    integrate(coarse, z, 0.0, static_cast<std::size_t>(days / 200.0), [](auto, auto, auto&) {});
    EXPECT_GT((z.q - y.q).lpNorm<Eigen::Infinity>(), 1e-10);
}

// Translation and rotation invariance: the total momentum and angular momentum of a variational
// step are conserved to round-off (|L| ≈ 2e-5 in these units); the energy error stays bounded.
TEST(SolarSystem, ConservationLaws) {
    galerkin::stepper stepper(sys, 50.0, galerkin::rule_kind::gauss, 3);
    auto x = solar_system::initial_state();
    const Eigen::Vector3d p0 = test::total_momentum(x.p), l0 = test::angular_momentum(x.q, x.p);
    const double e0 = sys.energy(x);
    double worst = 0;
    integrate(stepper, x, 0.0, 4000, [&](auto, auto, const phase_state<18>& y) {
        worst = std::max(worst, std::abs(sys.energy(y) - e0) / std::abs(e0));
    });
    EXPECT_LT((test::total_momentum(x.p) - p0).norm(), 1e-18);
    EXPECT_LT((test::angular_momentum(x.q, x.p) - l0).norm(), 1e-13 * l0.norm());
    EXPECT_LT(worst, 1e-9);
}
