// tests/schemes/test_dimensions.cpp: large and run-time dimensions on every path. A planetary
// N-body system at d = 18 (6 bodies; d fixed at compile time, past the former limit of 16) and
// at d = 18 and 60 (20 bodies) known only at run time runs on the separable fast path (Simpson,
// Newmark), the family (run-time degree) and the general engine (derivatives by hand); the
// general engine's automatic derivatives (fixed d) run at d = 18 and 60. A fixed d = 60 on
// every path is not compiled: it cost about 25 s of the suite's build and tested nothing the
// fixed 18 and the run-time 60 do not. At 18 and 60 the first derivatives come from reverse
// mode, and the simplified iteration on them is checked against Newton.
// References: the conservation laws of the continuous system that a variational integrator keeps
// (total momentum, by the discrete Noether theorem, to round-off; angular momentum to the
// Newton tolerance; energy bounded), and the agreement of independent paths that compute the
// same scheme (Simpson = lobatto-2; general engine = family for a separable L).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "compare_steppers.hpp"
#include "nbody.hpp"
#include "test_support.hpp"
#include "varsym/integrate.hpp"
#include "varsym/schemes/galerkin.hpp"
#include "varsym/schemes/newmark.hpp"
#include "varsym/schemes/simpson.hpp"
#include "varsym/schemes/variational.hpp"

using namespace varsym;
using test::planetary_start;

namespace {

constexpr double orbit_h = 0.5; // the innermost orbit (r = 10) has period 2π·10^1.5 ≈ 199

template <int D>
struct case_of {
    planetary_start start;
    separable_system<D, test::gravity<D>> sys;
    phase_state<D> x0;
    explicit case_of(int bodies, Eigen::Vector3d field = Eigen::Vector3d::Zero())
        : start(bodies),
          sys(mat<D>(start.mass_diagonal().asDiagonal()), test::gravity<D>{start.masses, field}),
          x0{vec<D>(start.q), vec<D>(start.p)} {}
};

struct drift {
    double energy = 0, momentum = 0, angular = 0;
};

/// Runs n steps and returns the largest relative energy error, and the largest change of the
/// total and angular momenta over the run.
template <class Stepper, class System, int D>
drift run_and_measure(Stepper&& stepper, const System& sys, phase_state<D> x, std::size_t n) {
    const double e0 = sys.energy(x);
    const Eigen::Vector3d p0 = test::total_momentum(x.p), l0 = test::angular_momentum(x.q, x.p);
    drift d;
    integrate(stepper, x, 0.0, n, [&](std::size_t, double, const phase_state<D>& y) {
        d.energy = std::max(d.energy, std::abs((sys.energy(y) - e0) / e0));
        d.momentum = std::max(d.momentum,
                              (test::total_momentum(y.p) - p0).template lpNorm<Eigen::Infinity>());
        d.angular = std::max(
            d.angular, (test::angular_momentum(y.q, y.p) - l0).template lpNorm<Eigen::Infinity>());
    });
    return d;
}

// Tolerances. |q| ≤ 30, |p_i| ≲ 3e-4 for a planet and the sum of the planets' for the central
// body. The total momentum's forces cancel in pairs up to the round-off of each pair's force
// (≈ 1e-16 × h|∇V| ≈ 1e-21 a step), and the compensated sums keep p to ~1e-20: measured ≤ 1.2e-19
// over 2000 steps, so 1e-17. Angular momentum Σ q × p is conserved to the Newton tolerance
// (ε|q| per step, times |p|) and the round-off of its own evaluation (ε · 30 · 3e-4 ≈ 2e-18):
// measured ≤ 1.1e-17, so 1e-15. Two paths computing the same scheme drift apart by round-off:
// 1e-11 relative to |q| over the short runs here.
constexpr double momentum_tol = 1e-17, angular_tol = 1e-15, gap_tol = 30 * 1e-11;

template <int D>
void every_path(int bodies, std::size_t n) {
    const case_of<D> c(bodies);
    using sys_t = decltype(c.sys);
    const char* names[] = {"simpson", "newmark", "gauss-2", "lobatto-3"};
    const drift drifts[] = {
        run_and_measure(simpson::stepper<sys_t>(c.sys, orbit_h), c.sys, c.x0, n),
        run_and_measure(newmark::stepper<sys_t>(c.sys, orbit_h), c.sys, c.x0, n),
        run_and_measure(galerkin::stepper<sys_t>(c.sys, orbit_h, galerkin::rule_kind::gauss, 2),
                        c.sys, c.x0, n / 4),
        run_and_measure(galerkin::stepper<sys_t>(c.sys, orbit_h, galerkin::rule_kind::lobatto, 3),
                        c.sys, c.x0, n / 4)};
    for (int i = 0; i < 4; ++i) {
        const drift& d = drifts[i];
        std::printf("d = %d%s, %-9s: energy %.2e, momentum %.2e, angular momentum %.2e\n",
                    c.sys.dimension(), D == dynamic ? " (run time)" : "", names[i], d.energy,
                    d.momentum, d.angular);
        EXPECT_LT(d.energy, 1e-5) << "d = " << c.sys.dimension();
        EXPECT_LE(d.momentum, momentum_tol);
        EXPECT_LE(d.angular, angular_tol);
    }
    // Simpson by the reduced d × d solve and as lobatto-2 by the family's 2d × 2d solve.
    EXPECT_LE(test::max_difference(
                  simpson::stepper<sys_t>(c.sys, orbit_h),
                  galerkin::stepper<sys_t>(c.sys, orbit_h, galerkin::rule_kind::lobatto, 2), c.x0,
                  static_cast<int>(n / 4)),
              gap_tol);
    // The general engine with the system's derivatives by hand against the family.
    using lag = separable_lagrangian<sys_t>;
    EXPECT_LE(test::max_difference(
                  general::stepper<lag>(lagrangian_system<lag>({c.sys}), orbit_h,
                                        {scheme_kind::gauss, 3}),
                  galerkin::stepper<sys_t>(c.sys, orbit_h, galerkin::rule_kind::gauss, 3), c.x0,
                  static_cast<int>(n / 10)),
              gap_tol);
}

/// The general engine with automatic derivatives (fixed d) against the same Lagrangian's
/// derivatives by hand.
template <int D>
void automatic_derivatives(int bodies, int n) {
    const case_of<D> c(bodies);
    using lag = separable_lagrangian<decltype(c.sys)>;
    using ad_lag = test::gravity_lagrangian<D>;
    lagrangian_terms<D> by_hand, by_ad;
    const vec<D> v = c.start.mass_diagonal().cwiseInverse().cwiseProduct(c.start.p);
    evaluate(lag{c.sys}, c.x0.q, v, by_hand);
    evaluate(ad_lag{c.start.masses}, c.x0.q, v, by_ad);
    EXPECT_NEAR(by_ad.value, by_hand.value, 1e-15);
    EXPECT_LE((by_ad.lq - by_hand.lq).template lpNorm<Eigen::Infinity>(), 1e-17);
    EXPECT_LE((by_ad.lqq - by_hand.lqq).template lpNorm<Eigen::Infinity>(), 1e-17);
    EXPECT_LE((by_ad.lvv - by_hand.lvv).template lpNorm<Eigen::Infinity>(), 1e-18);
    EXPECT_EQ(by_ad.lqv.template lpNorm<Eigen::Infinity>(), 0.0);
    // First derivatives alone (reverse mode above d = 8): the same, to a few ulps.
    lagrangian_terms<D> first;
    evaluate_gradient(ad_lag{c.start.masses}, c.x0.q, v, first);
    ASSERT_GT(by_hand.lq.template lpNorm<Eigen::Infinity>(), 1e-6); // not vacuous
    EXPECT_LE((first.lq - by_hand.lq).template lpNorm<Eigen::Infinity>(), 1e-17);
    EXPECT_LE((first.lv - by_hand.lv).template lpNorm<Eigen::Infinity>(), 1e-18);
    EXPECT_NEAR(first.value, by_hand.value, 1e-15);
    EXPECT_LE(
        test::max_difference(
            general::stepper<ad_lag>(lagrangian_system<ad_lag>({c.start.masses}), orbit_h,
                                     scheme_kind::simpson),
            general::stepper<lag>(lagrangian_system<lag>({c.sys}), orbit_h, scheme_kind::simpson),
            c.x0, n),
        gap_tol);
    // The simplified iteration on AD gradients against Newton on the hand derivatives.
    newton_options simplified;
    simplified.iteration = iteration_kind::simplified;
    EXPECT_LE(
        test::max_difference(
            general::stepper<ad_lag>(lagrangian_system<ad_lag>({c.start.masses}), orbit_h,
                                     scheme_kind::simpson, simplified),
            general::stepper<lag>(lagrangian_system<lag>({c.sys}), orbit_h, scheme_kind::simpson),
            c.x0, 5 * n),
        gap_tol);
}

} // namespace

