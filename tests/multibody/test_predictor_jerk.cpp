// tests/multibody/test_predictor_jerk.cpp: the general engine's Newton predictor for a robot
// (schemes/variational_solve.hpp, predict_dynamics) where a step continues the last one: the
// third Taylor term from the free motion's jerk, (a₀,j − a₀,j−1)/h, and the history that carries
// it across a checkpoint.
// References: the converged increments of the same step (what the predictor estimates), whose
// distance to a Taylor expansion of order k falls as h^(k+1); a run taken straight through.
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "multibody/random_tree.hpp"
#include "varsym/multibody/lagrangian.hpp"
#include "varsym/schemes/variational.hpp"
#include "varsym/systems/forcing.hpp"

namespace {

using namespace varsym;
using arm_lagrangian = multibody::robot_lagrangian;
using damping = rayleigh_damping<dynamic>;

/// The stepper with its predictor and increments in view (protected there).
template <class F = unforced>
struct probe : general::stepper<arm_lagrangian, F> {
    using general::stepper<arm_lagrangian, F>::stepper;
    Eigen::MatrixXd predicted(const phase_state<dynamic>& x) {
        this->predict_dynamics(x);
        return this->x_;
    }
    [[nodiscard]] const Eigen::MatrixXd& increments() const { return this->x_; }
};

lagrangian_system<arm_lagrangian> arm() {
    return lagrangian_system<arm_lagrangian>(
        arm_lagrangian(std::make_shared<const multibody::tree>(test::random_tree(21))));
}

phase_state<dynamic> start(int n) {
    return {Eigen::VectorXd::Constant(n, 0.4), Eigen::VectorXd::LinSpaced(n, -1.0, 1.0)};
}

/// After one step of h from start(): the distance of the second step's prediction to its
/// converged increments, where the step continues the first (the jerk) and from a stepper
/// without that history (second order).
struct errors {
    double continued, fresh;
};
errors prediction_errors(double h) {
    const auto sys = arm();
    const scheme_spec spec(scheme_kind::gauss, 2);
    probe<> p(sys, h, spec);
    phase_state<dynamic> x = start(sys.dimension());
    EXPECT_TRUE(p.step(x).converged);
    probe<> converged = p, fresh(sys, h, spec);
    phase_state<dynamic> y = x;
    EXPECT_TRUE(converged.step(y).converged);
    const Eigen::MatrixXd& want = converged.increments();
    return {(p.predicted(x) - want).lpNorm<Eigen::Infinity>(),
            (fresh.predicted(x) - want).lpNorm<Eigen::Infinity>()};
}

} // namespace

TEST(PredictorJerk, ContinuingAStepGainsAnOrder) {
    // Halving h divides the second-order predictor's error by about 2³ and the jerk's by about
    // 2⁴ (its estimate of the jerk is O(h), so the term it adds is O(h⁴)). The bounds leave a
    // quarter of an order each way. Negative control: the fresh stepper's ratio stays below 2^3.4.
    const errors coarse = prediction_errors(0.02), fine = prediction_errors(0.01);
    const double continued = std::log2(coarse.continued / fine.continued);
    const double fresh = std::log2(coarse.fresh / fine.fresh);
    EXPECT_GE(continued, 3.75) << coarse.continued << " → " << fine.continued;
    EXPECT_LE(continued, 4.5);
    EXPECT_GE(fresh, 2.75) << coarse.fresh << " → " << fine.fresh;
    EXPECT_LE(fresh, 3.4);
    EXPECT_LT(fine.continued, 0.1 * fine.fresh);
}

TEST(PredictorJerk, OnlyWhereTheStepContinuesTheLast) {
    // A state changed between steps (1e-12 on one momentum: an impulse, a state set by hand)
    // starts the next step from the second-order predictor, bit for bit the fresh stepper's; the
    // unchanged state takes the jerk (negative control: the predictions differ).
    const auto sys = arm();
    const scheme_spec spec(scheme_kind::simpson);
    probe<> p(sys, 0.01, spec), fresh(sys, 0.01, spec);
    phase_state<dynamic> x = start(sys.dimension());
    ASSERT_TRUE(p.step(x).converged);
    probe<> kept = p;
    phase_state<dynamic> moved = x;
    moved.p(2) += 1e-12;
    EXPECT_EQ(p.predicted(moved), fresh.predicted(moved));
    EXPECT_NE(kept.predicted(x), fresh.predicted(x));
}

TEST(PredictorJerk, NotAfterAStepThatDidNotPredict) {
    // The simplified iteration predicts from its kept Jacobian; only its fallback to Newton
    // takes the jerk's start. A Newton prediction left by a step that then failed (here taken by
    // hand) must not pair with the next committed step: after it, the prediction is the fresh
    // stepper's, bit for bit.
    const auto sys = arm();
    const scheme_spec spec(scheme_kind::gauss, 2);
    newton_options o;
    o.iteration = iteration_kind::simplified;
    probe<> p(sys, 1e-3, spec, o), fresh(sys, 1e-3, spec, o);
    phase_state<dynamic> x = start(sys.dimension());
    phase_state<dynamic> other = x;
    other.q.array() += 0.1;
    (void)p.predicted(other);
    ASSERT_TRUE(p.step(x).converged); // by the kept Jacobian (a fallback would predict anew)
    EXPECT_EQ(p.predicted(x), fresh.predicted(x));
}

