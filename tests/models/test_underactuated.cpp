// tests/models/test_underactuated.cpp: the cart-pole and the acrobot of the models layer against
// independent references: their textbook equations of motion in closed form (Barto, Sutton &
// Anderson 1983 and Florian 2007 for the cart-pole; Spong 1995 for the acrobot), integrated by
// Boost.Odeint's Dormand–Prince method at tolerance 1e-13; the acrobot with point masses against
// the double pendulum model (another Lagrangian, in absolute angles); and the momentum of the
// cart, whose coordinate is cyclic, which the discrete Lagrange–d'Alembert principle advances by
// exactly h u per step.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <boost/numeric/odeint.hpp>

#include "varsym/models/model.hpp"

namespace vm = varsym::models;
using varsym::scheme_kind;
using varsym::scheme_spec;
using state4 = std::array<double, 4>; // (q1, q2, q1', q2')

namespace {

/// Integrates x' = f(x) from x over [0, t] with relative and absolute tolerance 1e-13.
template <class F>
state4 reference(F f, state4 x, double t) {
    namespace odeint = boost::numeric::odeint;
    odeint::integrate_adaptive(
        odeint::make_controlled<odeint::runge_kutta_dopri5<state4>>(1e-13, 1e-13),
        [&](const state4& y, state4& dy, double) { dy = f(y); }, x, 0.0, t, 1e-4);
    return x;
}

/// The simulation of `name` with parameters changed by `set`, from q0 and v0, by gauss-4
/// (order 8) with step h, advanced to time t.
std::unique_ptr<vm::simulation> run(const char* name,
                                    const std::vector<std::pair<const char*, double>>& set,
                                    std::vector<double> q0, std::vector<double> v0, double h,
                                    double t) {
    const vm::model& m = vm::get(name);
    std::vector<double> values = m.defaults();
    for (const auto& [key, v] : set)
        values.at(static_cast<std::size_t>(m.parameter_index(key))) = v;
    const vm::problem pr = m.prepare(values, {std::move(q0), {}, std::move(v0)});
    auto sim = pr.simulate({scheme_spec(scheme_kind::gauss, 4), {}, h});
    sim->advance(static_cast<std::size_t>(std::llround(t / h)));
    return sim;
}

} // namespace

TEST(CartPole, MatchesBartoSuttonAndersonEquationsUnderAPush) {
    // Barto et al.'s uniform pole (I = m l^2 / 3, the model's default), frictionless:
    //   th'' = (g sin th + cos th (-u - m l th'^2 sin th)/(M+m)) / (l (4/3 - m cos^2 th/(M+m)))
    //   x''  = (u + m l (th'^2 sin th - th'' cos th)) / (M+m)
    const double big_m = 1.0, m = 0.1, l = 0.5, g = 9.81, u = 1.5, t = 2.0;
    auto f = [&](const state4& s) {
        const double c = std::cos(s[1]), sn = std::sin(s[1]), total = big_m + m;
        const double tmp = (u + m * l * s[3] * s[3] * sn) / total;
        const double th_dd = (g * sn - c * tmp) / (l * (4.0 / 3.0 - m * c * c / total));
        const double x_dd = tmp - m * l * th_dd * c / total;
        return state4{s[2], s[3], x_dd, th_dd};
    };
    const state4 ref = reference(f, {0.0, 0.1, 0.0, 0.0}, t);
    const auto sim = run("cart-pole", {{"push", u}}, {0.0, 0.1}, {0.0, 0.0}, 0.005, t);
    // p from the reference's velocities: p_x = (M+m) x' + m l cos th th', p_th = m l cos th x'
    // + (4/3) m l^2 th'.
    const double c = std::cos(ref[1]);
    const double px = (big_m + m) * ref[2] + m * l * c * ref[3];
    const double pth = m * l * c * ref[2] + 4.0 / 3.0 * m * l * l * ref[3];
    EXPECT_NEAR(sim->q()[0], ref[0], 1e-9);
    EXPECT_NEAR(sim->q()[1], ref[1], 1e-9);
    EXPECT_NEAR(sim->p()[0], px, 1e-9);
    EXPECT_NEAR(sim->p()[1], pth, 1e-9);
    // Negative control: the same push on the other sign is far from the reference.
    const auto other = run("cart-pole", {{"push", -u}}, {0.0, 0.1}, {0.0, 0.0}, 0.005, t);
    EXPECT_GT(std::abs(other->q()[0] - ref[0]), 0.1);
}