TEST(Dimensions, EighteenFixedOnEveryPath) {
    every_path<18>(6, test::sanitized ? 200 : 2000);
}
TEST(Dimensions, RunTimeDimensionOnEveryPath) {
    every_path<dynamic>(6, test::sanitized ? 200 : 2000);
    every_path<dynamic>(20, test::sanitized ? 40 : 200);
}
TEST(Dimensions, AutomaticDerivativesAtEighteen) {
    automatic_derivatives<18>(6, test::sanitized ? 2 : 20);
}
TEST(Dimensions, AutomaticDerivativesAtSixty) {
    automatic_derivatives<60>(20, test::sanitized ? 1 : 2);
}

TEST(Dimensions, MomentumCheckCanFail) {
    // Negative control: a uniform external field (force −m_i g on each body) changes the total
    // momentum by −n h (Σ m_i) g, far above momentum_tol.
    const case_of<18> c(6, Eigen::Vector3d(1e-6, 0.0, 0.0));
    const drift d =
        run_and_measure(simpson::stepper<decltype(c.sys)>(c.sys, orbit_h), c.sys, c.x0, 100);
    double total_mass = 0;
    for (double m : c.start.masses)
        total_mass += m;
    EXPECT_NEAR(d.momentum, 100 * orbit_h * total_mass * 1e-6, 1e-12);
    EXPECT_GT(d.momentum, 1e6 * momentum_tol); // and far above what the test allows
}
