// tests/models/test_spring_pendulum.cpp: the model spring-pendulum (models/src/spring_pendulum.cpp)
// against exact and linearized solutions. With θ ≡ 0 the radial motion is exactly harmonic:
// L = m ṙ²/2 − k (r − l0)²/2 + m g r, so r(t) = r_eq + ε cos(ω_r t), r_eq = l0 + m g/k,
// ω_r = √(k/m), at any ε. A small swing from r_eq has ω_θ = √(g/r_eq) to O(θ0²).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "varsym/models/model.hpp"

namespace {

using namespace varsym;

struct spring_run {
    std::unique_ptr<models::simulation> sim;
    double r_eq = 0.0;
};

/// The default spring pendulum (m = 1 kg, k = 40 N/m, l0 = 1 m, g = 9.81) from (r, θ) at rest,
/// Simpson's scheme at step h.
spring_run spring_start(double r_offset, double theta, double h) {
    const models::model& m = models::get("spring-pendulum");
    const auto values = m.defaults();
    spring_run run;
    run.r_eq = 1.0 + 9.81 / 40.0;
    const models::problem pr = m.prepare(values, {{run.r_eq + r_offset, theta}, {}, {0.0, 0.0}});
    run.sim = pr.simulate({scheme_spec(scheme_kind::simpson), {}, h});
    return run;
}

TEST(SpringPendulum, RadialMotionIsTheExactHarmonicOne) {
    const double eps = 0.1, h = 1e-3, omega_r = std::sqrt(40.0);
    auto run = spring_start(eps, 0.0, h);
    run.sim->advance(2000); // t = 2 s, about 2 radial periods
    const double exact = run.r_eq + eps * std::cos(omega_r * 2.0);
    // Simpson's nonlinear scheme is of order 4: at h ω_r = 0.0063 the phase error over 2 s is
    // about (h ω)^4 ω t / 180 ~ 1e-10, times ε.
    EXPECT_NEAR(run.sim->q()[0], exact, 1e-8);
    EXPECT_EQ(run.sim->q()[1], 0.0); // θ stays exactly 0 (∂L/∂θ = 0 there)
}

TEST(SpringPendulum, SmallSwingHasTheLinearizedFrequency) {
    const double theta0 = 1e-3, h = 1e-3;
    auto run = spring_start(0.0, theta0, h);
    const double omega = std::sqrt(9.81 / run.r_eq);
    // The first zero of θ after t = 0: a quarter period of the linearized swing.
    double previous = theta0, t_zero = 0.0;
    while (run.sim->advance(run.sim->step() + 1) && run.sim->time() < 2.0) {
        const double theta = run.sim->q()[1];
        if (theta <= 0.0) { // linear interpolation between the two steps
            t_zero = run.sim->time() - h * theta / (theta - previous);
            break;
        }
        previous = theta;
    }
    const double quarter = std::numbers::pi / (2.0 * omega);
    // The nonlinear corrections are O(θ0²) = 1e-6 relative; the interpolation's O(h²) error
    // at the zero crossing is below 1e-7 s.
    EXPECT_NEAR(t_zero, quarter, 1e-5 * quarter);
    // Negative control: the swing of a rigid pendulum of the unstretched length l0 differs by
    // ~10 %; the check above separates the two.
    EXPECT_GT(std::abs(t_zero - std::numbers::pi / (2.0 * std::sqrt(9.81))), 1e-2 * quarter);
}

TEST(SpringPendulum, EnergyStaysBoundedAtTheDefaultStart) {
    const models::model& m = models::get("spring-pendulum");
    const auto sim =
        m.prepare(m.defaults()).simulate({scheme_spec(scheme_kind::simpson), {}, 5e-3});
    const double e0 = sim->watched_energy();
    double worst = 0.0;
    for (int k = 1; k <= 40; ++k) { // 200 s, 40 000 steps: chaotic exchange, bounded error
        sim->advance(static_cast<std::size_t>(k) * 1000);
        worst = std::max(worst, std::abs(sim->watched_energy() - e0));
    }
    EXPECT_LT(worst, 1e-4 * std::abs(e0));
    EXPECT_GT(worst, 0.0); // the check reads real values: not exactly constant at this h
}

} // namespace
