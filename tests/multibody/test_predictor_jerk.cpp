// tests/multibody/test_predictor_jerk.cpp: the general engine's Newton predictor for a robot
// (schemes/variational_solve.hpp, predict_dynamics) where a step continues the last one: the
// third Taylor term from the free motion's jerk, (a₀,j − a₀,j−1)/h, the last step's miss, and the
// history that carries them across a checkpoint.
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

/// Damping and a PD controller tracking a moving reference: a force continuous in time, with a
/// rate in t as well as in the state.
using smooth_force = force_sum<damping, pd_controller<dynamic>>;
smooth_force tracking(int n) {
    pd_controller<dynamic> pd;
    pd.kp = 20.0 * Eigen::MatrixXd::Identity(n, n);
    pd.kd = 2.0 * Eigen::MatrixXd::Identity(n, n);
    pd.reference = [](double t, Eigen::VectorXd& r, Eigen::VectorXd& rate) {
        r.setConstant(0.4 + 0.3 * std::sin(3.0 * t));
        rate.setConstant(0.9 * std::cos(3.0 * t));
    };
    return smooth_force(damping::diagonal(Eigen::VectorXd::LinSpaced(n, 0.5, 2.0)), pd);
}

/// The same force, not declared continuous in time, as a control held over each step is not.
struct undeclared {
    static constexpr int dim = dynamic;
    smooth_force f;
    Eigen::VectorXd operator()(const Eigen::VectorXd& q, const Eigen::VectorXd& v, double t) const {
        return f(q, v, t);
    }
    void derivatives(const Eigen::VectorXd& q, const Eigen::VectorXd& v, double t,
                     force_terms<dynamic>& r) const {
        f.derivatives(q, v, t, r);
    }
};
static_assert(force_continuous_in_time<smooth_force>());
static_assert(!force_continuous_in_time<undeclared>());
// What jumps between steps, or may: a control held over each step, a schedule u(t) of any kind,
// and a sum with either.
struct torque_input {
    static constexpr int dim = 2, controls = 1;
    template <class T>
    tvec<T, 2> operator()(const tvec<T, 2>&, const tvec<T, 2>&, double, const tvec<T, 1>& u) const {
        return tvec<T, 2>(u(0), T(0.0));
    }
};
static_assert(!force_continuous_in_time<controlled<torque_input>>());
static_assert(!force_continuous_in_time<prescribed_force<dynamic>>());
static_assert(!force_continuous_in_time<force_sum<damping, prescribed_force<dynamic>>>());

/// After one step of h from start(n): the distance of the second step's prediction to its
/// converged increments, where the step continues the first (the jerk) and from a stepper
/// without that history (second order); make(h) gives a new stepper. `same`: the two
/// predictions are equal, bit for bit.
struct errors {
    double continued, fresh;
    bool same;
};
template <class Make>
errors prediction_errors(int n, double h, Make make) {
    auto p = make(h);
    phase_state<dynamic> x = start(n);
    EXPECT_TRUE(p.step(x).converged);
    auto converged = p, fresh = make(h);
    fresh.set_time(p.time());
    phase_state<dynamic> y = x;
    EXPECT_TRUE(converged.step(y).converged);
    const Eigen::MatrixXd& want = converged.increments();
    const Eigen::MatrixXd a = p.predicted(x), b = fresh.predicted(x);
    return {(a - want).lpNorm<Eigen::Infinity>(), (b - want).lpNorm<Eigen::Infinity>(), a == b};
}

/// The orders of the continued and the fresh predictions, from h = 0.02 and 0.01, and the
/// errors at h = 0.01.
struct orders {
    double continued, fresh;
    errors fine;
};
template <class Make>
orders prediction_orders(int n, Make make) {
    const errors coarse = prediction_errors(n, 0.02, make), fine = prediction_errors(n, 0.01, make);
    return {std::log2(coarse.continued / fine.continued), std::log2(coarse.fresh / fine.fresh),
            fine};
}

} // namespace

