// tests/schemes/test_discrete_euler_lagrange.cpp: each step solves the position–momentum form
// of the discrete Euler–Lagrange equations of its discrete Lagrangian (docs/design.md, "The one
// idea"),
//   p_j = −∂L_d/∂q_l,  0 = ∂L_d/∂q_m,  p_{j+1} = ∂L_d/∂q_r,
// with the partial derivatives of L_d (paper eqs. lagrangien-discret, LLhh) taken by finite
// differences: this checks the stepper against the Lagrangian itself, not against the
// Hamiltonian form it was derived into.
#include <gtest/gtest.h>

#include <numbers>

#include "test_support.hpp"
#include "varsym/problems/pendulum.hpp"
#include "varsym/schemes/newmark.hpp"
#include "varsym/schemes/simpson.hpp"

using namespace varsym;

namespace {

// ∂f/∂x_i by central differences with Richardson extrapolation: error O(δ⁴) + O(ε|f|/δ).
template <int D, class F>
vec<D> gradient_fd(F&& f, const vec<D>& x, double delta) {
    vec<D> g(x.size());
    for (int i = 0; i < x.size(); ++i) {
        auto central = [&](double dl) {
            vec<D> a = x, b = x;
            a(i) += dl;
            b(i) -= dl;
            return (f(a) - f(b)) / (2 * dl);
        };
        g(i) = (4 * central(delta / 2) - central(delta)) / 3;
    }
    return g;
}

// Tolerance: L_d is O(10) here, so round-off in the differences is ~1e-15·10/δ = 1e-10 with
// δ = 1e-4, truncation ~δ⁴|L⁽⁵⁾| ≈ 1e-13. 1e-8 relative to max(1, |p|) leaves room for both.
constexpr double delta = 1e-4;
constexpr double tol = 1e-8;

template <class System>
void check_simpson(const System& sys, phase_state<System::dim> x, double h, int steps) {
    using V = vec<System::dim>;
    simpson::stepper<System> s(sys, h);
    for (int j = 0; j < steps; ++j) {
        const phase_state<System::dim> before = x;
        ASSERT_TRUE(s.step(x).converged);
        const V ql = before.q, qm = s.last_stage(), qr = x.q;
        const double scale = std::max(1.0, x.p.template lpNorm<Eigen::Infinity>());
        const V dl = gradient_fd<System::dim>(
            [&](const V& y) { return simpson::discrete_lagrangian(sys, h, y, qm, qr); }, ql, delta);
        const V dm = gradient_fd<System::dim>(
            [&](const V& y) { return simpson::discrete_lagrangian(sys, h, ql, y, qr); }, qm, delta);
        const V dr = gradient_fd<System::dim>(
            [&](const V& y) { return simpson::discrete_lagrangian(sys, h, ql, qm, y); }, qr, delta);
        EXPECT_LE((before.p + dl).template lpNorm<Eigen::Infinity>(), tol * scale) << "step " << j;
        EXPECT_LE(dm.template lpNorm<Eigen::Infinity>(), tol * scale) << "step " << j;
        EXPECT_LE((x.p - dr).template lpNorm<Eigen::Infinity>(), tol * scale) << "step " << j;
    }
}

template <class System>
void check_newmark(const System& sys, phase_state<System::dim> x, double h, int steps) {
    using V = vec<System::dim>;
    newmark::stepper<System> s(sys, h);
    for (int j = 0; j < steps; ++j) {
        const phase_state<System::dim> before = x;
        ASSERT_TRUE(s.step(x).converged);
        const V ql = before.q, qr = x.q;
        const double scale = std::max(1.0, x.p.template lpNorm<Eigen::Infinity>());
        const V dl = gradient_fd<System::dim>(
            [&](const V& y) { return newmark::discrete_lagrangian(sys, h, y, qr); }, ql, delta);
        const V dr = gradient_fd<System::dim>(
            [&](const V& y) { return newmark::discrete_lagrangian(sys, h, ql, y); }, qr, delta);
        EXPECT_LE((before.p + dl).template lpNorm<Eigen::Infinity>(), tol * scale) << "step " << j;
        EXPECT_LE((x.p - dr).template lpNorm<Eigen::Infinity>(), tol * scale) << "step " << j;
    }
}

} // namespace

TEST(DiscreteEulerLagrange, SimpsonPendulum) {
    const auto sys = pendulum::make_system(1.0, 2 * std::numbers::pi);
    check_simpson(sys, {vec<1>{std::numbers::pi / 2}, vec<1>{0.0}}, 1.18 / 20, 40);
}

TEST(DiscreteEulerLagrange, NewmarkPendulum) {
    const auto sys = pendulum::make_system(1.0, 2 * std::numbers::pi);
    check_newmark(sys, {vec<1>{std::numbers::pi / 2}, vec<1>{0.0}}, 1.18 / 20, 40);
}

TEST(DiscreteEulerLagrange, CoupledPendulums) {
    const auto sys = test::coupled_system();
    check_simpson(sys, {vec<2>{1.0, -0.5}, vec<2>{0.3, 1.2}}, 0.1, 30);
    check_newmark(sys, {vec<2>{1.0, -0.5}, vec<2>{0.3, 1.2}}, 0.1, 30);
}
