// tests/run/test_state.cpp: the library's run state and observers. A run stopped by an observer
// and resumed from its run_state ends on the same bits as a straight run (the property the
// tool's checkpoints rest on); the ready observers fire on the steps they promise.
#include <gtest/gtest.h>

#include <numbers>
#include <vector>

#include "varsym/problems/pendulum.hpp"
#include "varsym/run/observers.hpp"
#include "varsym/run/state.hpp"
#include "varsym/schemes/scheme_kind.hpp"

using namespace varsym;

namespace {
const auto run_sys = pendulum::make_system(1.0, 2 * std::numbers::pi);
const phase_state<1> run_start{vec<1>{std::numbers::pi / 2}, vec<1>{0.0}};
constexpr double run_h = 0.02;
} // namespace

TEST(RunState, StopAndResumeIsBitExactForEveryKindOfStepper) {
    for (const scheme_spec spec :
         {scheme_spec(scheme_kind::simpson), scheme_spec(scheme_kind::newmark),
          scheme_spec(scheme_kind::gauss, 3), scheme_spec(scheme_kind::lobatto, 4)}) {
        SCOPED_TRACE(spec.label());
        auto straight = run_state<1>::start(run_start);
        with_stepper(spec, run_sys, run_h, {}, [&](auto& s) {
            EXPECT_TRUE(integrate_from(s, straight, 600, [](const auto&) {}));
        });
        // The first run stops itself at t = 3.7 (step 185) and keeps its state, as a
        // checkpoint callback would.
        std::vector<run_state<1>> saved;
        auto part = run_state<1>::start(run_start);
        with_stepper(spec, run_sys, run_h, {}, [&](auto& s) {
            const bool done = integrate_from(
                s, part, 600,
                observe::all(observe::checkpoint_every_steps(
                                 50, [&](const run_state<1>& r) { saved.push_back(r); }),
                             observe::until_time(3.7, run_h)));
            EXPECT_FALSE(done);
        });
        EXPECT_EQ(part.step, 185u);
        ASSERT_EQ(saved.size(), 3u); // steps 50, 100, 150
        EXPECT_EQ(saved.back().step, 150u);
        // A new stepper resumed from the checkpoint at step 150 finishes the run.
        auto resumed = saved.back();
        with_stepper(spec, run_sys, run_h, {}, [&](auto& s) {
            restore(s, resumed);
            EXPECT_TRUE(integrate_from(s, resumed, 600, [](const auto&) {}));
        });
        EXPECT_EQ(resumed.step, 600u);
        EXPECT_EQ(resumed.x.q(0), straight.x.q(0));
        EXPECT_EQ(resumed.x.p(0), straight.x.p(0));
        EXPECT_EQ(resumed.stats.newton_iterations, straight.stats.newton_iterations);
        EXPECT_DOUBLE_EQ(resumed.time(run_h), 12.0);
    }
}

TEST(RunState, WithoutCarriesTheResumeDiffers) {
    // Negative control: dropping the compensated-summation carries (restoring only q and p) is
    // not bit-exact, so the test above checks something.
    auto straight = run_state<1>::start(run_start);
    simpson::stepper a(run_sys, run_h);
    integrate_from(a, straight, 5000, [](const auto&) {});
    auto part = run_state<1>::start(run_start);
    simpson::stepper b(run_sys, run_h);
    integrate_from(b, part, 2500, [](const auto&) {});
    part.carry_q.setConstant(1e-17);
    part.carry_p.setConstant(-1e-17);
    simpson::stepper c(run_sys, run_h);
    restore(c, part);
    integrate_from(c, part, 5000, [](const auto&) {});
    EXPECT_NE(part.x.q(0), straight.x.q(0));
}

TEST(Observers, EveryFiresOnMultiplesAndCanStop) {
    simpson::stepper s(run_sys, run_h);
    auto r = run_state<1>::start(run_start, 1.0);
    std::vector<std::size_t> seen;
    const bool done = integrate_from(s, r, 100, observe::every(30, [&](const run_state<1>& x) {
                                         seen.push_back(x.step);
                                         return x.step == 60; // stop at the second call
                                     }));
    EXPECT_FALSE(done);
    EXPECT_EQ(seen, (std::vector<std::size_t>{30, 60}));
    EXPECT_EQ(r.stats.steps, 60u);
    EXPECT_DOUBLE_EQ(r.time(run_h), 1.0 + 60 * run_h);
    EXPECT_THROW(observe::every(0, [](const auto&) {}), std::invalid_argument);
}

TEST(Observers, CheckpointByWallTimeFiresAfterItsInterval) {
    simpson::stepper s(run_sys, run_h);
    auto r = run_state<1>::start(run_start);
    int saves = 0;
    // An interval longer than the run: never fires. A tiny one: fires on (nearly) every step.
    integrate_from(s, r, 200,
                   observe::checkpoint_every_seconds(3600.0, [&](const auto&) { ++saves; }));
    EXPECT_EQ(saves, 0);
    integrate_from(s, r, 400,
                   observe::checkpoint_every_seconds(1e-9, [&](const auto&) { ++saves; }));
    EXPECT_GE(saves, 150);
    EXPECT_THROW(observe::checkpoint_every_seconds(0.0, [](const auto&) {}), std::invalid_argument);
}
