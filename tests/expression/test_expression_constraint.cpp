// Typed holonomic constraints (systems/expression_constraint.hpp) in the constrained general
// engine, whose constraint count is then known at run time only.
// References: the same pendulum with its rod written in C++ (a compile-time count, derivatives
// by automatic differentiation; tests/schemes/test_constrained.cpp holds it to its exact
// solution): the two runs must agree to round-off, step by step; the Jacobian and curvature
// against the automatic derivatives; the refusals of what is not a holonomic constraint.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "test_support.hpp"
#include "varsym/integrate.hpp"
#include "varsym/schemes/constrained.hpp"
#include "varsym/systems/expression_constraint.hpp"
#include "varsym/systems/expression_lagrangian.hpp"

namespace varsym {
namespace {

// The planar pendulum as a point mass on a rod: L = ½ m |v|² − m g y, |x| = ℓ.
struct typed_mass {
    static constexpr int dim = 2;
    template <class T>
    T operator()(const tvec<T, 2>& q, const tvec<T, 2>& v) const {
        return 0.5 * v.squaredNorm() - 9.81 * q(1);
    }
};
struct typed_rod {
    static constexpr int dim = 2, count = 1;
    template <class T>
    tvec<T, 1> operator()(const tvec<T, 2>& q) const {
        return tvec<T, 1>(q.squaredNorm() - 1.5 * 1.5);
    }
};

const std::vector<expression_parameter> rod_parameters{{"g", 9.81}, {"l", 1.5}};

expression_constraint typed_rod_expression() {
    return {{"x**2 + y**2 - l**2"}, {"x", "y"}, rod_parameters};
}

TEST(ExpressionConstraint, DerivativesMatchAutomaticDifferentiation) {
    const expression_constraint c({"x**2 + y**2 - l**2", "sin(x)*y - g*x**3"}, {"x", "y"},
                                  rod_parameters);
    ASSERT_EQ(c.size(), 2);
    const vec<dynamic> q = vec<dynamic>::Map(std::vector<double>{0.3, -1.1}.data(), 2);
    const vec<dynamic> g = c(q);
    EXPECT_DOUBLE_EQ(g(0), 0.09 + 1.21 - 2.25);
    EXPECT_DOUBLE_EQ(g(1), std::sin(0.3) * -1.1 - 9.81 * 0.027);
    Eigen::MatrixXd jac;
    c.jacobian(q, jac);
    // By hand: ∇g_1 = (2x, 2y); ∇g_2 = (cos x · y − 3 g x², sin x).
    EXPECT_NEAR(jac(0, 0), 0.6, 1e-15);
    EXPECT_NEAR(jac(0, 1), -2.2, 1e-15);
    EXPECT_NEAR(jac(1, 0), std::cos(0.3) * -1.1 - 3.0 * 9.81 * 0.09, 1e-14);
    EXPECT_NEAR(jac(1, 1), std::sin(0.3), 1e-15);
    // H = λ_1 ∇²g_1 + λ_2 ∇²g_2: ∇²g_1 = 2 I; ∇²g_2 = [[−sin x · y − 6 g x, cos x], [cos x, 0]].
    mat<dynamic> h;
    c.curvature(q, vec<dynamic>::Map(std::vector<double>{0.5, -2.0}.data(), 2), h);
    EXPECT_NEAR(h(0, 0), 1.0 - 2.0 * (std::sin(0.3) * 1.1 - 6.0 * 9.81 * 0.3), 1e-13);
    EXPECT_NEAR(h(0, 1), -2.0 * std::cos(0.3), 1e-15);
    EXPECT_NEAR(h(1, 0), h(0, 1), 0.0);
    EXPECT_NEAR(h(1, 1), 1.0, 1e-15);
}

TEST(ExpressionConstraint, PendulumMatchesTheCompiledRodStepByStep) {
    using typed = general::constrained_stepper<typed_mass, typed_rod>;
    using expressed = general::constrained_stepper<expression_lagrangian, expression_constraint>;
    const expression_lagrangian l("0.5*(x_dot**2 + y_dot**2) - g*y", {"x", "y"}, rod_parameters);
    for (const scheme_spec spec :
         {scheme_spec(scheme_kind::simpson), scheme_spec(scheme_kind::gauss, 3)}) {
        SCOPED_TRACE(spec.label());
        typed a(lagrangian_system<typed_mass>({}), {}, 0.02, spec);
        expressed b(lagrangian_system<expression_lagrangian>(l), typed_rod_expression(), 0.02,
                    spec);
        EXPECT_EQ(b.constraints(), 1);
        // θ = 2 from the downward vertical, at rest.
        phase_state<2> xa{vec<2>{1.5 * std::sin(2.0), -1.5 * std::cos(2.0)}, vec<2>::Zero()};
        phase_state<dynamic> xb{xa.q, xa.p};
        a.check_initial(xa);
        b.check_initial(xb);
        double apart = 0.0, residual = 0.0;
        for (int j = 0; j < 500; ++j) {
            ASSERT_TRUE(a.step(xa).converged);
            ASSERT_TRUE(b.step(xb).converged);
            apart = std::max({apart, (xa.q - xb.q).lpNorm<Eigen::Infinity>(),
                              (xa.p - xb.p).lpNorm<Eigen::Infinity>()});
            residual = std::max(residual, b.residual(xb.q));
        }
        // Same equations, derivatives exact in both: only the order of round-off differs.
        EXPECT_LE(apart, 1e-11);
        RecordProperty("apart_" + spec.label(), test::sci(apart));
        EXPECT_LE(residual, 1e-13);
        EXPECT_NEAR(b.mean_multiplier()(0), a.mean_multiplier()(0), 1e-10);
        // Negative control: a different step size moves the state far more than that.
        expressed c(lagrangian_system<expression_lagrangian>(l), typed_rod_expression(), 0.021,
                    spec);
        phase_state<dynamic> xc{vec<dynamic>(vec<2>{1.5 * std::sin(2.0), -1.5 * std::cos(2.0)}),
                                vec<dynamic>::Zero(2)};
        for (int j = 0; j < 500; ++j)
            ASSERT_TRUE(c.step(xc).converged);
        EXPECT_GT((xc.q - xb.q).lpNorm<Eigen::Infinity>(), 1e-3);
    }
}

TEST(ExpressionConstraint, OffTheRodIsRefusedOrProjected) {
    const expression_lagrangian l("0.5*(x_dot**2 + y_dot**2) - g*y", {"x", "y"}, rod_parameters);
    general::constrained_stepper<expression_lagrangian, expression_constraint> st(
        lagrangian_system<expression_lagrangian>(l), typed_rod_expression(), 0.01,
        scheme_spec(scheme_kind::simpson));
    phase_state<dynamic> x{vec<dynamic>(vec<2>{1.0, -1.0}), vec<dynamic>(vec<2>{1.0, 1.0})};
    EXPECT_THROW(st.check_initial(x), std::invalid_argument);
    const phase_state<dynamic> y = st.project(x);
    EXPECT_NEAR(y.q.norm(), 1.5, 1e-14);
    EXPECT_NO_THROW(st.check_initial(y));
    EXPECT_NEAR(y.q.dot(y.p), 0.0, 1e-14); // p = v for unit mass: tangent to the circle
}

TEST(ExpressionConstraint, WhatIsNotAHolonomicConstraintIsRefused) {
    auto message = [](std::vector<std::string> eq) {
        try {
            expression_constraint c(std::move(eq), {"x", "y"}, rod_parameters);
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    EXPECT_NE(message({"x*y_dot"}).find("depends on the velocity y_dot"), std::string::npos);
    EXPECT_NE(message({"x - 1", "x**2 + t"}).find("constraint 2"), std::string::npos);
    EXPECT_NE(message({"x**2 + t"}).find("the time t"), std::string::npos);
    EXPECT_NE(message({"x + y +"}).find("constraint 1:"), std::string::npos);
    EXPECT_NE(message({"x + z"}).find("'z'"), std::string::npos) << message({"x + z"});
    EXPECT_NE(message({}).find("at least one"), std::string::npos);
    // Simplified away: t*0 and y_dot - y_dot are not dependences.
    EXPECT_EQ(message({"x**2 + y**2 - 1 + 0*t + y_dot - y_dot"}), "accepted");
}

} // namespace
} // namespace varsym
