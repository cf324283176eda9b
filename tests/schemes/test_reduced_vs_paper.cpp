// tests/schemes/test_reduced_vs_paper.cpp: the fast reduced steppers (one D×D Newton solve)
// give the same trajectories as the paper's full Newton systems F_N and F_S, to round-off.
#include <gtest/gtest.h>

#include <numbers>

#include "test_support.hpp"
#include "varsym/integrate.hpp"
#include "varsym/problems/pendulum.hpp"
#include "varsym/reference/paper_schemes.hpp"
#include "varsym/schemes/newmark.hpp"
#include "varsym/schemes/simpson.hpp"

using namespace varsym;
using std::numbers::pi;

namespace {

// Runs both steppers side by side for n steps; returns the largest |Δq|, |Δp| seen.
template <class Fast, class Reference, int D>
double max_difference(Fast fast, Reference ref, phase_state<D> x0, std::size_t n) {
    phase_state<D> a = x0, b = x0;
    double worst = 0;
    for (std::size_t j = 0; j < n; ++j) {
        EXPECT_TRUE(fast.step(a).converged);
        EXPECT_TRUE(ref.step(b).converged);
        worst = std::max({worst, (a.q - b.q).template lpNorm<Eigen::Infinity>(),
                          (a.p - b.p).template lpNorm<Eigen::Infinity>()});
    }
    return worst;
}

} // namespace

// Tolerance 1e-13 over 10 periods at Table 1's step counts: both solve the same equations to
// machine precision for the increments (Δq, Δp), accumulated with compensated summation, so
// they differ by round-off in the increments only (measured: ≤ 4e-14).
TEST(ReducedVsPaper, PendulumTenPeriods) {
    const pendulum::exact_solution exact(1.0, 2 * pi, pi / 2, 0.0);
    const auto sys = pendulum::make_system(1.0, 2 * pi);
    const phase_state<1> x0{vec<1>{pi / 2}, vec<1>{0.0}};
    for (int n : {50, 100, 200}) {
        const double h = exact.period() / n;
        const auto steps = static_cast<std::size_t>(10 * n);
        EXPECT_LE(max_difference(newmark::stepper(sys, h), paper_reference::newmark_stepper(sys, h),
                                 x0, steps),
                  1e-13)
            << "newmark, N = " << n;
        EXPECT_LE(max_difference(simpson::stepper(sys, h), paper_reference::simpson_stepper(sys, h),
                                 x0, steps),
                  1e-13)
            << "simpson, N = " << n;
    }
}

// Figure 2's N = 10: the increments are as large as the state (|Δp| ≈ 4, |p| ≤ 9), so each step
// rounds at ~1 ulp of p (2e-15) and the shear of the flow grows that over 100 steps (measured
// ≤ 2.5e-13): 1e-12.
TEST(ReducedVsPaper, PendulumTenPeriodsCoarse) {
    const pendulum::exact_solution exact(1.0, 2 * pi, pi / 2, 0.0);
    const auto sys = pendulum::make_system(1.0, 2 * pi);
    const phase_state<1> x0{vec<1>{pi / 2}, vec<1>{0.0}};
    const double h = exact.period() / 10;
    EXPECT_LE(
        max_difference(newmark::stepper(sys, h), paper_reference::newmark_stepper(sys, h), x0, 100),
        1e-12);
    EXPECT_LE(
        max_difference(simpson::stepper(sys, h), paper_reference::simpson_stepper(sys, h), x0, 100),
        1e-12);
}

TEST(ReducedVsPaper, RotatingPendulum) {
    const auto sys = pendulum::make_system(1.5, 2.0);
    const phase_state<1> x0{vec<1>{0.5}, vec<1>{7.0}};
    const double h = 0.02;
    EXPECT_LE(
        max_difference(simpson::stepper(sys, h), paper_reference::simpson_stepper(sys, h), x0, 500),
        1e-12); // q grows to ~60 rad here: same relative accuracy as above
    EXPECT_LE(
        max_difference(newmark::stepper(sys, h), paper_reference::newmark_stepper(sys, h), x0, 500),
        1e-12);
}

TEST(ReducedVsPaper, CoupledPendulumsWithFullMassMatrix) {
    // d = 2 with a non-diagonal M: the reduction M q_m + c∇V(q_m) = b holds for any SPD M.
    const auto sys = test::coupled_system();
    const phase_state<2> x0{vec<2>{1.0, -0.5}, vec<2>{0.3, 1.2}};
    const double h = 0.05;
    EXPECT_LE(
        max_difference(simpson::stepper(sys, h), paper_reference::simpson_stepper(sys, h), x0, 400),
        1e-13);
    EXPECT_LE(
        max_difference(newmark::stepper(sys, h), paper_reference::newmark_stepper(sys, h), x0, 400),
        1e-13);
}
