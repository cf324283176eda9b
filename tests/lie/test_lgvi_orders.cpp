// tests/lie/test_lgvi_orders.cpp: orders 2, 4, 6 of the Lie group integrator by step halving,
// against closed forms (the free symmetric body's attitude, the symmetric top's nutation θ(t),
// the planar pendulum's Jacobi-elliptic solution) and against a fine-step reference (an
// asymmetric top); the symmetric top agrees with the Euler-angle `heavy-top` on the general
// engine, and passes within 5e-7 rad of the vertical, where the Euler angles are singular.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>

#include "lie_support.hpp"
#include "test_support.hpp"
#include "varsym/diagnostics/convergence.hpp"
#include "varsym/lie/symmetric_top.hpp"
#include "varsym/problems/pendulum.hpp"

using namespace varsym;
using namespace varsym::test;

namespace {

/// Step counts per order where the error is in the asymptotic regime and above round-off.
std::array<double, 3> counts(int order) {
    return order == 2 ? std::array<double, 3>{400, 800, 1600}
                      : (order == 4 ? std::array<double, 3>{200, 400, 800}
                                    : std::array<double, 3>{100, 200, 400});
}

/// For orders 2, 4, 6: the error of `end(x)`, x the state after n steps from x0 over [0, t],
/// at the counts above; the fitted order, recorded as the test property NAME_order_P with its
/// errors, is within `tol` of P.
template <class Error>
void expect_orders(const std::string& name, const rigid_body& b, const body_state& x0, double t,
                   double tol, Error&& error) {
    for (const int order : {2, 4, 6}) {
        const auto steps = counts(order);
        std::array<double, 3> err{};
        for (std::size_t i = 0; i < 3; ++i)
            err[i] = error(run_body(b, x0, t, static_cast<std::size_t>(steps[i]), order));
        const double p = fitted_order(steps, err);
        ::testing::Test::RecordProperty(name + "_order_" + std::to_string(order),
                                        sci(p) + " (errors " + sci(err[0]) + ", " + sci(err[1]) +
                                            ", " + sci(err[2]) + ")");
        EXPECT_NEAR(p, order, tol) << name << ", order " << order;
    }
}

} // namespace

// Free body, I₁ = I₂ = 1, I₃ = 0.5, 10 s: against R(t) = exp(tπ̂/I₁) R₀ exp(tνê₃) exactly.
TEST(LgviOrder, FreeSymmetricBodyAgainstClosedForm) {
    const rigid_body body(diag(1.0, 1.0, 0.5));
    body_state x0;
    x0.R = so3::from_euler(0.7, 0.3, 0.2);
    x0.pi = vec3(0.3, -0.5, 2.0);
    const body_state exact = lie::free_symmetric_motion(body, x0).at(10.0);
    expect_orders("free_body", body, x0, 10.0, 0.1,
                  [&](const body_state& x) { return state_error(x, exact); });
}

// The symmetric heavy top against the closed-form θ(t) (Goldstein §5.7) over one nutation
// period and a half: cos θ = R₃₃.
TEST(LgviOrder, SymmetricTopAgainstClosedFormNutation) {
    const rigid_body top = symmetric_top();
    const body_state x0 = top_start(top);
    const auto nut = lie::nutation_of(top, x0);
    const double t = 1.5 * nut.period();
    expect_orders("top", top, x0, t, 0.15, [&](const body_state& x) {
        return std::abs(std::acos(x.R(2, 2)) - nut.theta(t));
    });
}

// Through the vertical: p_φ = p_ψ (1 + 1e-7) makes the axis pass within θ_min ≈ 5e-7 rad of
// the vertical every nutation period. The group integrator keeps its orders there (against the
// closed form, in cos θ = R₃₃, which is smooth through the vertical).
TEST(LgviOrder, TopThroughTheVerticalKeepsItsOrder) {
    const rigid_body top = symmetric_top();
    body_state x0;
    const double theta0 = 0.5, spin = 3.0;
    x0.R = so3::from_euler(theta0, 0.0, 0.0);
    // π₃ = sin θ₀ Π₂ + cos θ₀ Π₃ = Π₃ (1 + 1e-7).
    x0.pi = vec3(0.0, spin * (1.0 + 1e-7 - std::cos(theta0)) / std::sin(theta0), spin);
    const auto nut = lie::nutation_of(top, x0);
    RecordProperty("theta_min", sci(nut.theta_min()));
    ASSERT_LT(nut.theta_min(), 2e-6);
    const double t = 2.25 * nut.period();
    expect_orders("through_vertical", top, x0, t, 0.2, [&](const body_state& x) {
        return std::abs(x.R(2, 2) - std::cos(nut.theta(t)));
    });
}

// The 3D pendulum swinging in a plane (about its principal axis e₁, centre of mass 1 m below
// the pivot) is the planar pendulum: against its Jacobi-elliptic solution (problems/pendulum.hpp)
// at a swing of 2.5 rad, over 3 s.
TEST(LgviOrder, PlanarSwingOfThe3dPendulumIsThePendulum) {
    const rigid_body body(diag(2.0, 1.5, 1.0), vec3(0, 0, -1.0), 9.81);
    const double q0 = 2.5, t = 3.0;
    body_state x0;
    x0.R = so3::exp(vec3(q0, 0, 0));
    const pendulum::exact_solution exact(2.0, std::sqrt(9.81 / 2.0), q0, 0.0);
    const auto ref = exact.at(t);
    expect_orders("pendulum", body, x0, t, 0.1, [&](const body_state& x) {
        EXPECT_LT(std::abs(x.pi(1)) + std::abs(x.pi(2)), 1e-13); // stays in its plane
        const double q = std::atan2(x.R(2, 1), x.R(1, 1));       // R = R_x(q)
        return std::max(std::abs(q - ref.q(0)), std::abs(x.pi(0) - ref.p(0)) / 2.0);
    });
}

// An asymmetric top with an off-axis centre of mass (no closed form): against the order-6
// integrator at 16 times the finest step count (its error is below 1e-13 here).
TEST(LgviOrder, AsymmetricTopAgainstFineReference) {
    const rigid_body top(diag(2.0, 1.6, 0.8), vec3(0.1, -0.2, 0.7), 3.0);
    const body_state x0 = euler_start(top, 0.9, 0.2, -0.4, 0.3, 1.0, 5.0);
    const double t = 2.0;
    const body_state ref = run_body(top, x0, t, 6400, 6);
    expect_orders("asymmetric_top", top, x0, t, 0.15,
                  [&](const body_state& x) { return state_error(x, ref); });
}
