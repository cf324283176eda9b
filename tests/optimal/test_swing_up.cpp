// DMOC on a nonlinear problem against an indirect solution: the pendulum swing-up (m = l = 1,
// g = 9.81, T = 2, from hanging at rest to upright at rest, minimising ∫ u²/2). The reference
// solves Pontryagin's boundary value problem (θ̇ = ω, ω̇ = −g sin θ + λ_ω, λ̇_θ = g cos θ λ_ω,
// λ̇_ω = −λ_θ, u = λ_ω) by shooting on (λ_θ(0), λ_ω(0)) with Boost.Odeint's Dormand–Prince at
// 1e-13, seeded from DMOC's costates: a different integrator and a different method. Also the
// exact first and second derivatives against finite differences, and a stop from the callback.
#include <array>
#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include <boost/numeric/odeint.hpp>
#include <gtest/gtest.h>

#include "optimal/fixtures.hpp"
#include "varsym/optimal/dmoc.hpp"
#include "varsym/optimal/replay.hpp"
#include "varsym/optimal/solve.hpp"

namespace {

using namespace varsym;
constexpr double swing_g = 9.81, swing_time = 2.0;

struct swing_pendulum {
    static constexpr int dim = 1;
    template <class T>
    T operator()(const tvec<T, 1>& q, const tvec<T, 1>& v) const {
        using std::cos;
        return 0.5 * v(0) * v(0) + swing_g * cos(q(0));
    }
};
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
    const auto tr = optimal::transcribe(swing_pendulum{}, swing_torque{}, p);
    Eigen::VectorXd x0 = tr->start();
    const int points = steps * tr->table().degree + 1;
    for (int g = 0; g < points; ++g) {
        const double s = std::numbers::pi * g / (points - 1);
        x0(g) = s + amplitude * std::sin(s);
    }
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
    const Eigen::MatrixXd nodes = optimal::replay(swing_pendulum{}, swing_torque{}, run.path);
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
    const auto tr = optimal::transcribe(swing_pendulum{}, swing_torque{}, p);
    const Eigen::VectorXd x =
        Eigen::VectorXd::LinSpaced(tr->variables(), 0.3, 2.9).array().sin() + 0.5;
    const auto e = optimal_test::check_derivatives(
        *tr, x, 0.7, Eigen::VectorXd::LinSpaced(tr->constraints(), -1.0, 2.0));
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
            optimal::transcribe(swing_pendulum{}, swing_torque{}, p));
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
    const auto tr = optimal::transcribe(swing_pendulum{}, swing_torque{}, p);
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

} // namespace
