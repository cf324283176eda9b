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
    // A state changed between steps (1e-12 on one momentum: an impulse, a restart) starts
    // the next step from the second-order predictor, bit for bit the fresh stepper's; the
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

TEST(PredictorJerk, AResumedRunTakesTheSameSteps) {
    // 40 steps straight, and 20 + a new stepper given the saved history and carries + 20:
    // equal to the last bit, with a force (Rayleigh damping: the history also keeps the work)
    // and without. Negative control: resumed without the history, the run differs.
    const auto sys = arm();
    const int n = sys.dimension();
    const damping c = damping::diagonal(Eigen::VectorXd::LinSpaced(n, 0.5, 2.0));
    const scheme_spec spec(scheme_kind::gauss, 2);
    const auto check = [&](auto make) {
        auto straight = make(), first = make();
        phase_state<dynamic> a = start(n), b = start(n);
        for (int j = 0; j < 40; ++j)
            ASSERT_TRUE(straight.step(a).converged);
        for (int j = 0; j < 20; ++j)
            ASSERT_TRUE(first.step(b).converged);
        std::vector<double> history;
        first.save_history(history);
        for (const bool kept : {true, false}) {
            auto second = make();
            phase_state<dynamic> y = b;
            second.summation().restore(y, first.summation().carry_q(), first.summation().carry_p());
            second.restore_history(y, kept ? history : std::vector<double>{});
            second.set_time(first.time());
            for (int j = 0; j < 20; ++j)
                ASSERT_TRUE(second.step(y).converged);
            if (kept) {
                EXPECT_EQ(y.q, a.q);
                EXPECT_EQ(y.p, a.p);
                EXPECT_EQ(second.total_work(), straight.total_work());
            } else {
                EXPECT_NE(y.p, a.p);
            }
        }
        // A history of another length is refused, not misread.
        history.push_back(0.0);
        auto other = make();
        EXPECT_THROW(other.restore_history(b, history), std::invalid_argument);
    };
    check([&] { return probe<>(sys, 0.01, spec); });
    check([&] { return probe<damping>(sys, c, 0.01, spec); });
}

TEST(PredictorJerk, AHistoryWithoutTheJerkStartsItAfresh) {
    // A forced stepper's history before the predictor kept its jerk: the time, work and carry
    // (3 numbers). Taken, with the second-order predictor for the next step; the work restored.
    const auto sys = arm();
    const int n = sys.dimension();
    const damping c = damping::diagonal(Eigen::VectorXd::Constant(n, 1.0));
    probe<damping> p(sys, c, 0.01, scheme_spec(scheme_kind::gauss, 2)),
        fresh(sys, c, 0.01, scheme_spec(scheme_kind::gauss, 2));
    const phase_state<dynamic> x = start(n);
    p.restore_history(x, {0.0, 0.25, 0.0});
    EXPECT_EQ(p.total_work(), 0.25);
    EXPECT_EQ(p.predicted(x), fresh.predicted(x));
}
