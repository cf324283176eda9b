// tests/problems/test_pendulum_exact.cpp: the exact pendulum solution against evaluations that
// do not use Jacobi functions: the energy identity, the ODE by finite differences, the period
// by quadrature of its integral, and A&S tables.
#include <gtest/gtest.h>

#include <boost/math/quadrature/gauss_kronrod.hpp>

#include "varsym/problems/pendulum.hpp"

using std::numbers::pi;
using varsym::pendulum::exact_solution;
using varsym::pendulum::regime;

namespace {

struct case_t {
    double m, omega, q0, p0;
};

// Libration (paper's case, a generic one, one near the separatrix, one shifted by 2π·3),
// rotation both ways, all with distinct m and ω.
const case_t cases[] = {
    {1.0, 2 * pi, pi / 2, 0.0},          {2.5, 1.3, 0.3, -2.0}, {0.7, 3.0, 3.0, 0.1},
    {1.0, 2 * pi, pi / 2 + 6 * pi, 1.0}, {1.5, 2.0, 0.5, 7.0},  {1.5, 2.0, -1.0, -9.0},
};

double max_abs_derivative_scale(const case_t& c, const exact_solution& e) {
    // |dq/dt| ≤ 2ωk (and |dp/dt| ≤ mω²): a scale for the residuals.
    return 2.0 * c.omega * std::max(1.0, e.modulus()) * std::max(1.0, c.m * c.omega);
}

} // namespace

TEST(PendulumExact, PaperPeriodMatchesTabulatedK) {
    // K(m = 1/2) = 1.8540746773013719 (Abramowitz & Stegun, Table 17.1); T = 4K/ω with ω = 2π.
    const exact_solution e(1.0, 2 * pi, pi / 2, 0.0);
    EXPECT_EQ(e.kind(), regime::libration);
    EXPECT_NEAR(e.modulus(), std::sqrt(0.5), 1e-15);
    EXPECT_NEAR(e.period(), 4 * 1.8540746773013719 / (2 * pi), 1e-15);
}

TEST(PendulumExact, EnergyIdentityHolds) {
    // H(q(t), p(t)) = p²/(2m) + mω²(1 − cos q) must equal H(q₀, p₀) at every t.
    for (const auto& c : cases) {
        const exact_solution e(c.m, c.omega, c.q0, c.p0);
        const auto sys = varsym::pendulum::make_system(c.m, c.omega);
        const double h0 = sys.energy({varsym::vec<1>{c.q0}, varsym::vec<1>{c.p0}});
        EXPECT_NEAR(e.energy(), h0, 1e-13 * h0);
        for (int i = 0; i <= 400; ++i) {
            const double t = e.period() * 3.7 * i / 400.0;
            EXPECT_NEAR(sys.energy(e.at(t)), h0, 1e-12 * h0) << "t = " << t;
        }
    }
}

TEST(PendulumExact, SatisfiesHamiltonsEquationsByFiniteDifferences) {
    // dq/dt = p/m and dp/dt = −mω² sin q, derivatives by the 8th-order central difference
    // (coefficients 4/5, −1/5, 4/105, −1/280). With δ = 0.01/(ωk) the truncation error is
    // ~δ⁸|f⁽⁹⁾|/630 ≈ 1e-19 of the scale and round-off ~2ε|f|/δ ≈ 1e-13 of it: tolerance 1e-12.
    const double w[] = {4.0 / 5, -1.0 / 5, 4.0 / 105, -1.0 / 280};
    for (const auto& c : cases) {
        const exact_solution e(c.m, c.omega, c.q0, c.p0);
        const double delta = 0.01 / (c.omega * std::max(1.0, e.modulus()));
        const double scale = max_abs_derivative_scale(c, e);
        for (int i = 0; i <= 97; ++i) {
            const double t = e.period() * 2.0 * i / 97.0 + 0.1;
            double dq = 0, dp = 0;
            for (int k = 1; k <= 4; ++k) {
                const auto plus = e.at(t + k * delta), minus = e.at(t - k * delta);
                dq += w[k - 1] * (plus.q(0) - minus.q(0)) / delta;
                dp += w[k - 1] * (plus.p(0) - minus.p(0)) / delta;
            }
            const auto x = e.at(t);
            EXPECT_NEAR(dq, x.p(0) / c.m, 1e-12 * scale) << "t = " << t;
            EXPECT_NEAR(dp, -c.m * c.omega * c.omega * std::sin(x.q(0)), 1e-12 * scale)
                << "t = " << t;
        }
    }
}