TEST(CartPole, TheCartMomentumGrowsByExactlyThePushTimesTime) {
    // x is cyclic, so d p_x/dt = u; the forced discrete Euler-Lagrange equations give p_x(t_j) =
    // p_x(0) + j h u up to round-off (the quadrature weights of the force sum to h).
    const double u = 0.75, h = 0.01;
    const vm::model& m = vm::get("cart-pole");
    std::vector<double> values = m.defaults();
    values.at(static_cast<std::size_t>(m.parameter_index("push"))) = u;
    const auto sim = m.prepare(values, {{0.0, 2.0}, {}, {0.3, -1.0}})
                         .simulate({scheme_spec(scheme_kind::simpson), {}, h});
    const double p0 = sim->p()[0];
    // The energy balance: E − E₀ − W (W the push's work, read from the model's columns) stays at
    // the scheme's error.
    const std::vector<std::string>& names = sim->columns();
    ASSERT_GE(names.size(), 2U);
    ASSERT_EQ(names.at(0), "energy");
    ASSERT_EQ(names.at(1), "work");
    std::vector<double> row(names.size());
    sim->values(row);
    const double e0 = row[0];
    double worst = 0.0, balance = 0.0, largest_work = 0.0;
    sim->advance(2000, [&] {
        worst = std::max(worst, std::abs(sim->p()[0] - p0 - u * sim->time()));
        sim->values(row);
        balance = std::max(balance, std::abs(row[0] - e0 - row[1]));
        largest_work = std::max(largest_work, std::abs(row[1]));
        return false;
    });
    EXPECT_LT(worst, 1e-11);
    // Simpson at h = 0.01 over 20 s: measured 1.9e-8 J (2e-10 of the work, 107 J); budget 5×.
    EXPECT_LT(balance, 1e-7);
    EXPECT_GT(largest_work, 1.0); // not vacuous: the push does work
}

TEST(Acrobot, WithPointMassesIsTheDoublePendulumInRelativeAngles) {
    // lc1 = l1, lc2 = l2, no inertia about the centres: the double pendulum's Lagrangian in
    // th1 = q1, th2 = q1 + q2 (another model, written in absolute angles). A Galerkin variational
    // integrator commutes with a linear change of coordinates (the interpolant and the quadrature
    // of the transformed curve are the transformed ones), so the two discrete flows agree to
    // round-off, not merely to the scheme's error: measured 2e-16 .. 8e-16 after 1500 steps.
    const double t = 3.0, h = 0.002;
    const auto acro = run("acrobot", {{"lc1", 1.0}, {"lc2", 1.0}, {"I1", 0.0}, {"I2", 0.0}},
                          {1.0, 0.5}, {0.0, 0.0}, h, t);
    const auto dp = run("double-pendulum", {}, {1.0, 1.5}, {0.0, 0.0}, h, t);
    EXPECT_NEAR(acro->q()[0], dp->q()[0], 1e-12);
    EXPECT_NEAR(acro->q()[0] + acro->q()[1], dp->q()[1], 1e-12);
    EXPECT_NEAR(acro->p()[0] - acro->p()[1], dp->p()[0], 1e-12); // p_th1 = p_q1 - p_q2
    EXPECT_GT(std::abs(acro->q()[0] - 1.0), 0.1); // it moved
}

TEST(Acrobot, MatchesSpongsEquationsUnderAnElbowTorque) {
    // Spong (1995): d11 q1'' + d12 q2'' + h1 + phi1 = 0, d12 q1'' + d22 q2'' + h2 + phi2 = u.
    const double m1 = 1.0, m2 = 1.0, l1 = 1.0, lc1 = 0.5, lc2 = 0.5, i1 = 1.0 / 12.0,
                 i2 = 1.0 / 12.0, g = 9.81, u = 0.8, t = 3.0;
    auto f = [&](const state4& s) {
        const double c2 = std::cos(s[1]), s2 = std::sin(s[1]);
        const double d11 =
            m1 * lc1 * lc1 + m2 * (l1 * l1 + lc2 * lc2 + 2 * l1 * lc2 * c2) + i1 + i2;
        const double d12 = m2 * (lc2 * lc2 + l1 * lc2 * c2) + i2, d22 = m2 * lc2 * lc2 + i2;
        const double h1 = -m2 * l1 * lc2 * s2 * s[3] * s[3] - 2 * m2 * l1 * lc2 * s2 * s[3] * s[2];
        const double h2 = m2 * l1 * lc2 * s2 * s[2] * s[2];
        const double phi1 =
            (m1 * lc1 + m2 * l1) * g * std::sin(s[0]) + m2 * lc2 * g * std::sin(s[0] + s[1]);
        const double phi2 = m2 * lc2 * g * std::sin(s[0] + s[1]);
        const double r1 = -h1 - phi1, r2 = u - h2 - phi2, det = d11 * d22 - d12 * d12;
        return state4{s[2], s[3], (d22 * r1 - d12 * r2) / det, (d11 * r2 - d12 * r1) / det};
    };
    const state4 ref = reference(f, {1.0, 0.0, 0.0, 0.0}, t);
    const auto sim = run("acrobot", {{"torque", u}}, {1.0, 0.0}, {0.0, 0.0}, 0.002, t);
    EXPECT_NEAR(sim->q()[0], ref[0], 1e-8);
    EXPECT_NEAR(sim->q()[1], ref[1], 1e-8);
    const auto free = run("acrobot", {}, {1.0, 0.0}, {0.0, 0.0}, 0.002, t); // negative control
    EXPECT_GT(std::abs(free->q()[1] - ref[1]), 1e-2);
}
