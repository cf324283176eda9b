// The ensemble building blocks (run/ensemble.hpp): the grid's numbering, the parallel loop (every
// member once, exceptions carried out), and one member's run: its event time against the exact
// pendulum (the quarter period, where q crosses 0), its failure report, and its final state
// against a plain loop of steps.
#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <vector>

#include "varsym/problems/pendulum.hpp"
#include "varsym/run/ensemble.hpp"
#include "varsym/schemes/simpson.hpp"

namespace varsym {
namespace {

TEST(ensemble_grid, numbers_members_with_the_last_axis_fastest) {
    const grid g({{"a", 0.0, 1.0, 3}, {"b", -1.0, 1.0, 2}});
    ASSERT_EQ(g.size(), 6U);
    std::vector<double> v;
    g.point(0, v);
    EXPECT_EQ(v, (std::vector<double>{0.0, -1.0}));
    g.point(1, v);
    EXPECT_EQ(v, (std::vector<double>{0.0, 1.0}));
    g.point(4, v);
    EXPECT_EQ(v, (std::vector<double>{1.0, -1.0}));
    EXPECT_EQ(grid_axis({"c", 0.1, 0.7, 7}).value(6), 0.7); // the last point is `last` exactly
    EXPECT_EQ(grid_axis({"c", 5.0, 9.0, 1}).value(0), 5.0);
    EXPECT_THROW(grid({{"a", 0.0, 1.0, 0}}), std::invalid_argument);
}

TEST(ensemble_loop, calls_every_member_once_on_any_number_of_threads) {
    for (unsigned threads : {1U, 2U, 3U, 0U}) {
        std::vector<std::atomic<int>> calls(1000);
        for_each_member(calls.size(), threads, [&](std::size_t m) { ++calls[m]; });
        for (const auto& c : calls)
            ASSERT_EQ(c.load(), 1) << threads << " threads";
    }
    std::atomic<int> after{0};
    EXPECT_THROW(for_each_member(100, 2,
                                 [&](std::size_t m) {
                                     if (m == 10) throw std::runtime_error("member 10");
                                     if (m > 60) ++after;
                                 }),
                 std::runtime_error);
    EXPECT_LT(after.load(), 40); // the loop stopped taking members
}

TEST(ensemble_member, event_time_is_the_exact_quarter_period) {
    // From rest at q0 = 2 (libration), q reaches 0 at T/4 exactly; T from the elliptic integral.
    const auto sys = pendulum::make_system(1.0, 1.0);
    const pendulum::exact_solution exact(1.0, 1.0, 2.0, 0.0);
    const double period = exact.period(), h = period / 200;
    simpson::stepper s(sys, h);
    const member_result r = run_member(
        s, phase_state<1>{vec<1>{2.0}, vec<1>{0.0}}, {200, true, 0.0},
        [&](const phase_state<1>& x) { return sys.energy(x); },
        [](double, const phase_state<1>& x) { return x.q(0); });
    ASSERT_EQ(r.status, member_result::outcome::event);
    EXPECT_EQ(r.steps, 50); // the crossing is at step 50 of 200 (t = T/4 up to round-off)
    // Linear interpolation across the step: its error is (h²/8) |q''/q'| ≈ 0 where q'' = −sin q
    // vanishes, so the scheme's own O(h⁴) phase error remains (measured 1.7e-10 · T).
    EXPECT_NEAR(r.event_time, period / 4, 1e-8 * period);
    EXPECT_LT(r.max_energy_error, 1e-5);
    // Negative control: the event of q − 0.5 is not at T/4.
    simpson::stepper s2(sys, h);
    const member_result r2 = run_member(
        s2, phase_state<1>{vec<1>{2.0}, vec<1>{0.0}}, {200, false, 0.0},
        [&](const phase_state<1>& x) { return sys.energy(x); },
        [](double, const phase_state<1>& x) { return x.q(0) - 0.5; });
    EXPECT_GT(std::abs(r2.event_time - period / 4), 0.01 * period);
    EXPECT_TRUE(std::isnan(r2.lyapunov)); // indicators off
}

TEST(ensemble_member, ends_as_a_plain_loop_and_reports_a_failure) {
    const auto sys = pendulum::make_system(1.0, 1.0);
    simpson::stepper s(sys, 0.05), plain(sys, 0.05);
    phase_state<1> x{vec<1>{1.0}, vec<1>{0.3}};
    const member_result r = run_member(
        s, x, {300, true, 0.0}, [&](const phase_state<1>& y) { return sys.energy(y); },
        [](double, const phase_state<1>&) { return 1.0; });
    for (int k = 0; k < 300; ++k)
        ASSERT_TRUE(plain.step(x).converged);
    EXPECT_EQ(r.status, member_result::outcome::completed);
    EXPECT_EQ(r.q[0], x.q(0));
    EXPECT_EQ(r.p[0], x.p(0));
    EXPECT_NEAR(r.time, 15.0, 1e-12);
    // A step far beyond Newton's reach: reported, with the state before it.
    simpson::stepper wild(sys, 40.0);
    const member_result f = run_member(
        wild, phase_state<1>{vec<1>{3.1}, vec<1>{0.0}}, {10, true, 0.0},
        [&](const phase_state<1>& y) { return sys.energy(y); },
        [](double, const phase_state<1>&) { return 1.0; });
    EXPECT_EQ(f.status, member_result::outcome::failed);
    EXPECT_NE(f.cause.find("Newton"), std::string::npos);
}

} // namespace
} // namespace varsym
