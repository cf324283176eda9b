// tests/schemes/test_integrate.cpp: the driver names the step and time of a failed step, keeps
// the last good state, and calls the observer once per step.
#include <gtest/gtest.h>

#include <numbers>
#include <string>

#include "varsym/integrate.hpp"
#include "varsym/problems/pendulum.hpp"
#include "varsym/schemes/simpson.hpp"

using namespace varsym;

namespace {

// A stepper that adds 1 to q and fails at step `fail_at` with a known report.
struct failing_stepper {
    static constexpr int dim = 1;
    int fail_at;
    int count = 0;
    [[nodiscard]] double step_size() const { return 0.25; }
    newton_report step(phase_state<1>& x) {
        if (++count == fail_at) return {false, 25, 123.5};
        x.q(0) += 1.0;
        return {true, 2, 0.0};
    }
};

} // namespace

TEST(Integrate, FailureNamesStepTimeAndResidual) {
    failing_stepper s{7};
    phase_state<1> x{vec<1>{0.0}, vec<1>{0.0}};
    int observed = 0;
    try {
        integrate(s, x, 1.0, 100, [&](std::size_t, double, const phase_state<1>&) { ++observed; });
        FAIL() << "expected step_failure";
    } catch (const step_failure& e) {
        EXPECT_EQ(e.step(), 7u);
        EXPECT_DOUBLE_EQ(e.time(), 1.0 + 6 * 0.25);
        EXPECT_EQ(e.report().residual, 123.5);
        const std::string msg = e.what();
        EXPECT_NE(msg.find("step 7"), std::string::npos) << msg;
        EXPECT_NE(msg.find("t = 2.5"), std::string::npos) << msg;
        EXPECT_NE(msg.find("1.235e+02"), std::string::npos) << msg;
        // diagnosis() is what() without the advice, for callers that give their own.
        EXPECT_EQ(msg, e.diagnosis() + "; use a smaller time step");
    }
    EXPECT_EQ(x.q(0), 6.0); // the state after the last good step
    EXPECT_EQ(observed, 7); // j = 0 … 6
}

TEST(Integrate, SummaryCountsNewtonIterations) {
    failing_stepper s{-1};
    phase_state<1> x{vec<1>{0.0}, vec<1>{0.0}};
    const auto sum = integrate(s, x, 0.0, 10, [](std::size_t, double, const phase_state<1>&) {});
    EXPECT_EQ(sum.steps, 10u);
    EXPECT_EQ(sum.newton_iterations, 20);
    EXPECT_EQ(sum.newton_iterations_max, 2);
}

TEST(Integrate, HugeStepDivergesWithAnError) {
    // One Simpson step per period of the paper's pendulum (h = T): Newton's iteration on the
    // midpoint equation does not converge at step 2, and the run must stop there.
    const pendulum::exact_solution exact(1.0, 2 * std::numbers::pi, std::numbers::pi / 2, 0.0);
    simpson::stepper s(pendulum::make_system(1.0, 2 * std::numbers::pi), exact.period());
    phase_state<1> x{vec<1>{std::numbers::pi / 2}, vec<1>{0.0}};
    EXPECT_THROW(integrate(s, x, 0.0, 3, [](std::size_t, double, const phase_state<1>&) {}),
                 step_failure);
}
