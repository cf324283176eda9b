// tests/numeric/test_energy.cpp: the energy error of both schemes stays bounded with no drift
// over 10⁴ periods; Newmark's energy is not constant on the nonlinear pendulum (paper §3) but
// is on the linear oscillator (the paper's remark on the linear scheme).
#include <gtest/gtest.h>

#include <numbers>

#include "test_support.hpp"
#include "varsym/integrate.hpp"
#include "varsym/problems/pendulum.hpp"
#include "varsym/schemes/scheme_kind.hpp"

using namespace varsym;
using std::numbers::pi;

namespace {

struct windows {
    double first = 0, last = 0; // max relative energy error over the first and last 100 periods
};

windows energy_windows(scheme_kind k, int steps_per_period, int periods) {
    const pendulum::exact_solution exact(1.0, 2 * pi, pi / 2, 0.0);
    const auto sys = pendulum::make_system(1.0, 2 * pi);
    const double h = exact.period() / steps_per_period;
    const auto n = static_cast<std::size_t>(steps_per_period) * periods;
    const std::size_t window = static_cast<std::size_t>(steps_per_period) * 100;
    phase_state<1> x{vec<1>{pi / 2}, vec<1>{0.0}};
    const double h0 = sys.energy(x);
    windows w;
    with_stepper(k, sys, h, {}, [&](auto& s) {
        integrate(s, x, 0.0, n, [&](std::size_t j, double, const phase_state<1>& y) {
            const double err = std::abs(sys.energy(y) - h0) / h0;
            if (j <= window) w.first = std::max(w.first, err);
            if (j >= n - window) w.last = std::max(w.last, err);
        });
    });
    return w;
}

} // namespace

TEST(Energy, BoundedWithoutDriftOverTenThousandPeriods) {
    // A symplectic scheme's energy error oscillates within a band set by h (backward error
    // analysis); a drift would make the last window's maximum exceed the first's. Over 5·10⁵
    // steps round-off adds at most ~1e-13, far below either band; the windows' maxima must
    // agree within 2 %.
    for (auto k : paper_schemes) {
        const auto w = energy_windows(k, 50, 10000);
        EXPECT_NEAR(w.last, w.first, 0.02 * w.first) << scheme_name(k);
        // Table 1's one-period values (9.06e-4, 1.30e-6) bound the band.
        EXPECT_LT(w.first, k == scheme_kind::newmark ? 1e-3 : 1.5e-6) << scheme_name(k);
    }
}

TEST(Energy, NewmarkEnergyIsNotConstantOnThePendulum) {
    // Paper §3: "although the Newmark scheme is symplectic, it does not preserve the energy".
    const auto w = energy_windows(scheme_kind::newmark, 50, 100);
    EXPECT_GT(w.first, 1e-4);
}

TEST(Energy, NewmarkConservesTheLinearOscillatorsEnergy) {
    // For V = kq²/2 the Newmark scheme is the implicit midpoint rule, which conserves the
    // quadratic energy exactly: only round-off (≤ 1e-13 over 10⁴ steps) remains.
    const separable_system<1, test::harmonic> sys(mat<1>{2.0}, test::harmonic{});
    newmark::stepper s(sys, 0.3);
    phase_state<1> x{vec<1>{1.0}, vec<1>{0.5}};
    const double h0 = sys.energy(x);
    double worst = 0;
    integrate(s, x, 0.0, 10000, [&](std::size_t, double, const phase_state<1>& y) {
        worst = std::max(worst, std::abs(sys.energy(y) - h0) / h0);
    });
    EXPECT_LT(worst, 1e-13);
}
