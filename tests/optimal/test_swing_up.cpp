// DMOC on a nonlinear problem against an indirect solution: the pendulum swing-up (m = l = 1,
// g = 9.81, T = 2, from hanging at rest to upright at rest, minimising ∫ u²/2). The reference
// solves Pontryagin's boundary value problem (θ̇ = ω, ω̇ = −g sin θ + λ_ω, λ̇_θ = g cos θ λ_ω,
// λ̇_ω = −λ_θ, u = λ_ω) by shooting on (λ_θ(0), λ_ω(0)) with Boost.Odeint's Dormand–Prince at
// 1e-13, seeded from DMOC's costates: a different integrator and a different method. Also the
// exact first and second derivatives against finite differences, and a stop from the callback.
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include <boost/numeric/odeint.hpp>
#include <gtest/gtest.h>

#include "optimal/fixtures.hpp"
#include "varsym/optimal/replay.hpp"
#include "varsym/optimize/solve.hpp"
#include "varsym/optimize/transcribe.hpp"

namespace {

using namespace varsym;
constexpr double swing_g = 9.81, swing_time = 2.0;

const optimal_test::one_dof swing_pendulum{.gravity = swing_g};
using swing_torque = optimal_test::direct_input<1>;

using swing_state = std::array<double, 5>; // θ, ω, λ_θ, λ_ω, ∫ u²/2

swing_state swing_shoot(double lt, double lw) {
    namespace ode = boost::numeric::odeint;
    swing_state x{0.0, 0.0, lt, lw, 0.0};
    const auto rhs = [](const swing_state& y, swing_state& d, double) {
        d = {y[1], -swing_g * std::sin(y[0]) + y[3], swing_g * std::cos(y[0]) * y[3], -y[2],
             0.5 * y[3] * y[3]};
    };
    ode::integrate_adaptive(
        ode::make_controlled<ode::runge_kutta_dopri5<swing_state>>(1e-13, 1e-13), rhs, x, 0.0,
        swing_time, 1e-3);
    return x;
}

/// Newton on the terminal conditions θ(T) = π, ω(T) = 0 (finite-difference Jacobian).
swing_state swing_indirect(double lt, double lw) {
    for (int it = 0; it < 40; ++it) {
        const swing_state e = swing_shoot(lt, lw);
        const double r0 = e[0] - std::numbers::pi, r1 = e[1];
        if (std::hypot(r0, r1) < 1e-12) break;
        const double d = 1e-7;
        const swing_state a = swing_shoot(lt + d, lw), b = swing_shoot(lt, lw + d);
        const double j00 = (a[0] - e[0]) / d, j10 = (a[1] - e[1]) / d, j01 = (b[0] - e[0]) / d,
                     j11 = (b[1] - e[1]) / d, det = j00 * j11 - j01 * j10;
        lt -= (j11 * r0 - j01 * r1) / det;
        lw -= (-j10 * r0 + j00 * r1) / det;
    }
    swing_state e = swing_shoot(lt, lw);
    e[2] = lt; // the initial costates found
    e[3] = lw;
    return e;
}

struct swing_run {
    optimal::trajectory path;
    optimal::nlp_result result;
};

/// DMOC from the guess θ(t) = π t/T + amplitude sin(π t/T).
swing_run swing_solve(const scheme_spec& spec, int steps, double amplitude) {
    optimal::control_problem p;
    p.time = swing_time;
    p.steps = steps;
    p.scheme = spec;
    p.q_start = p.v_start = p.v_end = Eigen::VectorXd::Zero(1);
    p.q_end = Eigen::VectorXd::Constant(1, std::numbers::pi);
    const auto tr = optimal::transcribe(swing_pendulum, swing_torque{}, p);
    const Eigen::VectorXd x0 = tr->start_along([&](double t) {
        const double s = std::numbers::pi * t / swing_time;
        return Eigen::VectorXd::Constant(1, s + amplitude * std::sin(s));
    });
    const auto r = optimal::solve(*tr, {}, &x0);
    return {tr->unpack(r), r};
}

TEST(OptimalSwingUp, TwoExtremalsAgreeWithTheIndirectSolution) {
    // Measured: the guesses with amplitude 0 and 2 reach the extremal that rises directly
    // (θ ≥ 0, J = 34.0653), amplitude −2 the one that first swings back to θ ≈ −0.53
    // (J = 32.7385, the lower of the two). Each against its own shooting solution.
    for (const double amplitude : {0.0, -2.0}) {
        const auto coarse = swing_solve(scheme_kind::simpson, 20, amplitude);
        const auto fine = swing_solve(scheme_kind::simpson, 40, amplitude);
        ASSERT_EQ(fine.result.verdict, optimal::status::solved) << fine.result.message;
        const auto& c = fine.path.costate;
        const double h = swing_time / 40;
        const swing_state ref =
            swing_indirect(-(-3 * c(0, 0) + 4 * c(0, 1) - c(0, 2)) / (2 * h), c(0, 0));
        // The shooting converged: θ(T) = π, ω(T) = 0 to its stopping test (1e-12) and the
        // integrator's 1e-13 controls.
        EXPECT_NEAR(ref[0], std::numbers::pi, 1e-11) << amplitude;
        EXPECT_NEAR(ref[1], 0.0, 1e-11) << amplitude;
        const double e_coarse = std::abs(coarse.path.cost - ref[4]),
                     e_fine = std::abs(fine.path.cost - ref[4]);
        EXPECT_NEAR(std::log2(e_coarse / e_fine), 4.0, 0.3) << amplitude; // Simpson: order 4
        EXPECT_LT(e_fine / ref[4], 2e-6) << amplitude;
        EXPECT_NEAR(fine.path.costate(0, 0), ref[3], 1e-4) << amplitude; // λ_ω(0) = u(0)
        if (amplitude == 0.0) {
            EXPECT_NEAR(ref[4], 34.0653, 1e-4);
            EXPECT_GE(fine.path.q.minCoeff(), -1e-9);
        } else {
            EXPECT_NEAR(ref[4], 32.7385, 1e-4);
            EXPECT_LT(fine.path.q.minCoeff(), -0.5);
        }
    }
}

TEST(OptimalSwingUp, ClosureOnTheNonlinearProblem) {
    const auto run = swing_solve({scheme_kind::gauss, 2}, 30, 0.0);
    ASSERT_TRUE(run.result.converged());
    const Eigen::MatrixXd nodes = optimal::replay(swing_pendulum, swing_torque{}, run.path);
    EXPECT_LT((nodes.topRows(1) - run.path.q).cwiseAbs().maxCoeff(), 1e-10);
    EXPECT_LT(std::abs(nodes(0, 30) - std::numbers::pi), 1e-10);
}

TEST(OptimalSwingUp, DerivativesMatchFiniteDifferences) {
    // At an arbitrary point (not a solution): ∂g/∂x and the Hessian of σJ + λᵀg against
    // central differences of g and of σ∇J + (∂g/∂x)ᵀλ, step 1e-6 (error O(1e-12) + round-off
    // O(1e-10) on entries of size ≤ 1e2).
    optimal::control_problem p;
    p.time = swing_time;
    p.steps = 3;
    p.scheme = {scheme_kind::gauss, 2};
    p.q_start = p.v_start = p.v_end = Eigen::VectorXd::Zero(1);
    p.q_end = Eigen::VectorXd::Constant(1, 3.0);
    const auto tr = optimal::transcribe(swing_pendulum, swing_torque{}, p);
    const Eigen::VectorXd x =
        Eigen::VectorXd::LinSpaced(tr->variables(), 0.3, 2.9).array().sin() + 0.5;
    const auto e = optimal_test::check_derivatives(
        *tr, x, 0.7, Eigen::VectorXd::LinSpaced(tr->constraints(), -1.0, 2.0));
    // The cost's gradient too (measured 2.5e-10: the differences' round-off, ε|J|/step).
    EXPECT_LT(e.gradient, 1e-8);
    EXPECT_LT(e.jacobian, 1e-7);
    EXPECT_LT(e.hessian, 1e-7);
    EXPECT_GT(e.largest_hessian, 1.0); // not vacuous: L's third derivatives are there
}

TEST(OptimalSwingUp, MeshRefinementFollowsOneExtremal) {
    // From N = 10 by doublings to 40, the refined solve reaches the direct one's optimum (the
    // extremal that rises directly) to the solver's tolerance, in fewer iterations at N = 40.
    const auto make = [](int n) {
        optimal::control_problem p;
        p.time = swing_time;
        p.steps = n;
        p.q_start = p.v_start = p.v_end = Eigen::VectorXd::Zero(1);
        p.q_end = Eigen::VectorXd::Constant(1, std::numbers::pi);
        return std::unique_ptr<optimal::transcription>(
            optimal::transcribe(swing_pendulum, swing_torque{}, p));
    };
    const auto refined = optimal::solve_refined(make, 40, 2);
    ASSERT_EQ(refined.steps, (std::vector<int>{10, 20, 40}));
    ASSERT_EQ(refined.result.verdict, optimal::status::solved);
    const auto direct = swing_solve(scheme_kind::simpson, 40, 0.0);
    EXPECT_NEAR(refined.result.cost, direct.path.cost, 1e-9);
    EXPECT_LT(refined.iterations.back(), direct.result.iterations);
    // start_from reproduces a trajectory of the same N: its own solution is already optimal.
    const auto same = make(40);
    const auto x0 = same->start_from(direct.path);
    const auto again = optimal::solve(*same, {}, &x0);
    EXPECT_LE(again.iterations, 3);
}

TEST(OptimalSwingUp, ProgressCallbackStopsTheSolver) {
    optimal::control_problem p;
    p.time = swing_time;
    p.steps = 20;
    p.q_start = p.v_start = p.v_end = Eigen::VectorXd::Zero(1);
    p.q_end = Eigen::VectorXd::Constant(1, std::numbers::pi);
    const auto tr = optimal::transcribe(swing_pendulum, swing_torque{}, p);
    optimal::solver_options o;
    int seen = 0;
    o.progress = [&](const optimal::iteration& it) {
        seen = it.number;
        return it.number < 2;
    };
    const auto r = optimal::solve(*tr, o);
    EXPECT_EQ(r.verdict, optimal::status::interrupted);
    EXPECT_EQ(seen, 2);
    EXPECT_EQ(r.x.size(), tr->variables());
}

// The same swing-up with the pendulum in Cartesian coordinates on the circle x² + y² = 1 (a
// holonomic constraint, L = ½|q̇|² − g y) and a force (u_x, u_y) on the bob: its normal part is
// taken up by the constraint and costs effort for nothing, so the optimum pushes along the
// circle, u_t = the angle formulation's torque (l = 1), and the optimal cost is the same.
struct swing_cartesian {
    static constexpr int dim = 2;
    template <class T>
    T operator()(const tvec<T, 2>& q, const tvec<T, 2>& v) const {
        return 0.5 * (v(0) * v(0) + v(1) * v(1)) - swing_g * q(1);
    }
};
struct swing_circle {
    static constexpr int dim = 2, count = 1;
    template <class T>
    tvec<T, 1> operator()(const tvec<T, 2>& q) const {
        return tvec<T, 1>(q(0) * q(0) + q(1) * q(1) - 1.0);
    }
};

optimal::control_problem swing_cartesian_problem(const scheme_spec& spec, int steps) {
    optimal::control_problem p;
    p.time = swing_time;
    p.steps = steps;
    p.scheme = spec;
    p.q_start = Eigen::Vector2d(0.0, -1.0);
    p.q_end = Eigen::Vector2d(0.0, 1.0);
    p.v_start = p.v_end = Eigen::VectorXd::Zero(2);
    return p;
}

swing_run swing_cartesian_solve(const scheme_spec& spec, int steps) {
    const auto tr =
        optimal::transcribe(swing_cartesian{}, swing_circle{}, optimal_test::direct_input<2>{},
                            swing_cartesian_problem(spec, steps));
    const Eigen::VectorXd x0 = tr->start_along([](double t) { // the direct rise, θ = π t/T
        const double s = std::numbers::pi * t / swing_time;
        return Eigen::VectorXd(Eigen::Vector2d(std::sin(s), -std::cos(s)));
    });
    const auto r = optimal::solve(*tr, {}, &x0);
    auto path = tr->unpack(r);
    const auto closure = optimal::check_closure(*tr, path);
    EXPECT_LT(closure.error, 1e-9) << closure.failure; // the constrained engine's replay
    return {std::move(path), r};
}

TEST(OptimalSwingUp, ConstrainedCartesianPendulumReachesTheSameExtremal) {
    const auto angle = swing_solve(scheme_kind::simpson, 40, 0.0);
    const auto& c = angle.path.costate;
    const double h = swing_time / 40;
    const swing_state ref =
        swing_indirect(-(-3 * c(0, 0) + 4 * c(0, 1) - c(0, 2)) / (2 * h), c(0, 0));
    EXPECT_NEAR(ref[0], std::numbers::pi, 1e-11); // the shooting converged (as above)
    EXPECT_NEAR(ref[1], 0.0, 1e-11);
    const auto coarse = swing_cartesian_solve(scheme_kind::simpson, 20);
    const auto fine = swing_cartesian_solve(scheme_kind::simpson, 40);
    ASSERT_EQ(fine.result.verdict, optimal::status::solved) << fine.result.message;
    const double e_coarse = std::abs(coarse.path.cost - ref[4]),
                 e_fine = std::abs(fine.path.cost - ref[4]);
    std::printf("Cartesian pendulum on the circle, Simpson N = 20 -> 40: cost %.9f, error "
                "%.2e -> %.2e (order %.2f); indirect %.9f\n",
                fine.path.cost, e_coarse, e_fine, std::log2(e_coarse / e_fine), ref[4]);
    EXPECT_NEAR(std::log2(e_coarse / e_fine), 4.0, 0.3);
    EXPECT_LT(e_fine / ref[4], 5e-6); // measured 3.5e-6: 4× the angle formulation's constant
    for (Eigen::Index n = 0; n < fine.path.q.cols(); ++n) { // on the circle, moving along it
        EXPECT_NEAR(fine.path.q.col(n).squaredNorm(), 1.0, 1e-12) << n;
        EXPECT_NEAR(fine.path.q.col(n).dot(fine.path.v.col(n)), 0.0, 1e-9) << n;
    }
    // The push along the circle is the torque: u(0) = λ_ω(0), as in the angle formulation.
    const Eigen::Vector2d q0 = fine.path.position(fine.path.control_times(0));
    const double along = fine.path.u(0, 0) * -q0(1) + fine.path.u(1, 0) * q0(0);
    // At t = (c₁ = 0) h: Simpson's first point is the start. Measured 3.3e-7 (N = 40 against the
    // continuous extremal); budget 30×.
    EXPECT_NEAR(along, ref[3], 1e-5);
}

TEST(OptimalSwingUp, ConstrainedDerivativesMatchFiniteDifferences) {
    // The impulses −G(Q)ᵀΛ, g(Q) = 0 and their second derivatives (g's third, through the
    // dual numbers) against central differences, at an arbitrary point.
    const auto tr =
        optimal::transcribe(swing_cartesian{}, swing_circle{}, optimal_test::direct_input<2>{},
                            swing_cartesian_problem({scheme_kind::gauss, 2}, 3));
    EXPECT_EQ(tr->variables(), 7 * 2 + 6 * 2 + 7 * 1);
    EXPECT_EQ(tr->constraints(), 7 * 2 + 5 * 1);
    const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(tr->variables(), 0.3, 2.9).array().sin();
    const auto e = optimal_test::check_derivatives(
        *tr, x, 0.7, Eigen::VectorXd::LinSpaced(tr->constraints(), -1.0, 2.0));
    EXPECT_LT(e.gradient, 1e-8); // measured 7e-11: the differences' round-off
    EXPECT_LT(e.jacobian, 1e-7);
    EXPECT_LT(e.hessian, 1e-7);
    EXPECT_GT(e.largest_hessian, 1.0);
}

TEST(OptimalSwingUp, RefusesBoundaryStatesOffTheConstraints) {
    const auto refused = [](const optimal::control_problem& p, const char* what) {
        try {
            (void)optimal::transcribe(swing_cartesian{}, swing_circle{},
                                      optimal_test::direct_input<2>{}, p);
            ADD_FAILURE() << "accepted: " << what;
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
        }
    };
    auto p = swing_cartesian_problem(scheme_kind::simpson, 10);
    p.q_start(1) = -1.1;
    refused(p, "the start position violates the constraints");
    p = swing_cartesian_problem(scheme_kind::simpson, 10);
    p.v_end(1) = 0.5; // across the circle at the top
    refused(p, "the end velocity is not tangent");
    p = swing_cartesian_problem(scheme_kind::simpson, 10);
    p.free_end_velocity = {true, true};
    refused(p, "free final state with holonomic constraints");
}

} // namespace