TEST(PredictorJerk, AResumedRunTakesTheSameSteps) {
    // 40 steps straight, and 20 + a new stepper given the saved history and carries + 20: equal
    // to the last bit. Negative control: a new stepper without the history predicts the 21st
    // step differently (by the jerk's term, O(h³) of the increments). With a force (Rayleigh
    // damping) the history keeps the work but no jerk, and the run resumes the same.
    const auto sys = arm();
    const int n = sys.dimension();
    const scheme_spec spec(scheme_kind::gauss, 2);
    const auto check = [&](auto make, std::size_t size) {
        auto straight = make(), first = make();
        phase_state<dynamic> a = start(n), b = start(n);
        for (int j = 0; j < 40; ++j)
            ASSERT_TRUE(straight.step(a).converged);
        for (int j = 0; j < 20; ++j)
            ASSERT_TRUE(first.step(b).converged);
        std::vector<double> history;
        first.save_history(history);
        EXPECT_EQ(history.size(), size);
        auto second = make(), blank = make(), copy = first;
        second.summation().restore(b, first.summation().carry_q(), first.summation().carry_p());
        second.restore_history(b, history);
        second.set_time(first.time());
        auto ahead = second;
        const Eigen::MatrixXd want = copy.predicted(b); // the straight run's next start
        EXPECT_EQ(ahead.predicted(b), want);
        if (size > 3) {
            EXPECT_NE(blank.predicted(b), want);
        }
        for (int j = 0; j < 20; ++j)
            ASSERT_TRUE(second.step(b).converged);
        EXPECT_EQ(b.q, a.q);
        EXPECT_EQ(b.p, a.p);
        EXPECT_EQ(second.total_work(), straight.total_work());
    };
    check([&] { return probe<>(sys, 0.01, spec); }, 1 + 3 * static_cast<std::size_t>(n));
    const damping c = damping::diagonal(Eigen::VectorXd::LinSpaced(n, 0.5, 2.0));
    check([&] { return probe<damping>(sys, c, 0.01, spec); }, 3);
}

TEST(PredictorJerk, HistoriesOfOtherLayoutsAreReadOrRefused) {
    // An empty history, and one without the jerk's part (a linear iteration's 1 + 2d numbers),
    // start the jerk afresh: the prediction after them is the fresh stepper's. A flag that does
    // not match the length, or is neither 0 nor 1, is refused, not misread.
    const auto sys = arm();
    const int n = sys.dimension();
    const auto d = static_cast<std::size_t>(n);
    const scheme_spec spec(scheme_kind::gauss, 2);
    probe<> p(sys, 0.01, spec), fresh(sys, 0.01, spec);
    phase_state<dynamic> x = start(n);
    ASSERT_TRUE(p.step(x).converged);
    probe<> kept = p;
    EXPECT_NE(kept.predicted(x), fresh.predicted(x)); // it would continue
    p.restore_history(x, {});
    EXPECT_EQ(p.predicted(x), fresh.predicted(x));

    newton_options o;
    o.iteration = iteration_kind::simplified;
    probe<> linear(sys, 0.01, spec, o);
    std::vector<double> without(1 + 2 * d, 0.0);
    EXPECT_NO_THROW(linear.restore_history(x, without));
    std::vector<double> with = without;
    with.push_back(0.0);
    EXPECT_NO_THROW(linear.restore_history(x, with));

    std::vector<double> saved;
    kept = probe<>(sys, 0.01, spec);
    phase_state<dynamic> y = start(n);
    ASSERT_TRUE(kept.step(y).converged);
    kept.save_history(saved);
    ASSERT_EQ(saved.size(), 1 + 3 * d);
    ASSERT_EQ(saved[0], 1.0);
    std::vector<double> flag_zero = saved, flag_two = saved, short_one{1.0};
    flag_zero[0] = 0.0;
    flag_two[0] = 2.0;
    for (const auto* bad : {&flag_zero, &flag_two, &short_one})
        EXPECT_THROW(fresh.restore_history(y, *bad), std::invalid_argument);
}

TEST(PredictorJerk, BiasForcesOnTheMassMatrixKinematicsAreTheBiasForces) {
    // The predictor's Newton–Euler pass on the kinematics its composite-rigid-body pass left:
    // the same numbers, bit for bit, as the pass with its own kinematics (negative control: a
    // state whose kinematics were not computed last differs).
    const auto sys = arm();
    const arm_lagrangian& l = sys.lagrangian();
    const int n = sys.dimension();
    std::mt19937 g(5);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    for (int k = 0; k < 5; ++k) {
        Eigen::VectorXd q(n), v(n), want, got, stale;
        for (int i = 0; i < n; ++i) {
            q(i) = u(g);
            v(i) = u(g);
        }
        Eigen::MatrixXd m;
        l.bias_forces(q, v, want);
        l.mass_matrix(q, m);
        l.bias_forces_after_mass_matrix(v, got);
        EXPECT_EQ(got, want);
        l.mass_matrix(q + Eigen::VectorXd::Constant(n, 0.5), m);
        l.bias_forces_after_mass_matrix(v, stale);
        EXPECT_NE(stale, want);
    }
}
