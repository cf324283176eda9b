// tests/schemes/test_general.cpp: the general engine (any L(q, q̇), derivatives by automatic
// differentiation) against the separable fast paths on systems both can run: one engine.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "compare_steppers.hpp"
#include "test_support.hpp"
#include "varsym/integrate.hpp"
#include "varsym/problems/pendulum.hpp"
#include "varsym/schemes/galerkin.hpp"
#include "varsym/schemes/newmark.hpp"
#include "varsym/schemes/simpson.hpp"
#include "varsym/schemes/variational.hpp"

using namespace varsym;
using std::numbers::pi;

namespace {

/// The pendulum written as a Lagrangian templated on the scalar (differentiated by jets).
struct pendulum_lagrangian {
    static constexpr int dim = 1;
    double m = 1.0, omega = 2 * pi;
    template <class T>
    T operator()(const tvec<T, 1>& q, const tvec<T, 1>& v) const {
        using std::cos;
        return 0.5 * m * v(0) * v(0) - m * omega * omega * (1.0 - cos(q(0)));
    }
};

/// test::coupled_system() written as a Lagrangian templated on the scalar.
struct coupled_lagrangian {
    static constexpr int dim = 2;
    template <class T>
    T operator()(const tvec<T, 2>& q, const tvec<T, 2>& v) const {
        using std::cos;
        const test::coupled_pendulums c;
        const T kinetic = 0.5 * (2.0 * v(0) * v(0) + 2.0 * 0.5 * v(0) * v(1) + 1.0 * v(1) * v(1));
        const T d = q(0) - q(1);
        return kinetic - (c.a * (1.0 - cos(q(0))) + c.b * (1.0 - cos(q(1))) + 0.5 * c.c * d * d);
    }
};

using test::max_difference;
using test::paper_h;
using test::paper_x0;
using test::pendulum_sys;

} // namespace

// For constant M the general engine solves the same discrete Euler–Lagrange equations as the
// separable path (divided by h), so the steps agree to round-off. 500 steps = 10 periods of the
// paper's pendulum. One step of either differs by a few ulps of |p| ≤ 9 (≤ 4e-15, measured
// 1.8e-15 by bench/bench_family.cpp); over 500 steps these add up like a random walk
// (√500 · 4e-15 ≈ 9e-14, measured up to 1.05e-13 for lobatto-5), so 3e-13. A wrong coefficient
// in either would show at the scheme's error level, ≥ 1e-9 here.
TEST(GeneralEngine, PendulumSameStepsAsSeparablePath) {
    const lagrangian_system<pendulum_lagrangian> sys{pendulum_lagrangian{}};
    EXPECT_LE(max_difference(general::stepper(sys, paper_h, scheme_kind::simpson),
                             simpson::stepper(pendulum_sys, paper_h), paper_x0, 500),
              1e-13);
    EXPECT_LE(max_difference(general::stepper(sys, paper_h, scheme_kind::newmark),
                             newmark::stepper(pendulum_sys, paper_h), paper_x0, 500),
              1e-13);
    for (auto kind : {scheme_kind::lobatto, scheme_kind::gauss})
        for (int s = 1; s <= 5; ++s) {
            const auto rule = family_member({kind, s}).first;
            EXPECT_LE(max_difference(general::stepper(sys, paper_h, {kind, s}),
                                     galerkin::stepper(pendulum_sys, paper_h, rule, s), paper_x0,
                                     500),
                      3e-13)
                << scheme_spec(kind, s).label();
        }
}

TEST(GeneralEngine, CoupledSystemSameStepsAsSeparablePath) {
    const auto sep = test::coupled_system();
    const lagrangian_system<coupled_lagrangian> sys{coupled_lagrangian{}};
    const lagrangian_system<separable_lagrangian<decltype(sep)>> by_hand{{sep}};
    const phase_state<2> x0{vec<2>{1.0, -0.5}, vec<2>{0.3, 0.8}};
    const double h = 0.05;
    EXPECT_LE(max_difference(general::stepper(sys, h, scheme_kind::simpson),
                             simpson::stepper(sep, h), x0, 400),
              1e-13);
    EXPECT_LE(max_difference(general::stepper(by_hand, h, scheme_kind::simpson),
                             simpson::stepper(sep, h), x0, 400),
              1e-13);
    for (int s = 1; s <= 4; ++s)
        EXPECT_LE(max_difference(general::stepper(sys, h, {scheme_kind::gauss, s}),
                                 galerkin::stepper(sep, h, galerkin::rule_kind::gauss, s), x0, 400),
                  1e-13)
            << s;
}

