// tests/multibody/test_articulated_iteration.cpp: the general engine's articulated iteration
// (schemes/variational_articulated.hpp) on robots. It solves the same step equations as Newton,
// so the reference is Newton's step from the same state: the two must agree to the round-off of
// the step's equations, on free motion, under forces, with mimic joints, over a run, and where the
// iteration cannot converge (the step then goes to Newton).
#include <cmath>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "multibody/random_tree.hpp"
#include "varsym/multibody/lagrangian.hpp"
#include "varsym/schemes/variational.hpp"
#include "varsym/systems/forcing.hpp"

namespace {

using namespace varsym;
using tree_lagrangian = multibody::robot_lagrangian;
using tree_system = lagrangian_system<tree_lagrangian>;

tree_system system_of(const multibody::tree& m) {
    return tree_system(tree_lagrangian(std::make_shared<const multibody::tree>(m)));
}

newton_options with_iteration(iteration_kind kind) {
    newton_options o;
    o.iteration = kind;
    return o;
}

phase_state<dynamic> moving_start(int n) {
    return {Eigen::VectorXd::LinSpaced(n, -0.8, 0.9), Eigen::VectorXd::LinSpaced(n, 1.0, -0.7)};
}

/// A constant torque (the gravity torques at one pose: the robot held there).
struct holding_torque {
    static constexpr int dim = dynamic;
    Eigen::VectorXd tau;
    Eigen::VectorXd operator()(const Eigen::VectorXd&, const Eigen::VectorXd&, double) const {
        return tau;
    }
    void derivatives(const Eigen::VectorXd&, const Eigen::VectorXd&, double,
                     force_terms<dynamic>& r) const {
        r.f = tau;
        r.fq.setZero(tau.size(), tau.size());
        r.fv.setZero(tau.size(), tau.size());
    }
};

/// Not a robot: a unit oscillator with automatic derivatives.
struct plain_spring {
    static constexpr int dim = 1;
    template <class T>
    T operator()(const tvec<T, 1>& q, const tvec<T, 1>& v) const {
        return 0.5 * v(0) * v(0) - 0.5 * q(0) * q(0);
    }
};

/// The stepper with its articulated iteration callable alone (protected there): the step's
/// increments without the hand-over to Newton.
template <class F>
struct articulated_probe : general::stepper<tree_lagrangian, F> {
    using general::stepper<tree_lagrangian, F>::stepper;
    newton_report alone(const phase_state<dynamic>& x) { return this->solve_articulated(x); }
};

/// Largest difference over `steps` steps of the articulated iteration's run from Newton's, each
/// step taken from Newton's state (so the differences do not compound), relative to the state's
/// size; and the articulated steps' iterations in all.
template <class F = unforced>
std::pair<double, int> against_newton(const tree_system& sys, F force, double h,
                                      const scheme_spec& spec, int steps) {
    general::stepper<tree_lagrangian, F> newton(sys, force, h, spec,
                                                with_iteration(iteration_kind::newton));
    articulated_probe<F> art(sys, force, h, spec, with_iteration(iteration_kind::articulated));
    phase_state<dynamic> x = moving_start(sys.dimension());
    double worst = 0.0;
    int iterations = 0;
    for (int j = 0; j < steps; ++j) {
        phase_state<dynamic> y = x;
        art.set_time(newton.time());
        // The iteration alone first (it commits nothing), then the step as the run takes it.
        const newton_report alone = art.alone(y);
        EXPECT_TRUE(alone.converged) << "step " << j;
        iterations += alone.iterations;
        const newton_report a = art.step(y);
        EXPECT_TRUE(a.converged) << "step " << j;
        EXPECT_EQ(a.iterations, alone.iterations) << "step " << j;
        EXPECT_TRUE(newton.step(x).converged) << "step " << j;
        const double scale = std::max(x.q.lpNorm<Eigen::Infinity>(), 1.0) +
                             std::max(x.p.lpNorm<Eigen::Infinity>(), 1.0);
        worst = std::max(
            worst, ((y.q - x.q).lpNorm<Eigen::Infinity>() + (y.p - x.p).lpNorm<Eigen::Infinity>()) /
                       scale);
    }
    return {worst, iterations};
}

// Both iterations stop where their updates reach round-off (2ε of the increments, the floor of
// updates within 64 ulp of q, an update within 64 ulp of q that leaves less than an ulp of q by
// its own contraction, or the residual's own round-off), so a step differs by a few ulps of q
// and p: 1e-13 of the state bounds that with room. The articulated iteration must get there by
// itself, every step (against_newton calls it alone): an update of the wrong sign or scale, or a
// wrong A, would diverge or stall and fail that, where the step itself would still be Newton's. Its
// updates a step at 1 ms, measured with GCC 12 and clang 14 before the stop by contraction (which
// can only end a solve sooner): 2.0–2.8 unforced, 3.9–4.0 under the PD controller; 5 bounds them (a
// linear iteration with a rate above about 10⁻² fails it).
// The same, but each run continuing its own steps, as a run does: the articulated iteration then
// starts from the jerk and the last step's miss, and stops by its own contraction near round-off.
// The iteration must take every step itself (a copy solves it alone first) in at most 4 updates
// on average, and the two runs' states after 300 steps of 1 ms may differ by what a few ulps a
// step add up to, 1e-13 of the state (measured with clang 14: 2.6e-17, in 1.41 updates a step).
TEST(ArticulatedIteration, ARunOfItsOwnStepsStaysWithNewtons) {
    const tree_system sys = system_of(test::random_tree(21));
    const scheme_spec spec(scheme_kind::gauss, 2);
    general::stepper<tree_lagrangian, unforced> newton(sys, unforced{}, 1e-3, spec,
                                                       with_iteration(iteration_kind::newton));
    articulated_probe<unforced> art(sys, unforced{}, 1e-3, spec,
                                    with_iteration(iteration_kind::articulated));
    phase_state<dynamic> x = moving_start(sys.dimension()), y = x;
    int updates = 0;
    const int steps = 300;
    for (int j = 0; j < steps; ++j) {
        articulated_probe<unforced> copy = art;
        const newton_report alone = copy.alone(y);
        ASSERT_TRUE(alone.converged) << "step " << j;
        updates += alone.iterations;
        ASSERT_TRUE(art.step(y).converged) << "step " << j;
        ASSERT_TRUE(newton.step(x).converged) << "step " << j;
    }
    const double scale = x.q.lpNorm<Eigen::Infinity>() + x.p.lpNorm<Eigen::Infinity>();
    const double gap =
        ((y.q - x.q).lpNorm<Eigen::Infinity>() + (y.p - x.p).lpNorm<Eigen::Infinity>()) / scale;
    EXPECT_LT(gap, 1e-13) << gap;
    EXPECT_LE(updates, 4 * steps) << static_cast<double>(updates) / steps << " a step";
}

TEST(ArticulatedIteration, StepsAsNewtonDoesOnABranchedTree) {
    const tree_system sys = system_of(test::random_tree(21));
    for (const scheme_spec& spec :
         {scheme_spec(scheme_kind::simpson), scheme_spec(scheme_kind::gauss, 2)}) {
        const auto [gap, iterations] = against_newton(sys, unforced{}, 1e-3, spec, 200);
        EXPECT_LT(gap, 1e-13);
        EXPECT_GT(iterations, 0);
        EXPECT_LT(iterations, 200 * 5);
    }
}

TEST(ArticulatedIteration, StepsAsNewtonDoesUnderDampingAndAPdController) {
    const tree_system sys = system_of(test::random_tree(5));
    const int n = sys.dimension();
    pd_controller<dynamic> pd;
    pd.kp = 30.0 * Eigen::MatrixXd::Identity(n, n);
    pd.kd = 3.0 * Eigen::MatrixXd::Identity(n, n);
    pd.reference = [](double t, Eigen::VectorXd& r, Eigen::VectorXd& rate) {
        r.setConstant(0.2 * std::sin(2.0 * t));
        rate.setConstant(0.4 * std::cos(2.0 * t));
    };
    using damped_pd = force_sum<rayleigh_damping<dynamic>, pd_controller<dynamic>>;
    const damped_pd f(rayleigh_damping<dynamic>::diagonal(Eigen::VectorXd::Constant(n, 0.7)), pd);
    const auto [gap, iterations] =
        against_newton(sys, f, 1e-3, scheme_spec(scheme_kind::gauss, 2), 200);
    EXPECT_LT(gap, 1e-13);
    EXPECT_LT(iterations, 200 * 5);
}

// Mimic joints: the mass solves are the dense factorisation's, the steps the same.
TEST(ArticulatedIteration, StepsAsNewtonDoesWithMimicJoints) {
    const auto [gap, iterations] = against_newton(system_of(test::mimic_tree(true)), unforced{},
                                                  1e-3, scheme_spec(scheme_kind::simpson), 100);
    EXPECT_LT(gap, 1e-13);
    EXPECT_LT(iterations, 100 * 5);
}

// Under joint damping far beyond what the mass term holds (h D / M of order 10), what the
// iteration leaves out dominates: its updates grow, and the step goes to Newton, whose Jacobian
// has the damping: the step is Newton's, to the bit.
TEST(ArticulatedIteration, AStepItCannotTakeGoesToNewton) {
    const tree_system sys = system_of(test::random_tree(21));
    const int n = sys.dimension();
    const scheme_spec spec(scheme_kind::gauss, 2);
    using heavy_damping = rayleigh_damping<dynamic>;
    const heavy_damping heavy = heavy_damping::diagonal(Eigen::VectorXd::Constant(n, 1e3));
    general::stepper<tree_lagrangian, heavy_damping> newton(sys, heavy, 1e-2, spec,
                                                            with_iteration(iteration_kind::newton));
    general::stepper<tree_lagrangian, heavy_damping> art(
        sys, heavy, 1e-2, spec, with_iteration(iteration_kind::articulated));
    phase_state<dynamic> x = moving_start(n), y = x;
    for (int j = 0; j < 5; ++j) {
        const newton_report a = art.step(y), b = newton.step(x);
        ASSERT_TRUE(a.converged);
        ASSERT_TRUE(b.converged);
        EXPECT_GT(a.iterations, b.iterations); // the articulated updates spent, then Newton's
        EXPECT_EQ(y.q, x.q);
        EXPECT_EQ(y.p, x.p);
    }
}

// A robot held at rest by its gravity torques: the residual is round-off from the start, and the
// iteration stops there (at_round_off) instead of trading roundings until it runs out.
TEST(ArticulatedIteration, HeldAtRestTakesNoUpdate) {
    const tree_system sys = system_of(test::random_tree(21));
    const int n = sys.dimension();
    const Eigen::VectorXd q0 = Eigen::VectorXd::Constant(n, 0.3);
    Eigen::VectorXd hold(n);
    sys.lagrangian().bias_forces(q0, Eigen::VectorXd::Zero(n), hold); // g(q0) = ∂V/∂q
    general::stepper<tree_lagrangian, holding_torque> art(
        sys, holding_torque{hold}, 1e-3, scheme_spec(scheme_kind::gauss, 2),
        with_iteration(iteration_kind::articulated));
    phase_state<dynamic> x{q0, Eigen::VectorXd::Zero(n)};
    int updates = 0;
    for (int j = 0; j < 500; ++j) {
        const newton_report r = art.step(x);
        ASSERT_TRUE(r.converged);
        updates += r.iterations;
    }
    EXPECT_LT(updates, 50);
    EXPECT_LT((x.q - q0).lpNorm<Eigen::Infinity>(), 1e-12);
}

// A run resumed from a saved state and history continues as the straight run, to the bit and
// update for update: the articulated iteration keeps nothing across steps but the predictor's
// jerk and miss.
TEST(ArticulatedIteration, AResumedRunRepeatsTheStraightOne) {
    const tree_system sys = system_of(test::random_tree(21));
    const scheme_spec spec(scheme_kind::gauss, 2);
    const newton_options o = with_iteration(iteration_kind::articulated);
    general::stepper<tree_lagrangian> straight(sys, 1e-3, spec, o), first(sys, 1e-3, spec, o);
    phase_state<dynamic> x = moving_start(sys.dimension()), y = x;
    for (int j = 0; j < 40; ++j) {
        straight.step(x);
        first.step(y);
    }
    std::vector<double> history;
    first.save_history(history);
    general::stepper<tree_lagrangian> resumed(sys, 1e-3, spec, o);
    resumed.summation().restore(y, first.summation().carry_q(), first.summation().carry_p());
    resumed.set_time(first.time());
    resumed.restore_history(y, history);
    int gap = 0; // iterations the resumed run took beyond the straight one's
    for (int j = 0; j < 40; ++j)
        gap += resumed.step(y).iterations - straight.step(x).iterations;
    EXPECT_EQ(x.q, y.q);
    EXPECT_EQ(x.p, y.p);
    // Its steps also start alike: without the history the first one starts from the
    // second-order predictor, and took one update more (checked), with the same converged bits.
    EXPECT_EQ(gap, 0);
}

// Not a robot: the iteration is refused at construction, with what to choose instead.
TEST(ArticulatedIteration, RefusedWithoutMassSolves) {
    EXPECT_THROW(general::stepper<plain_spring>(lagrangian_system<plain_spring>(plain_spring{}),
                                                0.01, scheme_spec(scheme_kind::simpson),
                                                with_iteration(iteration_kind::articulated)),
                 std::invalid_argument);
}

} // namespace