TEST(PendulumExact, PeriodMatchesQuadratureOfThePeriodIntegral) {
    // Libration: T = (4/ω) ∫₀^{π/2} dφ / sqrt(1 − k² sin²φ)  (paper eq. periode);
    // rotation: T = ∫₀^{2π} m dq / sqrt(2m(E − V(q))). Both by 61-point Gauss–Kronrod
    // quadrature (smooth integrands), independent of Boost's Carlson-based ellint_1.
    using boost::math::quadrature::gauss_kronrod;
    for (const auto& c : cases) {
        const exact_solution e(c.m, c.omega, c.q0, c.p0);
        double t_quad = 0;
        if (e.kind() == regime::libration) {
            const double k2 = e.modulus() * e.modulus();
            t_quad = 4.0 / c.omega *
                     gauss_kronrod<double, 61>::integrate(
                         [&](double phi) {
                             return 1.0 / std::sqrt(1.0 - k2 * std::sin(phi) * std::sin(phi));
                         },
                         0.0, pi / 2, 15, 1e-15);
        } else {
            const double energy = e.energy();
            t_quad = gauss_kronrod<double, 61>::integrate(
                [&](double q) {
                    const double v = c.m * c.omega * c.omega * (1 - std::cos(q));
                    return c.m / std::sqrt(2.0 * c.m * (energy - v));
                },
                0.0, 2 * pi, 15, 1e-15);
        }
        EXPECT_NEAR(e.period(), t_quad, 1e-12 * t_quad) << "q0 = " << c.q0 << ", p0 = " << c.p0;
        // After one period the state returns (a revolution further in rotation).
        const auto back = e.at(e.period());
        const double turn = e.kind() == regime::rotation ? (c.p0 > 0 ? 2 * pi : -2 * pi) : 0.0;
        EXPECT_NEAR(back.q(0), c.q0 + turn, 1e-12 * std::max(1.0, std::abs(c.q0)));
        EXPECT_NEAR(back.p(0), c.p0, 1e-12 * max_abs_derivative_scale(c, e));
    }
}

TEST(PendulumExact, TurningPointsAreExact) {
    // Regression: Boost 1.74's jacobi_elliptic returns dn(K | 1/2) = 0.70772 (not 1/√2); the
    // solution must not use it. At t = T/2 the paper's pendulum is at q = −π/2, p = 0.
    const exact_solution e(1.0, 2 * pi, pi / 2, 0.0);
    EXPECT_NEAR(e.at(e.period() / 2).q(0), -pi / 2, 1e-14);
    EXPECT_NEAR(e.at(e.period() / 2).p(0), 0.0, 1e-13);
    EXPECT_NEAR(e.at(e.period()).q(0), pi / 2, 1e-14);
    EXPECT_NEAR(e.at(0.0).q(0), pi / 2, 1e-15);
}

TEST(PendulumExact, RestStaysAtRest) {
    const exact_solution e(1.0, 2.0, 0.0, 0.0);
    EXPECT_EQ(e.kind(), regime::rest);
    EXPECT_EQ(e.at(12.3).q(0), 0.0);
    EXPECT_EQ(e.at(12.3).p(0), 0.0);
    EXPECT_NEAR(e.period(), pi, 1e-15);
}

TEST(PendulumExact, SeparatrixAndBadInputAreRefused) {
    EXPECT_THROW(exact_solution(1.0, 2.0, pi, 0.0), std::invalid_argument);   // upright
    EXPECT_THROW(exact_solution(1.0, 2.0, 0.0, 4.0), std::invalid_argument);  // p0 = 2mω
    EXPECT_THROW(exact_solution(0.0, 2.0, 0.1, 0.0), std::invalid_argument);  // m = 0
    EXPECT_THROW(exact_solution(1.0, -1.0, 0.1, 0.0), std::invalid_argument); // ω < 0
    EXPECT_THROW(exact_solution(1.0, 2.0, std::nan(""), 0.0), std::invalid_argument);
    try {
        exact_solution(1.0, 2.0, pi, 0.0);
    } catch (const std::invalid_argument& err) {
        EXPECT_NE(std::string(err.what()).find("separatrix"), std::string::npos);
    }
}