namespace {
/// A Lagrangian that becomes NaN once q leaves (−1, 1): sqrt of a negative number.
struct fragile_lagrangian {
    static constexpr int dim = 1;
    template <class T>
    T operator()(const tvec<T, 1>& q, const tvec<T, 1>& v) const {
        using std::sqrt;
        return 0.5 * v(0) * v(0) + sqrt(1.0 - q(0) * q(0));
    }
};
/// L = ½ q̇₁² − ½ q₂²: no kinetic term in q₂, a singular mass matrix.
struct degenerate_lagrangian {
    static constexpr int dim = 2;
    template <class T>
    T operator()(const tvec<T, 2>& q, const tvec<T, 2>& v) const {
        return 0.5 * v(0) * v(0) - 0.5 * q(1) * q(1);
    }
};
} // namespace

// Failures of the user's model stop the run with the step, the time and the cause.
TEST(GeneralEngine, NaNFromTheLagrangianStopsWithStepAndTime) {
    const lagrangian_system<fragile_lagrangian> sys{fragile_lagrangian{}};
    general::stepper s(sys, 0.1, scheme_kind::simpson);
    phase_state<1> x{vec<1>{0.0}, vec<1>{3.0}}; // moves right at speed ~3: leaves (−1, 1) soon
    try {
        integrate(s, x, 0.0, 100, [](auto, auto, const auto&) {});
        FAIL() << "expected step_failure";
    } catch (const step_failure& e) {
        EXPECT_GT(e.step(), 1u);
        EXPECT_NE(std::string(e.what()).find("NaN"), std::string::npos) << e.what();
        EXPECT_LT(std::abs(x.q(0)), 1.0); // the state is the last good one
    }
}

TEST(GeneralEngine, SingularMassMatrixRefusedAtStart) {
    const lagrangian_system<degenerate_lagrangian> sys{degenerate_lagrangian{}};
    try {
        sys.check_regular(vec<2>{0.0, 1.0}, vec<2>{1.0, 0.0});
        FAIL() << "expected invalid_argument";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("singular"), std::string::npos) << e.what();
    }
}

TEST(GeneralEngine, TooLargeStepFailsWithResidual) {
    const lagrangian_system<pendulum_lagrangian> sys{pendulum_lagrangian{}};
    general::stepper s(sys, 2.0, scheme_kind::simpson); // two linear periods in one step
    phase_state<1> x{vec<1>{3.0}, vec<1>{0.0}};
    EXPECT_THROW(integrate(s, x, 0.0, 50, [](auto, auto, const auto&) {}), step_failure);
}

namespace {

/// The potential −cos q₂ of a unit pendulum beside a free coordinate (a flywheel).
struct pendulum_beside_flywheel {
    [[nodiscard]] double value(const vec<2>& q) const { return -std::cos(q(1)); }
    [[nodiscard]] vec<2> gradient(const vec<2>& q) const { return {0.0, std::sin(q(1))}; }
    [[nodiscard]] mat<2> hessian(const vec<2>& q) const {
        return vec<2>(0.0, std::cos(q(1))).asDiagonal();
    }
};

} // namespace

TEST(GeneralEngine, ResidualStopHoldsWithEquationsOfEveryScale) {
    // The stop where the residual is round-off of its own terms (variational_solve.hpp,
    // at_round_off) compares them in the units of the increments. A flywheel of mass 1e12 and
    // momentum 1e12 beside a unit pendulum, gauss-2 at 5 ms, Newton: from each state of a run,
    // the general engine's step equals the separable path's (galerkin.hpp, whose Newton loop has
    // no such stop) to 1e-15 in the pendulum's angle and momentum (measured 1.1e-16 each).
    // Negative control: compared in the residual's own units, the flywheel's 1e12 gave the
    // pendulum's equations 7e-4 of slack, every step stopped at the predictor's O(h³) guess,
    // and the angle was 2.0e-8 off.
    mat<2> m;
    m << 1e12, 0.0, 0.0, 1.0;
    const separable_system<2, pendulum_beside_flywheel> sep{m, {}};
    const lagrangian_system<separable_lagrangian<decltype(sep)>> sys{{sep}};
    newton_options newton;
    newton.iteration = iteration_kind::newton;
    const double h = 0.005;
    general::stepper s(sys, h, {scheme_kind::gauss, 2}, newton);
    galerkin::stepper reference(sep, h, galerkin::rule_kind::gauss, 2);
    phase_state<2> x{vec<2>(0.0, 1.0), vec<2>(1e12, 0.0)};
    double worst_q = 0.0, worst_p = 0.0;
    for (int j = 0; j < 400; ++j) {
        phase_state<2> y = x;
        ASSERT_TRUE(reference.step(y).converged);
        ASSERT_TRUE(s.step(x).converged);
        worst_q = std::max(worst_q, std::abs(x.q(1) - y.q(1)));
        worst_p = std::max(worst_p, std::abs(x.p(1) - y.p(1)));
        x = y;
    }
    EXPECT_LE(worst_q, 1e-15);
    EXPECT_LE(worst_p, 1e-15);
}
