// A free final time: the minimum-time transfer of a double integrator (q̈ = u, |u| ≤ 1) from
// rest at 0 to rest at 1, whose optimum is bang-bang, u = +1 then −1, switching at T*/2, with
// T* = 2 √(1/1) = 2 (Kirk, Optimal Control Theory, §5.3); and the derivatives in T, the
// Hessian's row of T included, against finite differences on the nonlinear pendulum.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "optimal/fixtures.hpp"
#include "varsym/optimize/solve.hpp"
#include "varsym/optimize/transcribe.hpp"

namespace {

using namespace varsym;

const optimal_test::one_dof free_mass;
const optimal_test::one_dof timed_pendulum{.gravity = 9.81};
using free_push = optimal_test::direct_input<1>;

optimal::control_problem bang_bang(const scheme_spec& spec, int steps) {
    optimal::control_problem p;
    p.time = 3.0; // the first guess
    p.free_time = true;
    p.steps = steps;
    p.scheme = spec;
    p.cost = {.effort = 0.0, .time = 1.0};
    p.q_start = p.v_start = p.v_end = Eigen::VectorXd::Zero(1);
    p.q_end = Eigen::VectorXd::Ones(1);
    p.control_lower = Eigen::VectorXd::Constant(1, -1.0);
    p.control_upper = Eigen::VectorXd::Constant(1, 1.0);
    return p;
}

TEST(OptimalMinimumTime, DoubleIntegratorIsBangBang) {
    // With an even N the switch falls on a node; each half is then a quadratic q(t), which
    // every member's polynomial and quadrature hold exactly: T* to the solver's tolerance.
    for (const scheme_spec spec :
         {scheme_spec(scheme_kind::simpson), scheme_spec(scheme_kind::newmark),
          scheme_spec(scheme_kind::gauss, 3)}) {
        const auto tr = optimal::transcribe(free_mass, free_push{}, bang_bang(spec, 20));
        const auto r = optimal::solve(*tr);
        ASSERT_TRUE(r.converged()) << spec.label() << ": " << r.message;
        const auto path = tr->unpack(r);
        EXPECT_NEAR(path.node_times(20), 2.0, 1e-7) << spec.label();
        EXPECT_NEAR(path.cost, 2.0, 1e-7) << spec.label();
        for (Eigen::Index c = 0; c < path.u.cols(); ++c) { // +1 before the switch, −1 after
            const double t = path.control_times(c);
            if (std::abs(t - 1.0) < 1e-6) continue; // at the switch itself u is not determined
            EXPECT_NEAR(path.u(0, c), t < 1.0 ? 1.0 : -1.0, 1e-6) << spec.label() << " at " << t;
        }
        // The closure holds with the time found, to round-off (with IPOPT's default relaxation
        // of the bounds by 1e-8 it was 9.4e-9: optimal/src/ipopt_solve.cpp).
        const Eigen::MatrixXd nodes = tr->replay(path);
        EXPECT_LT((nodes.topRows(1) - path.q).cwiseAbs().maxCoeff(), 1e-12) << spec.label();
    }
}

TEST(OptimalMinimumTime, DerivativesInTheTimeMatchFiniteDifferences) {
    optimal::control_problem p;
    p.time = 2.0;
    p.free_time = true;
    p.steps = 3;
    p.scheme = {scheme_kind::gauss, 2};
    p.cost = {.effort = 0.7, .power = 0.3, .time = 1.5};
    p.q_start = p.v_start = Eigen::VectorXd::Zero(1);
    p.v_end = Eigen::VectorXd::Constant(1, 0.4);
    p.q_end = Eigen::VectorXd::Constant(1, 3.0);
    // Velocity bounds: node velocities, and rows V/h at the interior points that depend on T.
    p.velocity_lower = Eigen::VectorXd::Constant(1, -5.0);
    p.velocity_upper = Eigen::VectorXd::Constant(1, 5.0);
    const auto tr = optimal::transcribe(timed_pendulum, free_push{}, p);
    EXPECT_TRUE(tr->has_hessian());
    const int n = tr->variables();
    Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(n, 0.3, 2.9).array().sin() + 0.5;
    x(n - 1) = 1.7; // T
    const Eigen::VectorXd lambda = Eigen::VectorXd::LinSpaced(tr->constraints(), -1.0, 2.0);
    const auto e = optimal_test::check_derivatives(*tr, x, 0.8, lambda);
    EXPECT_LT(e.jacobian, 1e-6);
    EXPECT_LT(e.gradient, 1e-6);
    // The Hessian against central differences of σ∇J + Jᵀλ (step 1e-6: about 1e-9 of entries
    // up to about 10); its row of T not vacuous: without it the gap is of order one.
    EXPECT_LT(e.hessian, 1e-6 * e.largest_hessian);
    {
        std::vector<double> hv;
        tr->hessian(x, 0.8, lambda, hv);
        const Eigen::MatrixXd hes = tr->hessian_pattern().dense(hv, n, n);
        EXPECT_GT(hes.row(n - 1).cwiseAbs().maxCoeff(), 0.1);
    }
    std::vector<double> values;
    tr->jacobian(x, values);
    const auto pattern = tr->jacobian_pattern();
    ASSERT_EQ(static_cast<int>(values.size()), pattern.size());
    const Eigen::MatrixXd jac = pattern.dense(values, tr->constraints(), n);
    EXPECT_GT(jac.col(n - 1).cwiseAbs().maxCoeff(), 1.0); // the T column is there
}

TEST(OptimalMinimumTime, AutomaticHessianFallsBackWhereTheExactOneFails) {
    // The pendulum swung up from hanging to upright at rest as fast as |u| <= 5 allows (the
    // example optimal_minimum_time's coarsest level, N = 20, gauss-2): with its exact Hessian
    // IPOPT ends at a point of local infeasibility (a one-switch motion on spurious roots of
    // steps too coarse for it, measured after 34 iterations); the automatic choice then solves
    // again with limited memory, which reaches the two-switch minimum (T = 2.387112 s at this N,
    // the example's 2.385581 s at N = 80). Negative control: the exact Hessian alone fails.
    optimal::control_problem p;
    p.time = 3.0;
    p.free_time = true;
    p.time_lower = 0.2;
    p.time_upper = 20.0;
    p.cost = {.effort = 0.0, .time = 1.0};
    p.steps = 20;
    p.scheme = {scheme_kind::gauss, 2};
    p.q_start = p.v_start = p.v_end = Eigen::VectorXd::Zero(1);
    p.q_end = Eigen::VectorXd::Constant(1, 3.141592653589793);
    p.control_lower = Eigen::VectorXd::Constant(1, -5.0);
    p.control_upper = Eigen::VectorXd::Constant(1, 5.0);
    const auto tr = optimal::transcribe(timed_pendulum, free_push{}, p);
    optimal::solver_options exact;
    exact.hessian = optimal::hessian_kind::exact;
    const auto alone = optimal::solve(*tr, exact);
    EXPECT_FALSE(alone.converged()) << alone.message;
    const auto r = optimal::solve(*tr);
    ASSERT_TRUE(r.converged()) << r.message;
    EXPECT_NE(r.message.find("by the limited-memory Hessian, after the exact one ended"),
              std::string::npos)
        << r.message;
    EXPECT_GT(r.iterations, alone.iterations);
    const auto path = tr->unpack(r);
    EXPECT_NEAR(path.node_times(20), 2.387112, 1e-6);
    EXPECT_LT(optimal::check_closure(*tr, path).error, 1e-10);
}

TEST(OptimalMinimumTime, RefusesInconsistentTimes) {
    auto p = bang_bang(scheme_kind::simpson, 10);
    p.time_upper = 1.0; // the guess 3 is outside [lower, 1]
    EXPECT_THROW((void)optimal::transcribe(free_mass, free_push{}, p), std::invalid_argument);
    p = bang_bang(scheme_kind::simpson, 10);
    p.free_time = false; // a cost on T with T fixed
    EXPECT_THROW((void)optimal::transcribe(free_mass, free_push{}, p), std::invalid_argument);
}

} // namespace