TEST(PredictorJerk, ContinuingAStepGainsAnOrder) {
    // Halving h divides the second-order predictor's error by about 2³ and the jerk's by about
    // 2⁴ (its estimate of the jerk is O(h), so the term it adds is O(h⁴)). The bounds leave a
    // quarter of an order each way. Without a force, and with a force continuous in time (the
    // jerk then has the force's rate in t too). Negative controls: the fresh stepper's ratio
    // stays below 2^3.4; the same force undeclared keeps the second-order start, bit for bit.
    const auto sys = arm();
    const int n = sys.dimension();
    const scheme_spec spec(scheme_kind::gauss, 2);
    const auto free = [&](double h) { return probe<>(sys, h, spec); };
    const auto forced = [&](double h) { return probe<smooth_force>(sys, tracking(n), h, spec); };
    const auto held = [&](double h) {
        return probe<undeclared>(sys, undeclared{tracking(n)}, h, spec);
    };
    const auto gains = [](const orders& order) {
        EXPECT_GE(order.continued, 3.75);
        EXPECT_LE(order.continued, 4.5);
        EXPECT_GE(order.fresh, 2.75);
        EXPECT_LE(order.fresh, 3.4);
        EXPECT_LT(order.fine.continued, 0.15 * order.fine.fresh); // 0.04 free, 0.09 forced
        EXPECT_FALSE(order.fine.same);
    };
    gains(prediction_orders(n, free));
    gains(prediction_orders(n, forced));
    const orders undeclared_order = prediction_orders(n, held);
    EXPECT_TRUE(undeclared_order.fine.same);
    EXPECT_LE(undeclared_order.continued, 3.4);
}

/// After 3 steps, the 4th step's prediction error with the last step's miss and without it (the
/// same history less the miss, as a checkpoint of the jerk's layout alone gives).
errors miss_errors(int n, double h) {
    const auto sys = arm();
    const scheme_spec spec(scheme_kind::gauss, 2);
    probe<> p(sys, h, spec);
    phase_state<dynamic> x = start(n);
    for (int j = 0; j < 3; ++j)
        EXPECT_TRUE(p.step(x).converged);
    std::vector<double> history;
    p.save_history(history);
    const std::size_t jerk = 1 + 3 * static_cast<std::size_t>(n);
    EXPECT_EQ(history.size(), jerk + 1 + 2 * static_cast<std::size_t>(n));
    EXPECT_EQ(history[jerk], 1.0); // the miss is kept
    history.resize(jerk);
    auto converged = p, without = p;
    without.restore_history(x, history);
    phase_state<dynamic> y = x;
    EXPECT_TRUE(converged.step(y).converged);
    const Eigen::MatrixXd& want = converged.increments();
    const Eigen::MatrixXd a = p.predicted(x), b = without.predicted(x);
    return {(a - want).lpNorm<Eigen::Infinity>(), (b - want).lpNorm<Eigen::Infinity>(), a == b};
}

TEST(PredictorJerk, TheLastMissGainsAnother) {
    // The miss of a step that took the jerk (its increments less their Taylor prediction) changes
    // by O(h) of itself to the next step: added to the next prediction, it leaves O(h⁵) of the
    // O(h⁴). Measured from h = 0.02 to 0.01 (gauss-2): the orders and the errors at h = 0.01.
    // Negative control: the same stepper restored without the miss predicts as the jerk alone.
    const int n = arm().dimension();
    const errors coarse = miss_errors(n, 0.02), fine = miss_errors(n, 0.01);
    const double with = std::log2(coarse.continued / fine.continued),
                 without = std::log2(coarse.fresh / fine.fresh);
    EXPECT_GE(with, 4.6); // measured 4.89; a quarter of an order below 5 leaves room
    EXPECT_LE(with, 5.5);
    EXPECT_GE(without, 3.75); // measured 3.95
    EXPECT_LE(without, 4.5);
    EXPECT_LT(fine.continued, 0.05 * fine.fresh); // measured 2.3e-10 against 1.5e-8
    EXPECT_FALSE(fine.same);
}

