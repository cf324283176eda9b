// tests/solvers/test_iteration_choice.cpp: the automatic choice between Newton and the
// articulated iteration (solvers/iteration_choice.hpp), step by step: its windows, holds and
// their doubling, counted against the rules written in the header, and its saved state.
#include <algorithm>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "varsym/solvers/iteration_choice.hpp"

namespace {

using varsym::iteration_choice;

/// Steps whose articulated updates are `updates` each (none handed to Newton) until the choice
/// takes Newton; the steps recorded.
int steps_until_newton(iteration_choice& c, int updates, int most) {
    for (int j = 0; j < most; ++j) {
        if (!c.articulated()) return j;
        c.record(updates, false);
    }
    return most;
}

TEST(IterationChoice, OffByDefault) {
    iteration_choice c;
    EXPECT_FALSE(c.on());
    for (int j = 0; j < 100; ++j)
        c.record(50, true);
    EXPECT_TRUE(c.articulated());
    EXPECT_EQ(c.steps(), 0);
}

TEST(IterationChoice, KeepsTheArticulatedIterationBelowTheBreakEven) {
    iteration_choice c(6.0);
    EXPECT_EQ(steps_until_newton(c, 6, 1000), 1000); // at the break-even: still cheaper or equal
    EXPECT_EQ(c.articulated_steps(), 1000);
}

TEST(IterationChoice, HoldsNewtonAfterASlowWindowAndDoublesTheHold) {
    iteration_choice c(6.0);
    int hold = iteration_choice::first_hold;
    for (int round = 0; round < 9; ++round) {
        // A window of slow steps, then a hold of Newton steps.
        EXPECT_EQ(steps_until_newton(c, 7, 1000), iteration_choice::window) << round;
        for (int j = 0; j < hold; ++j) {
            ASSERT_FALSE(c.articulated()) << round << " " << j;
            c.record(0, false);
        }
        hold = std::min(2 * hold, iteration_choice::max_hold);
    }
    // A good window resets the hold: the next slow window holds first_hold steps again.
    EXPECT_EQ(steps_until_newton(c, 2, iteration_choice::window), iteration_choice::window);
    EXPECT_EQ(steps_until_newton(c, 7, 1000), iteration_choice::window);
    int held = 0;
    while (!c.articulated()) {
        c.record(0, false);
        ++held;
    }
    EXPECT_EQ(held, iteration_choice::first_hold);
}

// A step handed to Newton counts its updates and Newton's step: one such step in a window of
// fast ones is enough to leave the window above a break-even of 4.
TEST(IterationChoice, AStepHandedToNewtonCountsNewtonsCost) {
    iteration_choice c(4.0);
    c.record(3, true); // 3 + 4 + 2.5
    for (int j = 1; j < iteration_choice::window; ++j)
        c.record(4, false);
    EXPECT_FALSE(c.articulated());
    iteration_choice d(4.0);
    for (int j = 0; j < iteration_choice::window; ++j)
        d.record(4, false);
    EXPECT_TRUE(d.articulated()); // negative control: the same window without the handed step
}

TEST(IterationChoice, ASavedStateContinuesAsTheStraightOne) {
    iteration_choice straight(5.0);
    std::vector<int> updates;
    for (int j = 0; j < 3000; ++j)
        updates.push_back(j % 700 < 300 ? 3 : 9); // fast, then slow stretches
    std::vector<double> saved;
    iteration_choice copy(5.0);
    for (int j = 0; j < 3000; ++j) {
        if (j == 1234) {
            straight.save(saved);
            ASSERT_EQ(saved.size(), static_cast<std::size_t>(iteration_choice::saved));
            ASSERT_TRUE(copy.restore(saved.data()));
        }
        if (j >= 1234) {
            ASSERT_EQ(copy.articulated(), straight.articulated()) << j;
            copy.record(copy.articulated() ? updates[j] : 0, false);
        }
        straight.record(straight.articulated() ? updates[j] : 0, false);
    }
}

TEST(IterationChoice, RefusesAStateItCouldNotHaveSaved) {
    iteration_choice c(5.0);
    const double inf = std::numeric_limits<double>::infinity();
    const double bad[][4] = {{16, 0, 0, 64},   {-1, 0, 0, 64}, {0.5, 0, 0, 64}, {0, -1, 0, 64},
                             {0, 0, 5000, 64}, {0, 0, 0, 32},  {0, 0, 0, 8192}, {0, inf, 0, 64}};
    for (const auto& b : bad)
        EXPECT_FALSE(c.restore(b)) << b[0] << " " << b[1] << " " << b[2] << " " << b[3];
    // States save() never writes: updates without steps, a hold within a window, a hold that
    // is not 64 · 2^k, a hold after no failed window, more steps left than the hold before
    // the next (half of it, below the largest).
    const double never[][4] = {{0, 5, 0, 64},  {3, 17, 10, 128}, {0, 0, 0, 96},
                               {0, 0, 10, 64}, {0, 0, 300, 256}, {0, 0, 128, 128}};
    for (const auto& b : never)
        EXPECT_FALSE(c.restore(b)) << b[0] << " " << b[1] << " " << b[2] << " " << b[3];
    const double holding[4] = {0, 0, 10, 128}, window[4] = {3, 17.0, 0, 64};
    EXPECT_TRUE(c.restore(holding));
    EXPECT_FALSE(c.articulated()); // 10 Newton steps left
    EXPECT_TRUE(c.restore(window));
    EXPECT_TRUE(c.articulated());
}

} // namespace
