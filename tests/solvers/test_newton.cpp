// tests/solvers/test_newton.cpp: Newton's method converges to machine precision, and reports
// failure (iteration cap, NaN) instead of returning a wrong answer.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "varsym/solvers/newton.hpp"

using namespace varsym;

TEST(Newton, ScalarRootToMachinePrecision) {
    // x² − 2 = 0 from x = 1: the root is √2 (std::sqrt is correctly rounded).
    vec<1> x{1.0};
    const auto rep = newton_solve<1>(x, [](const vec<1>& y, vec<1>& r, mat<1>& j) {
        r(0) = y(0) * y(0) - 2.0;
        j(0, 0) = 2.0 * y(0);
    });
    EXPECT_TRUE(rep.converged);
    EXPECT_LE(rep.iterations, 7);
    EXPECT_NEAR(x(0), std::sqrt(2.0), 2 * std::numeric_limits<double>::epsilon());
}

TEST(Newton, SystemRootToMachinePrecision) {
    // x² + y² = 4, x = y: root (√2, √2).
    vec<2> x{1.0, 0.5};
    const auto rep = newton_solve<2>(x, [](const vec<2>& y, vec<2>& r, mat<2>& j) {
        r << y(0) * y(0) + y(1) * y(1) - 4.0, y(0) - y(1);
        j << 2 * y(0), 2 * y(1), 1.0, -1.0;
    });
    EXPECT_TRUE(rep.converged);
    EXPECT_NEAR(x(0), std::sqrt(2.0), 4e-16);
    EXPECT_NEAR(x(1), std::sqrt(2.0), 4e-16);
}

TEST(Newton, IterationCapIsReportedWithResidual) {
    // atan(x) = 0 from x = 3: Newton diverges (|x| grows), so the cap is hit.
    vec<1> x{3.0};
    newton_options opt;
    opt.max_iterations = 5;
    const auto rep = newton_solve<1>(
        x,
        [](const vec<1>& y, vec<1>& r, mat<1>& j) {
            r(0) = std::atan(y(0));
            j(0, 0) = 1.0 / (1.0 + y(0) * y(0));
        },
        opt);
    EXPECT_FALSE(rep.converged);
    EXPECT_GT(rep.residual, 1.0); // |atan x| → π/2 as x diverges
}

TEST(Newton, NaNStopsAtOnce) {
    vec<1> x{1.0};
    const auto rep = newton_solve<1>(x, [](const vec<1>&, vec<1>& r, mat<1>& j) {
        r(0) = std::numeric_limits<double>::quiet_NaN();
        j(0, 0) = 1.0;
    });
    EXPECT_FALSE(rep.converged);
    EXPECT_EQ(rep.iterations, 1);
}

TEST(Newton, ChordStopNeedsAMeasuredRate) {
    // The chord's stop by its linear model, ρ/(1 − ρ)|δ| ≤ tolerance, takes ρ as measured above
    // round-off (1024 ε of the unknown). A chord update of 3e-14 after a Newton update of 1e-13,
    // both below that on an unknown of size 1, has no measured rate: its own ratio, 0.3 > 1/8,
    // says the updates are not contracting fast enough to stop (nor is it the round-off floor:
    // 3e-14 is above 64 ε, and below half the update before). Negative control: a chord update 1e-3
    // times its Newton update's stops by the model.
    newton_monitor slow({});
    EXPECT_FALSE(slow.converged(1e-13, 1.0));
    EXPECT_FALSE(slow.converged(3e-14, 1.0, true));
    newton_monitor model({});
    EXPECT_FALSE(model.converged(1e-10, 1.0));
    EXPECT_TRUE(model.converged(1e-13, 1.0, true)); // ρ = 1e-3: 8ρ|δ| = 8e-16 ≤ 7 · 2ε
}

TEST(Newton, ASecondUpdateBelowAnUlpOfTheReferenceStops) {
    // Increments of 1e-10 (typical) to coordinates of 0.5 (reference): u = ε · 0.5 = 1.1e-16,
    // about an ulp of q_j. Newton's second update in a row below u ends the solve while the
    // updates still shrink (a robot at rest: its residual sees increments below an ulp of q
    // through q̇ alone, and its updates shrank linearly to 2ε of the increments). Negative
    // controls, neither stopped by the quadratic model (δ³ > 2ε · 1e-10 · δ_prev²): an update
    // after one above u (1e-15, below the stall floor 64u = 7.1e-15) goes on; so does a linear
    // iteration, whose remainder ρ/(1 − ρ)|δ| the rule would not bound.
    newton_options o;
    o.typical = 1e-10;
    o.reference = 0.5;
    newton_monitor rest(o);
    EXPECT_FALSE(rest.converged(1e-16, 1e-10));
    EXPECT_TRUE(rest.converged(3e-17, 1e-10));
    newton_monitor above(o);
    EXPECT_FALSE(above.converged(1e-15, 1e-10));
    EXPECT_FALSE(above.converged(3e-16, 1e-10));
    newton_monitor chord(o); // a chord update (Newton's kept Jacobian) is Newton's too
    EXPECT_FALSE(chord.converged(1e-16, 1e-10));
    EXPECT_TRUE(chord.converged(3e-17, 1e-10, true));
    newton_monitor linear(o, true);
    EXPECT_FALSE(linear.converged(1e-16, 1e-10));
    EXPECT_FALSE(linear.converged(3e-17, 1e-10));
}