TEST(PredictorJerk, OnlyWhereTheStepContinuesTheLast) {
    // A state changed between steps (1e-12 on one momentum: an impulse, a state set by hand)
    // starts the next step from the second-order predictor, bit for bit the fresh stepper's,
    // without the jerk or the miss the three steps before keep; the unchanged state takes them
    // (negative control: the predictions differ).
    const auto sys = arm();
    const scheme_spec spec(scheme_kind::simpson);
    probe<> p(sys, 0.01, spec), fresh(sys, 0.01, spec);
    phase_state<dynamic> x = start(sys.dimension());
    for (int j = 0; j < 3; ++j) // the jerk and the miss both kept
        ASSERT_TRUE(p.step(x).converged);
    fresh.set_time(p.time());
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
    // step differently (by the jerk's term, O(h³) of the increments). With a force continuous in
    // time the history keeps the work and the jerk's state; with one not declared so, the work
    // alone; either run resumes the same.
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
        blank.set_time(first.time());
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
    // The jerk's flag, a₀, q and p; the miss's flag and the miss (d × s, s = 2).
    const std::size_t jerk =
        1 + 3 * static_cast<std::size_t>(n) + 1 + 2 * static_cast<std::size_t>(n);
    check([&] { return probe<>(sys, 0.01, spec); }, jerk);
    check([&] { return probe<smooth_force>(sys, tracking(n), 0.01, spec); }, 3 + jerk);
    check([&] { return probe<undeclared>(sys, undeclared{tracking(n)}, 0.01, spec); }, 3);
}

TEST(PredictorJerk, HistoriesOfOtherLayoutsAreReadOrRefused) {
    // An empty history, and one without the jerk's part (a linear iteration's 1 + 2d numbers),
    // start the jerk afresh: the prediction after them is the fresh stepper's. One without the
    // miss's part (the jerk's 1 + 3d numbers alone) continues the jerk. A flag that does not match
    // the length, or is neither 0 nor 1, is refused, not misread.
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
    ASSERT_EQ(saved.size(), 2 + 3 * d); // the first step took no jerk: no miss to keep
    ASSERT_EQ(saved[0], 1.0);
    ASSERT_EQ(saved.back(), 0.0);
    std::vector<double> flag_zero = saved, flag_two = saved, miss_two = saved, short_one{1.0};
    flag_zero[0] = 0.0;
    flag_two[0] = 2.0;
    miss_two.back() = 2.0;
    for (const auto* bad : {&flag_zero, &flag_two, &miss_two, &short_one})
        EXPECT_THROW(fresh.restore_history(y, *bad), std::invalid_argument);
    std::vector<double> jerk_alone(saved.begin(), saved.end() - 1);
    probe<> legacy(sys, 0.01, spec), with_flag(sys, 0.01, spec);
    legacy.restore_history(y, jerk_alone);
    with_flag.restore_history(y, saved);
    EXPECT_EQ(legacy.predicted(y), with_flag.predicted(y));
    EXPECT_NE(legacy.predicted(y), fresh.predicted(y)); // it continues the jerk
    // With the miss kept (after three steps): a miss flag or jerk flag that does not match.
    probe<> third(sys, 0.01, spec);
    phase_state<dynamic> w = start(n);
    for (int j = 0; j < 3; ++j)
        ASSERT_TRUE(third.step(w).converged);
    std::vector<double> full;
    third.save_history(full);
    ASSERT_EQ(full.size(), 2 + 3 * d + 2 * d);
    std::vector<double> miss_zero = full, miss_three = full, jerk_zero = full;
    miss_zero[1 + 3 * d] = 0.0;
    miss_three[1 + 3 * d] = 3.0;
    jerk_zero[0] = 0.0;
    for (const auto* bad : {&miss_zero, &miss_three, &jerk_zero})
        EXPECT_THROW(fresh.restore_history(w, *bad), std::invalid_argument);

    // A forced robot's history written before its force took the jerk, the timed part alone
    // (3 numbers), is read, and the jerk starts afresh (negative control: before it, the copy
    // would continue).
    probe<smooth_force> forced(sys, tracking(n), 0.01, spec);
    probe<smooth_force> forced_fresh(sys, tracking(n), 0.01, spec);
    phase_state<dynamic> z = start(n);
    ASSERT_TRUE(forced.step(z).converged);
    forced_fresh.set_time(forced.time());
    std::vector<double> timed;
    forced.save_history(timed);
    ASSERT_EQ(timed.size(), 3 + 2 + 3 * d);
    timed.resize(3);
    probe<smooth_force> going = forced, other = forced_fresh;
    EXPECT_NE(going.predicted(z), other.predicted(z));
    EXPECT_NO_THROW(forced.restore_history(z, timed));
    EXPECT_EQ(forced.predicted(z), forced_fresh.predicted(z));
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
