// tests/numeric/test_family_orders.cpp: the measured order of every member of the family is
// 2s (±0.15) on the paper's pendulum, for every s that double precision can measure.
//
// Error: max over the steps of one period of |q_j − q(t_j)|, against the exact solution in
// long double (so the reference adds nothing at the 1e-15 level), with t_j = j h exactly.
// For each member the step counts are where the error has reached its asymptotic regime and is
// still above the integrator's round-off floor (~2e-15: 10 ulps of |q| ≤ π/2). For s = 5 and 6
// no such window exists: the error falls from the pre-asymptotic regime (local orders 8 to 19)
// to the floor within one or two refinements. The last pair before the floor (N = 24 → 32, errors
// 1e-13 → 1e-14) shows about 10 for s = 5, but moves by ±0.25 with the last bits of the
// arithmetic, so it is not asserted; for s = 5, 6 the test requires that they reach the floor.
#include <gtest/gtest.h>

#include <numbers>
#include <vector>

#include "pendulum_period_error.hpp"
#include "varsym/diagnostics/convergence.hpp"
#include "varsym/schemes/galerkin.hpp"

using namespace varsym;
using galerkin::rule_kind;

namespace {

double state_error(rule_kind kind, int s, int steps_per_period) {
    const double h = static_cast<double>(test::paper_pendulum_exact().period() / steps_per_period);
    galerkin::stepper stepper(pendulum::make_system(1.0, 2 * std::numbers::pi), h, kind, s);
    return test::period_error(stepper, steps_per_period);
}

double measured_order(rule_kind kind, int s, const std::vector<double>& steps) {
    std::vector<double> errors;
    for (double n : steps)
        errors.push_back(state_error(kind, s, static_cast<int>(n)));
    return fitted_order(steps, errors);
}

} // namespace

TEST(FamilyOrders, Lobatto) {
    const std::vector<std::vector<double>> windows = {
        {64, 128, 256}, {64, 128, 256}, {48, 64, 96, 128}, {24, 32, 48, 64}};
    for (int s = 1; s <= 4; ++s)
        EXPECT_NEAR(measured_order(rule_kind::lobatto, s, windows[s - 1]), 2 * s, 0.15)
            << "s = " << s;
}

TEST(FamilyOrders, Gauss) {
    const std::vector<std::vector<double>> windows = {
        {64, 128, 256}, {64, 128, 256}, {32, 48, 64, 96, 128}, {24, 32, 48, 64}};
    for (int s = 1; s <= 4; ++s)
        EXPECT_NEAR(measured_order(rule_kind::gauss, s, windows[s - 1]), 2 * s, 0.15)
            << "s = " << s;
}

TEST(FamilyOrders, HighestDegreesReachTheRoundOffFloor) {
    // Measured: Lobatto 5, Gauss 5 at N = 48: ~1.4e-15; Lobatto 6, Gauss 6 at N = 24: ~2e-15.
    EXPECT_LT(state_error(rule_kind::lobatto, 5, 48), 1e-14);
    EXPECT_LT(state_error(rule_kind::gauss, 5, 48), 1e-14);
    EXPECT_LT(state_error(rule_kind::lobatto, 6, 24), 1e-14);
    EXPECT_LT(state_error(rule_kind::gauss, 6, 24), 1e-14);
    // … and are not there by accident at a coarse step: order 12 from 6e-9-level errors at N = 8.
    EXPECT_GT(state_error(rule_kind::gauss, 6, 8), 1e-10);
}
