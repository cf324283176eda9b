// Optimal control of a typed Lagrangian under typed holonomic constraints (the model `lagrangian`
// with constraints: input_system<expression_lagrangian, expression_constraint>, every derivative
// symbolic, g's third ones by its code run along a direction): a pendulum in Cartesian
// coordinates, a unit mass on the unit circle pushed horizontally, against the same system
// written in C++ through system_of (automatic derivatives of every order). Both transcribe one
// discrete problem, so they must reach one optimum in the same iterations; and the typed
// transcription's derivatives pass the finite-difference check.
#include <gtest/gtest.h>

#include <cmath>

#include "../optimal/fixtures.hpp"
#include "varsym/models/expression.hpp"
#include "varsym/optimize/model.hpp"
#include "varsym/optimize/solve.hpp"
#include "varsym/optimize/transcribe.hpp"

using namespace varsym;

namespace {

const char* const cartesian_text = "0.5*(x_dot**2 + y_dot**2) - g*y";

struct cartesian_pendulum {
    static constexpr int dim = 2;
    double g = 9.81;
    template <class T>
    T operator()(const tvec<T, 2>& q, const tvec<T, 2>& v) const {
        return 0.5 * (v(0) * v(0) + v(1) * v(1)) - g * q(1);
    }
};

struct on_circle {
    static constexpr int dim = 2, count = 1;
    template <class T>
    tvec<T, 1> operator()(const tvec<T, 2>& q) const {
        return tvec<T, 1>(q(0) * q(0) + q(1) * q(1) - 1.0);
    }
};

struct push_x {
    static constexpr int dim = 2, controls = 1;
    template <class T>
    tvec<T, 2> operator()(const tvec<T, 2>&, const tvec<T, 2>&, double, const tvec<T, 1>& u) const {
        return tvec<T, 2>(u(0), T(0.0));
    }
};

/// From hanging at rest to horizontal at rest in 2 s.
optimal::control_problem quarter_turn(int steps) {
    optimal::control_problem p;
    p.time = 2.0;
    p.steps = steps;
    p.q_start = Eigen::Vector2d(0.0, -1.0);
    p.q_end = Eigen::Vector2d(1.0, 0.0);
    p.v_start = p.v_end = Eigen::VectorXd::Zero(2);
    return p;
}

std::unique_ptr<optimal::transcription> typed(const optimal::control_problem& p, double g) {
    const std::vector<expression_parameter> parameters{{"g", g}};
    models::model m = models::expression_model(cartesian_text, {"x", "y"}, parameters);
    models::add_expression_inputs(m, cartesian_text, {"x", "y"}, parameters, {"x"},
                                  {"x**2 + y**2 - 1"});
    return optimal::transcribe(m, m.defaults(), {}, p);
}

} // namespace

TEST(OptimalTyped, ConstrainedTypedLagrangianMatchesTheSameSystemInCpp) {
    const optimal::control_problem p = quarter_turn(20);
    const auto symbolic = typed(p, 9.81);
    const auto automatic = optimal::transcribe(cartesian_pendulum{}, on_circle{}, push_x{}, p);
    ASSERT_EQ(symbolic->variables(), automatic->variables());
    ASSERT_EQ(symbolic->constraints(), automatic->constraints());
    // One discrete problem: the Hessians of the NLP's Lagrangian agree to round-off at an
    // arbitrary point (both exact: symbolic against automatic third derivatives of L and g).
    const Eigen::VectorXd x =
        0.5 * Eigen::VectorXd::LinSpaced(symbolic->variables(), 0.3, 2.9).array().sin();
    const Eigen::VectorXd lambda = Eigen::VectorXd::LinSpaced(symbolic->constraints(), -2.0, 1.5);
    const auto gap = optimal_test::hessian_gap(*symbolic, *automatic, x, 0.7, lambda);
    ASSERT_TRUE(gap.same_size);
    EXPECT_LT(gap.worst, 1e-12 * gap.largest);
    EXPECT_GT(gap.largest, 1.0);
    const auto e = optimal_test::check_derivatives(*symbolic, x, 0.7, lambda);
    EXPECT_LT(e.jacobian, 1e-7 * e.largest_jacobian);
    EXPECT_LT(e.hessian, 1e-6 * e.largest_hessian);

    const auto rs = optimal::solve(*symbolic), ra = optimal::solve(*automatic);
    ASSERT_TRUE(rs.converged() && ra.converged()) << rs.message << " / " << ra.message;
    EXPECT_NEAR(rs.cost, ra.cost, 1e-9 * ra.cost);
    EXPECT_EQ(rs.iterations, ra.iterations);
    // The closure: the constrained engine, stepping the typed system's own derivatives under
    // the optimal controls, retraces the optimal nodes.
    const auto closure = optimal::check_closure(*symbolic, symbolic->unpack(rs));
    EXPECT_TRUE(closure.failure.empty()) << closure.failure;
    EXPECT_LT(closure.error, 1e-9);
    // Negative control: another gravity is another optimum.
    const auto other = optimal::solve(*typed(p, 9.0));
    ASSERT_TRUE(other.converged());
    EXPECT_GT(std::abs(other.cost - rs.cost), 1e-3 * rs.cost);
}

TEST(OptimalTyped, TypedConstraintsAreCheckedWhenGiven) {
    // A constraint that does not parse, or names no coordinate, is refused when the inputs are
    // added (before any transcription), naming the constraint.
    models::model m = models::expression_model(cartesian_text, {"x", "y"}, {{"g", 9.81}});
    EXPECT_THROW(models::add_expression_inputs(m, cartesian_text, {"x", "y"}, {{"g", 9.81}}, {"x"},
                                               {"x**2 + z**2 - 1"}),
                 std::exception);
    EXPECT_THROW(models::add_expression_inputs(m, cartesian_text, {"x", "y"}, {{"g", 9.81}}, {"x"},
                                               {"x**2 + y_dot - 1"}),
                 std::exception);
}
