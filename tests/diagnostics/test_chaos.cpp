// Chaos indicators (diagnostics/chaos.hpp) along runs whose character is known: regular motions
// whose deviations grow linearly (Kepler, the integrable Lagrange top, a torus of Hénon–Heiles at
// E = 1/12), for which the mean MEGNO tends to 2 and λ to 0 like ln t / t (Cincotta and Simó
// 2000); an isochronous oscillator, whose deviations stay bounded, for which ⟨Y⟩ → 0; and chaotic
// motions (Hénon–Heiles at E = 1/6, the double pendulum released with both links horizontal),
// for which ⟨Y⟩ grows like λ t / 2. Bounds: the measured values (in comments) with the margin
// that a change of step size or scheme within reason keeps.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "varsym/diagnostics/chaos.hpp"
#include "varsym/problems/double_pendulum.hpp"
#include "varsym/problems/heavy_top.hpp"
#include "varsym/problems/henon_heiles.hpp"
#include "varsym/problems/kepler.hpp"
#include "varsym/problems/oscillator.hpp"
#include "varsym/schemes/simpson.hpp"
#include "varsym/schemes/variational.hpp"
#include "varsym/schemes/variational_sensitivity.hpp"

namespace varsym {
namespace {

/// The indicators after n steps of s from x, with ⟨Y⟩ also recorded at half the run.
struct indicators {
    double mean_megno, half_mean_megno, lyapunov, time;
};

template <class S, class X>
indicators run(S& s, X x, long n) {
    chaos_indicators c(static_cast<int>(x.q.size()), s.step_size());
    Eigen::MatrixXd j;
    double half = 0.0;
    for (long k = 1; k <= n; ++k) {
        EXPECT_TRUE(step_with_tangent(s, x, c, j).converged) << "step " << k;
        if (k == n / 2) half = c.mean_megno();
    }
    EXPECT_TRUE(c.ok());
    return {c.mean_megno(), half, c.lyapunov(), c.time()};
}

TEST(chaos, kepler_orbit_is_regular) {
    const kepler::orbit o(0.5, 1.0);
    simpson::stepper s(kepler::make_system(), o.period() / 400);
    const auto r = run(s, o.at(0.0L), 400L * 300); // 300 periods, t ≈ 1885
    EXPECT_NEAR(r.mean_megno, 2.0, 0.1);           // measured 1.9965
    EXPECT_LT(r.lyapunov, 0.01);                   // 0.0059 ≈ ln(t)/t · 1.5
}

TEST(chaos, integrable_heavy_top_is_regular) {
    const heavy_top::lagrangian top{1.0, 0.5, 1.0};
    general::stepper s(heavy_top::make_system(top), 0.02, scheme_kind::simpson);
    const vec<3> q(0.5, 0.0, 0.0), v(0.0, 0.3, 5.0);
    const phase_state<3> x{q, lagrangian_system<heavy_top::lagrangian>(top).momentum(q, v)};
    const auto r = run(s, x, 100000);    // t = 2000
    EXPECT_NEAR(r.mean_megno, 2.0, 0.1); // measured 1.980
    EXPECT_LT(r.lyapunov, 0.01);         // 0.0037
}

TEST(chaos, henon_heiles_torus_is_regular) {
    simpson::stepper s(henon_heiles::make_system(), 0.05);
    const auto r = run(s, henon_heiles::on_section(1.0 / 12.0, 0.1, 0.0), 40000); // t = 2000
    EXPECT_NEAR(r.mean_megno, 2.0, 0.1);                                          // measured 1.968
    EXPECT_LT(r.lyapunov, 0.01);                                                  // 0.0026
}

/// The isochronous oscillator: every orbit has the same period, so deviations do not grow at all
/// (no shear): Σ_k k ln a_k stays bounded, Y = (2/n) Σ_k k ln a_k → 0 and so does ⟨Y⟩, rather
/// than 2 (the value for a torus whose frequencies change with the action).
TEST(chaos, isochronous_oscillator_has_zero_megno) {
    const Eigen::MatrixXd one = Eigen::MatrixXd::Identity(1, 1);
    simpson::stepper s(oscillator::make_system(one, 4.0 * one), 0.05);
    phase_state<dynamic> x;
    x.q = Eigen::VectorXd::Ones(1);
    x.p = Eigen::VectorXd::Zero(1);
    const auto r = run(s, x, 40000);
    EXPECT_LT(std::abs(r.mean_megno), 0.05);
    EXPECT_LT(std::abs(r.lyapunov), 1e-3);
}

TEST(chaos, henon_heiles_at_escape_energy_is_chaotic) {
    simpson::stepper s(henon_heiles::make_system(), 0.05);
    const auto r = run(s, henon_heiles::on_section(1.0 / 6.0, -0.1, 0.0), 40000); // t = 2000
    // measured ⟨Y⟩ = 136 (59 at t = 1000), λ = 0.135
    EXPECT_GT(r.lyapunov, 0.05);
    EXPECT_GT(r.mean_megno, 50.0);
    const double ratio = r.mean_megno / r.half_mean_megno; // linear growth: about 2
    EXPECT_GT(ratio, 1.5);
    EXPECT_LT(ratio, 2.8);
    EXPECT_NEAR(r.mean_megno / (0.5 * r.lyapunov * r.time), 1.0, 0.25); // ⟨Y⟩ ≈ λ t / 2
}

TEST(chaos, double_pendulum_from_horizontal_links_is_chaotic) {
    general::stepper s(double_pendulum::make_system({}), 0.002, scheme_kind::simpson);
    phase_state<2> x;
    x.q << std::numbers::pi / 2, std::numbers::pi / 2;
    x.p.setZero();
    const auto r = run(s, x, 20000); // t = 40 s; measured ⟨Y⟩ = 14.9, λ = 0.74 /s
    EXPECT_GT(r.lyapunov, 0.3);
    EXPECT_GT(r.mean_megno, 8.0);
    EXPECT_NEAR(r.mean_megno / (0.5 * r.lyapunov * r.time), 1.0, 0.3);
}

TEST(chaos, refuses_zero_deviation_and_stops_at_a_non_finite_map) {
    EXPECT_THROW(chaos_indicators(Eigen::VectorXd::Zero(4), 0.1), std::invalid_argument);
    EXPECT_THROW(chaos_indicators(2, 0.0), std::invalid_argument);
    chaos_indicators c(1, 0.1);
    EXPECT_TRUE(c.advance(2.0 * Eigen::MatrixXd::Identity(2, 2)));
    EXPECT_NEAR(c.lyapunov(), std::log(2.0) / 0.1, 1e-12); // one step growing by 2
    EXPECT_NEAR(c.megno(), 2.0 * std::log(2.0), 1e-12);
    Eigen::MatrixXd bad = Eigen::MatrixXd::Identity(2, 2);
    bad(0, 0) = std::nan("");
    EXPECT_FALSE(c.advance(bad));
    EXPECT_FALSE(c.ok());
    EXPECT_EQ(c.steps(), 1);
    EXPECT_FALSE(c.advance(Eigen::MatrixXd::Identity(2, 2))); // stays stopped
}

} // namespace
} // namespace varsym
