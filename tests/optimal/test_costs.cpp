// The running costs on a fully actuated two-link arm in a vertical plane (uniform links of 1 kg
// and 1 m, joint torques u = τ): the gradients and Hessians against finite differences (also of
// a free final state's terms), and the
// invariant cost ∫ ½ τᵀM⁻¹τ against the effort ∫ ½ |τ|² on the same rest-to-rest motion, the
// comparison of Rojas-Quintero et al. (Mathematics 10(7), 1117, 2022).
#include <cmath>
#include <cstdio>
#include <numbers>

#include <gtest/gtest.h>

#include "optimal/fixtures.hpp"
#include "varsym/optimize/solve.hpp"
#include "varsym/optimize/transcribe.hpp"
#include "varsym/problems/linked_pendulum.hpp"

namespace {

using namespace varsym;

using optimal_test::two_link;
using joint_torques = optimal_test::direct_input<2>;

optimal::control_problem arm_problem(const optimal::cost_weights& w) {
    optimal::control_problem p;
    p.time = 1.0;
    p.steps = 40;
    p.q_start = p.v_start = p.v_end = Eigen::VectorXd::Zero(2);
    p.q_end = Eigen::Vector2d(std::numbers::pi / 2, std::numbers::pi / 2);
    p.cost = w;
    return p;
}

TEST(OptimalCosts, GradientsAndHessiansMatchFiniteDifferences) {
    for (const optimal::cost_weights& w :
         {optimal::cost_weights{.effort = 0.0, .invariant = 1.0},
          optimal::cost_weights{.effort = 0.5, .power = 2.0, .power_smoothing = 0.1}}) {
        auto p = arm_problem(w);
        p.steps = 3;
        p.scheme = {scheme_kind::gauss, 2};
        const auto tr = optimal::transcribe(two_link{}, joint_torques{}, p);
        const Eigen::VectorXd x =
            Eigen::VectorXd::LinSpaced(tr->variables(), 0.2, 3.1).array().cos() * 1.5;
        // The Hessian of σJ alone (λ = 0).
        const auto e =
            optimal_test::check_derivatives(*tr, x, 1.0, Eigen::VectorXd::Zero(tr->constraints()));
        Eigen::VectorXd g;
        tr->cost_gradient(x, g);
        EXPECT_LT(e.gradient, 1e-7 * std::max(1.0, g.cwiseAbs().maxCoeff()));
        EXPECT_EQ(tr->has_hessian(), w.invariant == 0.0);
        if (tr->has_hessian()) {
            EXPECT_LT(e.hessian, 1e-6 * std::max(1.0, e.largest_hessian));
        }
    }
}

TEST(OptimalCosts, FreeFinalStateDerivativesMatchFiniteDifferences) {
    // On the two-link arm (∂L/∂q̇ depends on q): the end's −∂L/∂q̇(Q_N, v_N) and its third
    // derivatives, and the terminal cost.
    auto p = arm_problem({});
    p.steps = 3;
    p.scheme = {scheme_kind::gauss, 2};
    p.free_end_position = {true, false};
    p.free_end_velocity = {true, true};
    p.cost.terminal_position = Eigen::Vector2d(3.0, 0.0);
    p.cost.terminal_velocity = Eigen::Vector2d(0.5, 2.0);
    const auto tr =
        optimal::transcribe(optimal_test::two_link{}, optimal_test::direct_input<2>{}, p);
    EXPECT_EQ(tr->variables(), 7 * 2 + 6 * 2 + 2);
    const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(tr->variables(), 0.3, 2.9).array().sin();
    const auto e = optimal_test::check_derivatives(
        *tr, x, 0.7, Eigen::VectorXd::LinSpaced(tr->constraints(), -1.0, 2.0));
    EXPECT_LT(e.gradient, 1e-7);
    EXPECT_LT(e.jacobian, 1e-7);
    EXPECT_LT(e.hessian, 1e-7);
    EXPECT_GT(e.largest_hessian, 1.0);
}

/// Joint torques on a chain in absolute angles: f = Bᵀu, f_i = u_i − u_{i+1}.
struct chain_torques {
    static constexpr int dim = 3, controls = 3;
    template <class T>
    tvec<T, 3> operator()(const tvec<T, 3>&, const tvec<T, 3>&, double, const tvec<T, 3>& u) const {
        return tvec<T, 3>(u(0) - u(1), u(1) - u(2), u(2));
    }
};

TEST(OptimalCosts, ExactHessianOfALagrangianWrittenWithDoubleConstants) {
    // linked_pendulum's L starts from T l(0.0): its third derivatives go through the dual
    // numbers of third_order.hpp. The Hessian of λᵀg against differences of Jᵀλ.
    optimal::control_problem p;
    p.time = 1.0;
    p.steps = 2;
    p.scheme = {scheme_kind::lobatto, 3};
    p.q_start = p.v_start = p.v_end = Eigen::VectorXd::Zero(3);
    p.q_end = Eigen::Vector3d(0.5, 1.0, 1.5);
    const linked_pendulum::lagrangian<3> chain({1.0, 0.8, 0.5}, {1.0, 0.7, 0.4}, 9.81);
    const auto tr = optimal::transcribe(chain, chain_torques{}, p);
    const auto e = optimal_test::check_derivatives(
        *tr, Eigen::VectorXd::LinSpaced(tr->variables(), 0.1, 2.3).array().sin(), 0.0,
        Eigen::VectorXd::LinSpaced(tr->constraints(), -1.5, 1.0));
    EXPECT_LT(e.gradient, 1e-8); // measured 1.1e-10: the differences' round-off, ε|J|/step
    // Lobatto's ℓ_i(c_j) = δ_ij: the controls' blocks hold one node per point.
    EXPECT_LT(e.jacobian, 1e-7 * e.largest_jacobian);
    EXPECT_LT(e.hessian, 1e-6 * e.largest_hessian);
    EXPECT_GT(e.largest_hessian, 1.0);
}

struct arm_measures {
    double cost, energy, power, amplitude; // ∫½|τ|², ∫ Σ|τ_i q̇_i| dt, max_t |q2(t)|
    Eigen::VectorXd x;                     // the optimum's unknowns
};

arm_measures arm_solve(const optimal::cost_weights& w) {
    const auto tr = optimal::transcribe(two_link{}, joint_torques{}, arm_problem(w));
    const auto r = optimal::solve(*tr);
    EXPECT_TRUE(r.converged()) << r.message;
    const auto path = tr->unpack(r);
    arm_measures m{path.cost, 0.0, 0.0, 0.0, r.x};
    // The joint power and the effort at the controls' (Lobatto) points, by the same quadrature;
    // q̇ from the dense output's slope.
    const auto& t = path.control_times;
    const std::vector<double> wq = {1.0 / 6, 4.0 / 6, 1.0 / 6}; // Simpson's weights
    for (Eigen::Index c = 0; c < t.size(); ++c) {
        const double dt = 1e-6;
        const Eigen::VectorXd v =
            (path.position(std::min(t(c) + dt, 1.0)) - path.position(std::max(t(c) - dt, 0.0))) /
            (std::min(t(c) + dt, 1.0) - std::max(t(c) - dt, 0.0));
        const double weight = path.h * wq[static_cast<std::size_t>(c % 3)];
        m.energy += weight * 0.5 * path.u.col(c).squaredNorm();
        m.power += weight * (path.u.col(c).array() * v.array()).abs().sum();
    }
    for (int i = 0; i <= 400; ++i)
        m.amplitude = std::max(m.amplitude, std::abs(path.position(i / 400.0)(1)));
    return m;
}

TEST(OptimalCosts, InvariantAgainstEffortOnTheSameMotion) {
    const auto effort = arm_solve({.effort = 1.0});
    const auto invariant = arm_solve({.effort = 0.0, .invariant = 1.0});
    std::printf("effort-optimal:    int |tau|^2/2 = %.4f, joint power int sum |tau q'| = %.4f, "
                "max |q2| = %.4f\n",
                effort.energy, effort.power, effort.amplitude);
    std::printf("invariant-optimal: int |tau|^2/2 = %.4f, joint power int sum |tau q'| = %.4f, "
                "max |q2| = %.4f\n",
                invariant.energy, invariant.power, invariant.amplitude);
    // Each optimum is best at its own cost, both ways: each problem's cost evaluated on the
    // other's optimum (the same unknowns and constraints: a feasible point of both) is higher.
    EXPECT_NEAR(effort.energy, effort.cost, 1e-9 * effort.cost);
    EXPECT_LT(effort.energy, invariant.energy);
    const auto effort_nlp =
        optimal::transcribe(two_link{}, joint_torques{}, arm_problem({.effort = 1.0}));
    const auto invariant_nlp = optimal::transcribe(two_link{}, joint_torques{},
                                                   arm_problem({.effort = 0.0, .invariant = 1.0}));
    ASSERT_EQ(effort.x.size(), invariant_nlp->variables());
    ASSERT_EQ(invariant.x.size(), effort_nlp->variables());
    const double effort_at_own = effort_nlp->cost(effort.x),
                 effort_at_other = effort_nlp->cost(invariant.x),
                 invariant_at_own = invariant_nlp->cost(invariant.x),
                 invariant_at_other = invariant_nlp->cost(effort.x);
    std::printf("effort cost %.6f at its optimum, %.6f at the invariant one; invariant cost "
                "%.6f at its optimum, %.6f at the effort one\n",
                effort_at_own, effort_at_other, invariant_at_own, invariant_at_other);
    EXPECT_NEAR(effort_at_own, effort.cost, 1e-12 * effort.cost);
    EXPECT_NEAR(invariant_at_own, invariant.cost, 1e-12 * invariant.cost);
    EXPECT_LT(effort_at_own, effort_at_other);
    EXPECT_LT(invariant_at_own, invariant_at_other);
    // The comparison the authors made, measured here (40 Simpson steps): the invariant optimum
    // spends less joint power (28.92 against 31.06 J) and swings the elbow less (max |q2| 2.11
    // against 2.69 rad), as they report for their arms.
    EXPECT_LT(invariant.power, 0.95 * effort.power);
    EXPECT_LT(invariant.amplitude, 0.85 * effort.amplitude);
}

} // namespace
