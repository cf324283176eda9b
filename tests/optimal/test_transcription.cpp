// DMOC on a linear-quadratic problem with a closed form: the minimum-effort transfer of a
// harmonic oscillator (ω = 1) from rest at q = 0 to rest at q = 1 in T = 2, whose optimal
// control, costate and cost follow from the controllability Gramian (Kirk, Optimal Control
// Theory, §5.2; docs/optimal_control.md): u(t) = λ_p(t) = Bᵀ e^{Aᵀ(T−t)} W⁻¹ d,
// J = ½ dᵀ W⁻¹ d, d = x_T − e^{AT} x_0. Also: the closure against the general engine, the
// derivatives against finite differences, and the refusals.
#include <cmath>
#include <cstdio>
#include <numbers>

#include <gtest/gtest.h>

#include "optimal/fixtures.hpp"
#include "varsym/optimal/replay.hpp"
#include "varsym/optimize/solve.hpp"
#include "varsym/optimize/transcribe.hpp"

namespace {

using namespace varsym;

const optimal_test::one_dof lq_oscillator{.spring = 1.0};
const optimal_test::direct_input<1> lq_nowhere{.gain = 0.0}; // an input that acts on nothing
using lq_push = optimal_test::direct_input<1>;

constexpr double lq_time = 2.0;

/// The closed form: λ_p(t) and J; with a free final state, ν and J from stationarity.
struct lq_exact {
    Eigen::Matrix2d w;
    Eigen::Vector2d nu, d;
    double cost = 0.0;
    lq_exact() {
        const double t = lq_time, s = std::sin(t), c = std::cos(t);
        // W = ∫₀ᵀ e^{Aσ} B Bᵀ e^{Aᵀσ} dσ, A = [0 1; −1 0], B = (0, 1)
        w << t / 2 - std::sin(2 * t) / 4, s * s / 2, s * s / 2, t / 2 + std::sin(2 * t) / 4;
        Eigen::Matrix2d e; // e^{AT}
        e << c, s, -s, c;
        d = Eigen::Vector2d(1.0, 0.0) - e * Eigen::Vector2d::Zero();
        nu = w.ldlt().solve(d);
        cost = 0.5 * d.dot(nu);
    }
    /// The final state free, with the terminal cost ½(x(T) − x_T)ᵀA(x(T) − x_T): x(T) = e^{AT}x₀
    /// + Wν and ½νᵀWν + ½(Wν − d)ᵀA(Wν − d) stationary: (I + AW)ν = A d.
    void soft_end(const Eigen::Matrix2d& a) {
        nu = (Eigen::Matrix2d::Identity() + a * w).lu().solve(a * d);
        const Eigen::Vector2d miss = w * nu - d;
        cost = 0.5 * nu.dot(w * nu) + 0.5 * miss.dot(a * miss);
    }
    /// q(T) fixed, q̇(T) free and unweighted: its costate vanishes at T, ν = (d₁/W₁₁, 0).
    void free_end_velocity() {
        nu = Eigen::Vector2d(d(0) / w(0, 0), 0.0);
        cost = 0.5 * nu.dot(w * nu);
    }
    [[nodiscard]] double costate(double t) const { // (e^{Aᵀ(T−t)} ν)_p
        const double r = lq_time - t;
        return std::sin(r) * nu(0) + std::cos(r) * nu(1);
    }
};

optimal::control_problem lq_problem(const scheme_spec& spec, int steps) {
    optimal::control_problem p;
    p.time = lq_time;
    p.steps = steps;
    p.scheme = spec;
    p.q_start = p.v_start = p.v_end = Eigen::VectorXd::Zero(1);
    p.q_end = Eigen::VectorXd::Ones(1);
    return p;
}

struct lq_errors {
    double cost, costate;
    int iterations;
};

/// The end free (terminal weights a on q, b on q̇; free_velocity: q(T) fixed, q̇(T) free).
struct lq_end {
    bool free = false, free_velocity = false;
    double a = 0.0, b = 0.0;
};

lq_errors lq_solve(const scheme_spec& spec, int steps,
                   optimal::hessian_kind hessian = optimal::hessian_kind::automatic,
                   const lq_end& end = {}) {
    lq_exact exact;
    auto problem = lq_problem(spec, steps);
    if (end.free) {
        exact.soft_end(Eigen::Vector2d(end.a, end.b).asDiagonal());
        problem.free_end_position = problem.free_end_velocity = {true};
        problem.cost.terminal_position = Eigen::VectorXd::Constant(1, end.a);
        problem.cost.terminal_velocity = Eigen::VectorXd::Constant(1, end.b);
    } else if (end.free_velocity) {
        exact.free_end_velocity();
        problem.free_end_velocity = {true};
    }
    const auto tr = optimal::transcribe(lq_oscillator, lq_push{}, problem);
    optimal::solver_options o;
    o.hessian = hessian;
    const auto r = optimal::solve(*tr, o);
    EXPECT_EQ(r.verdict, optimal::status::solved) << r.message;
    const auto path = tr->unpack(r);
    double costate = 0.0;
    for (Eigen::Index n = 0; n < path.node_times.size(); ++n)
        costate =
            std::max(costate, std::abs(path.costate(0, n) - exact.costate(path.node_times(n))));
    return {std::abs(path.cost - exact.cost), costate, r.iterations};
}

struct lq_member {
    scheme_spec spec;
    int steps; // coarse enough that the finer error stays far above round-off
};

TEST(OptimalLinearQuadratic, CostAndCostatesConvergeAtOrderTwoS) {
    // Theory (docs/optimal_control.md): the discrete adjoint of a Galerkin variational
    // integrator with controls at its quadrature points is the same symplectic partitioned
    // Runge–Kutta scheme, so cost and costates at the nodes converge at the state's order 2s.
    for (const lq_member m : {lq_member{scheme_kind::newmark, 10},
                              {scheme_kind::simpson, 10},
                              {{scheme_kind::gauss, 2}, 10},
                              {{scheme_kind::gauss, 3}, 5},
                              {{scheme_kind::gauss, 4}, 3},
                              {{scheme_kind::lobatto, 3}, 5},
                              {{scheme_kind::lobatto, 4}, 3}}) {
        const auto coarse = lq_solve(m.spec, m.steps), fine = lq_solve(m.spec, 2 * m.steps);
        const double order = m.spec.order();
        EXPECT_NEAR(std::log2(coarse.cost / fine.cost), order, 0.3) << m.spec.label();
        EXPECT_NEAR(std::log2(coarse.costate / fine.costate), order, 0.3) << m.spec.label();
        EXPECT_GT(fine.cost, 1e-14) << m.spec.label() << ": an order fitted on round-off";
        // A quadratic program: with the exact Hessian, one Newton step of IPOPT.
        EXPECT_LE(fine.iterations, 2) << m.spec.label();
    }
}

TEST(OptimalLinearQuadratic, FreeFinalStateAndTerminalCostConvergeAtOrderTwoS) {
    // The same transfer with the final state free under a terminal cost (a = 4, b = 1; the
    // closed form's ν from (I + AW)ν = A d), and with q̇(T) free and unweighted.
    for (const lq_end end : {lq_end{true, false, 4.0, 1.0}, lq_end{false, true}})
        for (const lq_member m : {lq_member{scheme_kind::newmark, 10},
                                  {scheme_kind::simpson, 10},
                                  {{scheme_kind::gauss, 3}, 5}}) {
            const auto automatic = optimal::hessian_kind::automatic;
            const auto coarse = lq_solve(m.spec, m.steps, automatic, end),
                       fine = lq_solve(m.spec, 2 * m.steps, automatic, end);
            const double order = m.spec.order();
            std::printf("%s end %-10s: cost error %.2e -> %.2e (order %.2f), costates order %.2f\n",
                        end.free ? "soft" : "q fixed, v free", m.spec.label().c_str(), coarse.cost,
                        fine.cost, std::log2(coarse.cost / fine.cost),
                        std::log2(coarse.costate / fine.costate));
            EXPECT_NEAR(std::log2(coarse.cost / fine.cost), order, 0.3) << m.spec.label();
            EXPECT_NEAR(std::log2(coarse.costate / fine.costate), order, 0.3) << m.spec.label();
            EXPECT_GT(fine.cost, 1e-14) << m.spec.label();
            EXPECT_LE(fine.iterations, 2) << m.spec.label(); // still a quadratic program
        }
}

TEST(OptimalLinearQuadratic, LimitedMemoryReachesTheSameOptimum) {
    const auto exact = lq_solve(scheme_kind::simpson, 20, optimal::hessian_kind::exact);
    const auto bfgs = lq_solve(scheme_kind::simpson, 20, optimal::hessian_kind::limited_memory);
    EXPECT_NEAR(bfgs.cost, exact.cost, 1e-11);
    EXPECT_GT(bfgs.iterations, exact.iterations); // it is a different iteration
}

TEST(OptimalLinearQuadratic, ClosureAgainstTheGeneralEngine) {
    // The optimal controls replayed by the general engine's own step solver reproduce the
    // optimal nodes to round-off; the same controls shifted by 1e-6 do not (negative control).
    for (const scheme_spec spec :
         {scheme_spec(scheme_kind::simpson), scheme_spec(scheme_kind::newmark),
          scheme_spec(scheme_kind::gauss, 3)}) {
        const auto tr = optimal::transcribe(lq_oscillator, lq_push{}, lq_problem(spec, 20));
        const auto r = optimal::solve(*tr);
        ASSERT_TRUE(r.converged());
        auto path = tr->unpack(r);
        const Eigen::MatrixXd nodes = optimal::replay(lq_oscillator, lq_push{}, path);
        EXPECT_LT((nodes.topRows(1) - path.q).cwiseAbs().maxCoeff(), 1e-12) << spec.label();
        EXPECT_LT((nodes.bottomRows(1) - path.p).cwiseAbs().maxCoeff(), 1e-12) << spec.label();
        path.u.array() += 1e-6;
        const Eigen::MatrixXd off = optimal::replay(lq_oscillator, lq_push{}, path);
        EXPECT_GT((off.topRows(1) - nodes.topRows(1)).cwiseAbs().maxCoeff(), 1e-8);
    }
}

TEST(OptimalInput, RefusesWhatCannotBeSolved) {
    auto p = lq_problem(scheme_kind::simpson, 10);
    const auto refused = [](const optimal::control_problem& q, const char* what) {
        try {
            (void)optimal::transcribe(lq_oscillator, lq_push{}, q);
            ADD_FAILURE() << "accepted: " << what;
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
        }
    };
    auto q = p;
    q.time = 0.0;
    refused(q, "time horizon must be positive");
    q = p;
    q.time = std::nan("");
    refused(q, "time horizon must be positive");
    q = p;
    q.q_end(0) = std::nan("");
    refused(q, "the end position must be finite");
    q = p;
    q.v_start = Eigen::VectorXd::Zero(2);
    refused(q, "the start velocity has 2 entries");
    q = p;
    q.control_lower = Eigen::VectorXd::Constant(1, 1.0);
    q.control_upper = Eigen::VectorXd::Constant(1, -1.0);
    refused(q, "control bounds are empty");
    q = p;
    q.position_upper = Eigen::VectorXd::Constant(1, 0.5);
    refused(q, "boundary position lies outside");
    q = p;
    q.effort = -Eigen::MatrixXd::Identity(1, 1);
    refused(q, "positive definite");
    q = p;
    q.cost.terminal_position = Eigen::VectorXd::Ones(1);
    refused(q, "terminal cost on a fixed final coordinate");
    q = p;
    q.free_end_velocity = {true, false};
    refused(q, "free final velocities has 2 flags");
    try {
        (void)optimal::transcribe(lq_oscillator, lq_nowhere, p);
        ADD_FAILURE() << "accepted an input that acts on nothing";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("do not act"), std::string::npos) << e.what();
    }
}

TEST(OptimalInput, UnreachableTargetIsReportedInfeasible) {
    // |u| ≤ 0.01 cannot move the oscillator from 0 to 1 in 2 s (|q| ≤ 0.01 (1 − cos 2) < 0.02).
    auto p = lq_problem(scheme_kind::simpson, 20);
    p.control_lower = Eigen::VectorXd::Constant(1, -0.01);
    p.control_upper = Eigen::VectorXd::Constant(1, 0.01);
    const auto tr = optimal::transcribe(lq_oscillator, lq_push{}, p);
    const auto r = optimal::solve(*tr);
    EXPECT_FALSE(r.converged());
    EXPECT_EQ(r.verdict, optimal::status::infeasible) << r.message;
    EXPECT_EQ(r.x.size(), tr->variables()); // the last iterate is kept
}

} // namespace
