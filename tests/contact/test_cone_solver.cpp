// The interior-point solve of one step's linearised contact problem (contact/cone_solver.hpp)
// against the closed form of a decoupled contact: with A = diag(a_n, a_t, a_t),
//   γ = max(0, −φ₀/a_n);  b = −d₀/a_t if |d₀| ≤ μ γ a_t (sticking), else −μγ d₀/|d₀| (sliding).
#include <cmath>

#include <gtest/gtest.h>

#include "varsym/contact/cone_solver.hpp"

namespace {

using varsym::contact::cone_problem;
using varsym::contact::solve_cone;

struct decoupled {
    double phi0, d1, d2, an, at, mu;
    Eigen::Vector3d exact() const {
        const double gamma = std::max(0.0, -phi0 / an);
        const Eigen::Vector2d d(d1, d2);
        const Eigen::Vector2d b = d.norm() <= mu * gamma * at
                                      ? Eigen::Vector2d(-d / at)
                                      : Eigen::Vector2d(-mu * gamma * d / d.norm());
        return {gamma, b(0), b(1)};
    }
    cone_problem problem() const {
        cone_problem p;
        p.c = Eigen::Vector3d(phi0, d1, d2);
        p.a = Eigen::Vector3d(an, at, at).asDiagonal();
        p.mu = Eigen::VectorXd::Constant(1, mu);
        return p;
    }
};

TEST(ConeSolver, MatchesTheDecoupledContactsClosedForm) {
    // Units of a 1 kg body at h = 1 ms: a ~ h²/m [m/(N s)] ~ 1e-3 s/kg · h; gaps ~ g h².
    for (const decoupled c : {decoupled{-5e-6, 1e-7, -5e-8, 1e-3, 2e-3, 0.5},   // sticks
                              decoupled{-5e-6, 3e-5, -1.5e-5, 1e-3, 2e-3, 0.5}, // slides
                              decoupled{-5e-6, 1e-4, 0.0, 1e-3, 1e-3, 0.0},     // frictionless
                              decoupled{2e-6, 1e-4, -5e-5, 1e-3, 2e-3, 0.5}}) { // separates
        const auto r = solve_cone(c.problem());
        ASSERT_TRUE(r.converged) << c.phi0 << " " << c.d1;
        const Eigen::Vector3d want = c.exact();
        // The tolerance 1e-13 m on gaps and slips bounds the impulses' error by 1e-13 / a
        // (1e-10 N s) plus the central path's κ/s of an inactive contact.
        EXPECT_NEAR(r.lambda(0), want(0), 2e-9) << c.phi0 << " " << c.d1;
        EXPECT_NEAR(r.lambda(1), want(1), 2e-9) << c.phi0 << " " << c.d1;
        EXPECT_NEAR(r.lambda(2), want(2), 2e-9) << c.phi0 << " " << c.d1;
        EXPECT_GE(r.values(0), -1e-13); // never below the ground
    }
}

TEST(ConeSolver, KeepsImpulsesInsideTheCone) {
    // Two coupled contacts (a box's edge): A symmetric positive definite, not diagonal.
    cone_problem p;
    Eigen::MatrixXd m(6, 6); // a fixed instance (independent of any random generator)
    m << 0.7, -0.2, 0.4, 0.1, -0.5, 0.3, 0.2, 0.9, -0.1, 0.6, 0.2, -0.4, -0.3, 0.5, 0.8, -0.2, 0.1,
        0.6, 0.4, -0.6, 0.3, 0.5, -0.7, 0.2, 0.1, 0.2, -0.9, 0.3, 0.6, -0.1, -0.5, 0.4, 0.2, -0.3,
        0.1, 0.8;
    p.a = 1e-3 * (m * m.transpose() + 6.0 * Eigen::MatrixXd::Identity(6, 6));
    p.c.resize(6);
    p.c << -4e-6, 2e-5, -1e-5, -3e-6, -1e-5, 3e-5;
    // Both with friction, then the first without (its rows in the solver's reduced system are
    // db = −r alone, coupled to the other contact through the normal rows).
    for (const Eigen::Vector2d& mu : {Eigen::Vector2d(0.3, 0.8), Eigen::Vector2d(0.0, 0.8)}) {
        p.mu = mu;
        const auto r = solve_cone(p);
        ASSERT_TRUE(r.converged) << mu.transpose();
        for (int i = 0; i < 2; ++i) {
            const double gamma = r.lambda(3 * i), phi = r.values(3 * i);
            const Eigen::Vector2d b = r.lambda.segment<2>(3 * i + 1),
                                  d = r.values.segment<2>(3 * i + 1);
            EXPECT_GT(gamma, 1e-4) << i; // both press: the checks below are not vacuous
            EXPECT_GE(phi, -1e-13);
            EXPECT_NEAR(gamma * phi, 0.0, 1e-15);
            EXPECT_LE(b.norm(), p.mu(i) * gamma * (1.0 + 1e-9));
            // Maximal dissipation: sticking (d = 0) or b opposite to d on the cone's edge.
            if (d.norm() > 1e-11) {
                EXPECT_NEAR(b.norm(), p.mu(i) * gamma, 1e-9 * gamma);
                if (p.mu(i) > 0.0) {
                    EXPECT_NEAR(b.dot(d) / (b.norm() * d.norm()), -1.0, 1e-6);
                }
            }
        }
    }
}

TEST(ConeSolver, AWrongFrictionCoefficientIsSeen) {
    // Negative control: the closed form for μ = 0.5 does not fit a solve with μ = 0.4 (sliding).
    decoupled c{-5e-6, 3e-5, -1.5e-5, 1e-3, 2e-3, 0.5};
    const Eigen::Vector3d want = c.exact();
    c.mu = 0.4;
    const auto r = solve_cone(c.problem());
    ASSERT_TRUE(r.converged);
    EXPECT_GT((r.lambda - want).norm(), 1e-4);
}

} // namespace