// The chord decisions of the general engine's Newton loops (chord_policy), by their rule: keep
// the Jacobian once an update is below chord_start of the unknown, take a chord update only
// where it shrank at least 1/min(contraction_limit, 1/8) times, call an update below 1024 ε of
// the unknown noise, and linearise the momentum where ρ |δ| ≤ ε |X|.
TEST(ChordPolicy, KeepsTheJacobianOnceSmallAndWhileItContracts) {
    newton_options o; // chord_start 1e-3, contraction_limit 1/8
    o.typical = 1.0;
    o.reference = 1.0;
    chord_policy p(o);
    EXPECT_FALSE(p.chord()); // the first iterate builds its Jacobian
    p.taken(1e-2, 1.0);
    EXPECT_FALSE(p.chord()); // 1e-2 of the unknown: not yet
    p.taken(1e-4, 1.0);
    ASSERT_TRUE(p.chord());
    EXPECT_TRUE(p.contracts(1.2e-5));  // 0.12 of the last update
    EXPECT_FALSE(p.contracts(1.3e-5)); // 0.13: too slow for a chord
    EXPECT_TRUE(p.at_noise(2e-13));    // below 1024 ε ≈ 2.3e-13
    EXPECT_FALSE(p.at_noise(3e-13));
    p.drop();
    EXPECT_FALSE(p.chord());
    p.taken(1e-8, 1.0);
    EXPECT_FALSE(p.chord()); // dropped for the rest of the solve
    o.chord_start = 0.0;     // never
    chord_policy never(o);
    never.taken(1e-12, 1.0);
    EXPECT_FALSE(never.chord());
}

TEST(ChordPolicy, AStaleJacobiansFirstUpdateIsGatedAndTheNextMustContract) {
    // keep_stale: a Jacobian factorised at another point (an earlier step's) before the solve.
    // The first iterate is a chord update, taken where it is below chord_start (1e-3) of the
    // unknown (no earlier update to compare it with), and not linearised (how far the Jacobian
    // is off is not known); the next must shrink 8-fold.
    newton_options o;
    o.typical = 1.0;
    o.reference = 1.0;
    chord_policy p(o);
    p.keep_stale(1.0);
    ASSERT_TRUE(p.chord());
    EXPECT_TRUE(p.contracts(0.9e-3));
    EXPECT_FALSE(p.contracts(1.1e-3));        // the caller drops the chord: Newton's from here
    EXPECT_FALSE(p.linearisable(1e-12, 1.0)); // a fresh Jacobian's rule would pass it (1e-24)
    p.taken(1e-4, 1.0);
    EXPECT_TRUE(p.chord());
    EXPECT_TRUE(p.contracts(1.2e-5));
    EXPECT_FALSE(p.contracts(1.3e-5));       // 0.13 of the last
    EXPECT_TRUE(p.linearisable(1e-12, 1.0)); // ρ = 1e-8 once a rate is known: 1e-20
    o.chord_start = 0.0;                     // chord updates off: nothing is kept
    chord_policy never(o);
    never.keep_stale(1.0);
    EXPECT_FALSE(never.chord());
}

TEST(ChordPolicy, LinearisesTheMomentumWithTheRateOfTheJacobianUsed) {
    newton_options o;
    o.typical = 1.0;
    chord_policy p(o);
    // A fresh Jacobian: ρ = |δ|/|X|, so |δ|²/|X| against ε.
    EXPECT_TRUE(p.linearisable(1e-9, 1.0));  // 1e-18
    EXPECT_FALSE(p.linearisable(1e-7, 1.0)); // 1e-14
    p.taken(1e-4, 1.0);
    ASSERT_TRUE(p.chord());
    // A kept one: ρ = |δ_k|/|δ_{k−1}| = 1e-5, ρ |δ| = 1e-14 > ε, where the fresh rule would pass.
    EXPECT_FALSE(p.linearisable(1e-9, 1.0));
    EXPECT_TRUE(p.linearisable(1e-11, 1.0)); // ρ = 1e-7: 1e-18
}
