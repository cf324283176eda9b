// tests/schemes/test_resume.cpp: what checkpoints and the exit-3 advice rest on. A stepper
// rebuilt from (q, p, carries) continues bit for bit; the linear stability limits computed from
// the steppers match closed forms; the highest frequency at a state matches its definition.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "test_support.hpp"
#include "varsym/diagnostics/stability.hpp"
#include "varsym/integrate.hpp"
#include "varsym/problems/chain.hpp"
#include "varsym/problems/pendulum.hpp"
#include "varsym/run/state.hpp"
#include "varsym/schemes/galerkin.hpp"
#include "varsym/schemes/newmark.hpp"
#include "varsym/schemes/simpson.hpp"
#include "varsym/schemes/variational.hpp"

using namespace varsym;

namespace {

const auto resume_pendulum = pendulum::make_system(1.0, 2 * std::numbers::pi);
const phase_state<1> start{vec<1>{std::numbers::pi / 2}, vec<1>{0.0}};

/// Runs n steps straight, and k steps, then a fresh stepper restored from the saved run_state
/// (x, carries, step, statistics) for the remaining n − k: the two final states must be the
/// same bits.
template <class Make>
void expect_bitwise_resume(Make make, std::size_t n, std::size_t k) {
    auto quiet = [](const auto&) {};
    auto straight = make();
    auto a = run_state<1>::start(start);
    EXPECT_TRUE(integrate_from(straight, a, n, quiet));

    auto first = make();
    auto b = run_state<1>::start(start);
    integrate_from(first, b, k, quiet);
    const run_state<1> saved = b; // what a checkpoint keeps
    auto second = make();         // as a resumed process would build it
    auto c = saved;
    restore(second, c);
    integrate_from(second, c, n, quiet);

    EXPECT_EQ(saved.step, k);
    EXPECT_EQ(a.x.q(0), c.x.q(0));
    EXPECT_EQ(a.x.p(0), c.x.p(0));
    EXPECT_EQ(a.carry_q(0), c.carry_q(0));
    EXPECT_EQ(a.carry_p(0), c.carry_p(0));
    EXPECT_EQ(a.stats.steps, c.stats.steps);
    EXPECT_EQ(a.stats.newton_iterations, c.stats.newton_iterations);
}

/// The unit harmonic oscillator's step for `Stepper` (m = 1, V = q²/2, ω = 1) at h = z.
template <class Make>
auto oscillator_step(Make make) {
    return [make](double z, phase_state<1>& x) {
        auto s = make(separable_system<1, test::harmonic>(mat<1>{1.0}, test::harmonic{1.0}), z);
        return s.step(x).converged;
    };
}

} // namespace

TEST(Resume, EveryStepperContinuesBitForBit) {
    // 500 steps of h = 0.02 (about 8.5 periods), interrupted at an arbitrary step.
    const double h = 0.02;
    expect_bitwise_resume([&] { return simpson::stepper(resume_pendulum, h); }, 500, 187);
    expect_bitwise_resume([&] { return newmark::stepper(resume_pendulum, h); }, 500, 213);
    using galerkin::rule_kind;
    expect_bitwise_resume(
        [&] { return galerkin::stepper(resume_pendulum, h, rule_kind::gauss, 3); }, 500, 251);
    using lag = separable_lagrangian<pendulum::system>;
    expect_bitwise_resume(
        [&] {
            return general::stepper<lag>(lagrangian_system<lag>({resume_pendulum}), h,
                                         scheme_spec(scheme_kind::lobatto, 3));
        },
        500, 99);
}

TEST(Stability, SimpsonLimitsMatchTheClosedForm) {
    // Simpson's step map of q'' = -q has trace 2 - a/3 - (2a/3 - a²/18)/(1 + a/24), a = (hω)²
    // (eq. simpson-hamilton with ∇V = q): |trace| > 2 for a in (8, 12) and a > 24.
    const auto iv = instability_intervals(
        oscillator_step([](auto sys, double h) { return simpson::stepper(sys, h); }), 10.0);
    ASSERT_EQ(iv.size(), 2u);
    EXPECT_NEAR(iv[0].from, 2 * std::sqrt(2.0), 1e-7);
    EXPECT_NEAR(iv[0].to, 2 * std::sqrt(3.0), 1e-7);
    EXPECT_NEAR(iv[1].from, 2 * std::sqrt(6.0), 1e-7);
    EXPECT_TRUE(std::isinf(iv[1].to));
}

TEST(Stability, StormerVerletLimitIsTwoAndGaussHasNone) {
    using galerkin::rule_kind;
    // Lobatto s = 1 (trapezoidal rule) is Störmer–Verlet: stable for hω < 2.
    const double lobatto1 =
        linear_stability_limit(oscillator_step([](auto sys, double h) {
                                   return galerkin::stepper(sys, h, rule_kind::lobatto, 1);
                               }),
                               10.0);
    EXPECT_NEAR(lobatto1, 2.0, 1e-8);
    // Newmark (midpoint rule) and Gauss s = 3: A-stable on linear problems, no limit.
    EXPECT_TRUE(std::isinf(linear_stability_limit(
        oscillator_step([](auto sys, double h) { return newmark::stepper(sys, h); }), 30.0, 0.01)));
    EXPECT_TRUE(std::isinf(linear_stability_limit(oscillator_step([](auto sys, double h) {
                                                      return galerkin::stepper(sys, h,
                                                                               rule_kind::gauss, 3);
                                                  }),
                                                  30.0, 0.01)));
}

TEST(Stability, HighestFrequency) {
    // Pendulum: ∇²V = m ω² cos q, so ω_max = ω √cos q, and 0 at q = π/2 (no restoring force).
    const double w = 2 * std::numbers::pi;
    EXPECT_NEAR(highest_frequency(resume_pendulum, phase_state<1>{vec<1>{0.0}, vec<1>{0.0}}), w,
                1e-12);
    EXPECT_NEAR(highest_frequency(resume_pendulum, phase_state<1>{vec<1>{1.0}, vec<1>{0.0}}),
                w * std::sqrt(std::cos(1.0)), 1e-12);
    EXPECT_NEAR(highest_frequency(resume_pendulum, start), 0.0, 1e-6);
    // The general engine's estimate agrees with the separable one through separable_lagrangian.
    using lag = separable_lagrangian<pendulum::system>;
    const lagrangian_system<lag> ls({resume_pendulum});
    EXPECT_NEAR(highest_frequency(ls, phase_state<1>{vec<1>{0.3}, vec<1>{0.7}}),
                highest_frequency(resume_pendulum, phase_state<1>{vec<1>{0.3}, vec<1>{0.7}}),
                1e-10);
    // The chain's Gershgorin bound is an upper bound of the exact largest eigenvalue, and for
    // the linear chain (β = 0, eigenvalues 2 − 2 cos(kπ/(n+1))) within 2 % at n = 50.
    const chain::system c(50, 0.0, 2.0);
    const phase_state<dynamic> x = c.lowest_mode(0.1);
    const double exact = std::sqrt((2 - 2 * std::cos(50 * std::numbers::pi / 51)) / 2.0);
    const double bound = highest_frequency(c, x);
    EXPECT_GE(bound, exact);
    EXPECT_LT(bound, 1.02 * exact);
}
