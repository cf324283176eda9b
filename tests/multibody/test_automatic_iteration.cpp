// tests/multibody/test_automatic_iteration.cpp: the general engine's automatic iteration for
// robots (schemes/variational_articulated.hpp, choose_iteration; solvers/iteration_choice.hpp):
// Newton or the articulated iteration, step by step, where the cost model puts Newton's step
// above choice_threshold articulated updates. Both solve the same step equations, so the
// reference is a run by Newton alone: the automatic run must end within round-off's growth of it
// where it takes the articulated iteration, and on Newton's bits where every step is Newton's.
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "multibody/random_tree.hpp"
#include "varsym/contact/stepper.hpp"
#include "varsym/multibody/lagrangian.hpp"
#include "varsym/schemes/variational.hpp"
#include "varsym/systems/forcing.hpp"

namespace {

using namespace varsym;
using robot_system = lagrangian_system<multibody::robot_lagrangian>;

/// The chain of bench/bench_robots.cpp: n links of 1 kg and 0.3 m along alternating y and x
/// axes, hanging from the ground.
multibody::tree chain_tree(int n) {
    multibody::tree m;
    for (int i = 0; i < n; ++i) {
        multibody::body b;
        b.name = "j" + std::to_string(i);
        b.link = "l" + std::to_string(i);
        b.placement.origin = multibody::vec3(0.0, 0.0, i == 0 ? 0.0 : -0.3);
        b.axis = i % 2 ? multibody::vec3::UnitX() : multibody::vec3::UnitY();
        b.mass = 1.0;
        b.com = multibody::vec3(0.0, 0.0, -0.15);
        b.inertia = multibody::vec3(0.008, 0.008, 0.001).asDiagonal();
        m.add_body(i - 1, b);
    }
    return m;
}

robot_system system_of_tree(const multibody::tree& m) {
    return robot_system(multibody::robot_lagrangian(std::make_shared<const multibody::tree>(m)));
}

robot_system hanging_chain(int n) {
    return system_of_tree(chain_tree(n));
}

/// The 30-link chain with a 31st body at its end on a mimic joint following q_0 / 2: its mass
/// solves are dense, so the automatic iteration keeps Newton where the chain alone chooses.
multibody::tree chain_with_mimic() {
    multibody::tree m = chain_tree(30);
    multibody::body b = m.bodies.back();
    b.name = "mimic";
    b.link = "lm";
    b.parent = 29;
    m.bodies.push_back(b);
    m.mimics = {{0, 0.5, 0.0}};
    return m;
}

/// At rest at q_i = 0.4 + 0.3 sin(1.7 i), as the benchmark starts.
phase_state<dynamic> bench_start(int n) {
    phase_state<dynamic> x{Eigen::VectorXd(n), Eigen::VectorXd::Zero(n)};
    for (int i = 0; i < n; ++i)
        x.q(i) = 0.4 + 0.3 * std::sin(1.7 * i);
    return x;
}

newton_options iteration_of(iteration_kind k) {
    newton_options o;
    o.iteration = k;
    return o;
}

double state_gap(const phase_state<dynamic>& a, const phase_state<dynamic>& b) {
    return ((a.q - b.q).lpNorm<Eigen::Infinity>() + (a.p - b.p).lpNorm<Eigen::Infinity>()) /
           (a.q.lpNorm<Eigen::Infinity>() + a.p.lpNorm<Eigen::Infinity>());
}

// 30 links: the model puts Newton's gauss-2 step at 7.3 articulated updates, Simpson's at 6.4
// (measured: 3.2 and 4.1 updates a step here), so every step is the articulated iteration's.
// Both runs stop at the step equations' round-off each step, and the chain falls for 0.3 s:
// measured 3e-16 apart after 300 steps; 1e-12 leaves room for round-off's growth on another
// compiler.
TEST(AutomaticIteration, ChoosesTheArticulatedIterationOnALongChain) {
    const robot_system sys = hanging_chain(30);
    for (const scheme_spec& spec :
         {scheme_spec(scheme_kind::gauss, 2), scheme_spec(scheme_kind::simpson)}) {
        general::stepper<multibody::robot_lagrangian> automatic(sys, 1e-3, spec);
        general::stepper<multibody::robot_lagrangian> newton(sys, 1e-3, spec,
                                                             iteration_of(iteration_kind::newton));
        ASSERT_TRUE(automatic.choice().on());
        // A part step (to a section) chooses again at its own step size.
        EXPECT_TRUE(automatic.with_step_size(5e-4).choice().on());
        EXPECT_GT(automatic.choice().break_even(), 5.0);
        EXPECT_LT(automatic.choice().break_even(), 8.0);
        phase_state<dynamic> x = bench_start(30), y = x;
        for (int j = 0; j < 300; ++j) {
            ASSERT_TRUE(automatic.step(x).converged) << j;
            ASSERT_TRUE(newton.step(y).converged) << j;
        }
        EXPECT_GE(automatic.choice().articulated_steps(), 270);
        EXPECT_EQ(automatic.choice().steps(), 300);
        EXPECT_FALSE(newton.choice().on()); // negative control: a named iteration is kept
        EXPECT_LT(state_gap(x, y), 1e-12);
    }
}

// Under damping far beyond what the mass term holds (h D / M of order 10 and more), every
// articulated step is handed to Newton; the choice then holds Newton for 64, 128, … steps after
// each window of 16. A step handed over is Newton's to the bit, and so is every held one: the
// run is Newton's run, bit for bit, with 16 steps tried in each of its first windows.
TEST(AutomaticIteration, GoesBackToNewtonWhereTheArticulatedIterationIsSlow) {
    const robot_system sys = hanging_chain(30);
    using joint_damping = rayleigh_damping<dynamic>;
    const joint_damping heavy = joint_damping::diagonal(Eigen::VectorXd::Constant(30, 1e3));
    const scheme_spec spec(scheme_kind::gauss, 2);
    general::stepper<multibody::robot_lagrangian, joint_damping> automatic(sys, heavy, 1e-2, spec);
    general::stepper<multibody::robot_lagrangian, joint_damping> newton(
        sys, heavy, 1e-2, spec, iteration_of(iteration_kind::newton));
    phase_state<dynamic> x = bench_start(30), y = x;
    for (int j = 0; j < 400; ++j) {
        ASSERT_TRUE(automatic.step(x).converged) << j;
        ASSERT_TRUE(newton.step(y).converged) << j;
    }
    EXPECT_EQ(x.q, y.q);
    EXPECT_EQ(x.p, y.p);
    // Windows at steps 0, 80 and 224 (16 + 64, then 16 + 128), the next at 496.
    EXPECT_EQ(automatic.choice().articulated_steps(), 48);
}

// The choice is on from 10 links of the chain (break-even 3.09 with gauss-2, 3.002 with
// Simpson), off at 9 (2.93 and 2.88): the threshold of choice_threshold, where the articulated
// iteration from rest takes 2.4-2.7 updates a step and is 6-11 % faster than Newton's
// (docs/robots.md). With one increment a step, gauss-1, from 36 links (5.56; 5.43 at 35): its
// updates shrink more slowly, and the threshold is choice_threshold_one_increment.
TEST(AutomaticIteration, ChoosesFromTenLinksOfAChain) {
    for (const scheme_spec& spec :
         {scheme_spec(scheme_kind::gauss, 2), scheme_spec(scheme_kind::simpson)}) {
        const general::stepper<multibody::robot_lagrangian> nine(hanging_chain(9), 1e-3, spec);
        const general::stepper<multibody::robot_lagrangian> ten(hanging_chain(10), 1e-3, spec);
        EXPECT_FALSE(nine.choice().on());
        EXPECT_TRUE(ten.choice().on());
        EXPECT_GE(ten.choice().break_even(), general::choice_threshold);
        EXPECT_LT(ten.choice().break_even(), 3.2);
    }
    const scheme_spec midpoint(scheme_kind::gauss, 1);
    EXPECT_FALSE(general::stepper<multibody::robot_lagrangian>(hanging_chain(35), 1e-3, midpoint)
                     .choice()
                     .on());
    const general::stepper<multibody::robot_lagrangian> long_midpoint(hanging_chain(36), 1e-3,
                                                                      midpoint);
    EXPECT_TRUE(long_midpoint.choice().on());
    EXPECT_GE(long_midpoint.choice().break_even(), general::choice_threshold_one_increment);
}

// Arms and small trees (7 bodies here) keep Newton: their break-even is below choice_threshold.
// So does the 30-link chain with a mimic joint, whose mass solves are dense (the chain alone
// chooses: the test above). The steps are Newton's to the bit.
TEST(AutomaticIteration, KeepsNewtonOnSmallRobotsAndMimicJoints) {
    for (const multibody::tree& t : {test::random_tree(21), chain_with_mimic()}) {
        const robot_system sys = system_of_tree(t);
        const scheme_spec spec(scheme_kind::gauss, 2);
        general::stepper<multibody::robot_lagrangian> automatic(sys, 1e-3, spec);
        general::stepper<multibody::robot_lagrangian> newton(sys, 1e-3, spec,
                                                             iteration_of(iteration_kind::newton));
        EXPECT_FALSE(automatic.choice().on());
        phase_state<dynamic> x{Eigen::VectorXd::LinSpaced(sys.dimension(), -0.8, 0.9),
                               Eigen::VectorXd::LinSpaced(sys.dimension(), 1.0, -0.7)};
        phase_state<dynamic> y = x;
        for (int j = 0; j < 100; ++j) {
            ASSERT_TRUE(automatic.step(x).converged);
            ASSERT_TRUE(newton.step(y).converged);
        }
        EXPECT_EQ(x.q, y.q);
        EXPECT_EQ(x.p, y.p);
    }
}

// A run resumed from a saved state and history continues as the straight run, to the bit, with
// the same choices: in the middle of a hold (damped) and of a window (free), and a history
// without the choice's state (written without it) restores with the choice afresh.
TEST(AutomaticIteration, AResumedRunRepeatsTheStraightOne) {
    const robot_system sys = hanging_chain(30);
    using joint_damping = rayleigh_damping<dynamic>;
    const scheme_spec spec(scheme_kind::gauss, 2);
    for (const double d : {1e3, 0.0}) {
        const joint_damping f = joint_damping::diagonal(Eigen::VectorXd::Constant(30, d));
        const double h = d > 0.0 ? 1e-2 : 1e-3;
        using automatic_stepper = general::stepper<multibody::robot_lagrangian, joint_damping>;
        automatic_stepper straight(sys, f, h, spec), first(sys, f, h, spec);
        phase_state<dynamic> x = bench_start(30), y = x;
        for (int j = 0; j < 100; ++j) { // damped: the hold of 128 from step 96
            ASSERT_TRUE(straight.step(x).converged);
            ASSERT_TRUE(first.step(y).converged);
        }
        EXPECT_EQ(first.choice().articulated(), d == 0.0);
        std::vector<double> history;
        first.save_history(history);
        automatic_stepper resumed(sys, f, h, spec);
        resumed.summation().restore(y, first.summation().carry_q(), first.summation().carry_p());
        resumed.set_time(first.time());
        resumed.restore_history(y, history);
        const long before = straight.choice().articulated_steps();
        for (int j = 0; j < 150; ++j) {
            EXPECT_EQ(resumed.choice().articulated(), straight.choice().articulated()) << j;
            ASSERT_TRUE(resumed.step(y).converged);
            ASSERT_TRUE(straight.step(x).converged);
        }
        EXPECT_EQ(x.q, y.q);
        EXPECT_EQ(x.p, y.p);
        EXPECT_EQ(resumed.choice().articulated_steps(),
                  straight.choice().articulated_steps() - before);
        // A stepper without the choice (Newton, named) reads the history and ignores the
        // choice's part.
        automatic_stepper named(sys, f, h, spec, iteration_of(iteration_kind::newton));
        EXPECT_NO_THROW(named.restore_history(y, history));
        // Without the choice's four numbers: read, and the choice starts a window.
        history.resize(history.size() - iteration_choice::saved);
        automatic_stepper older(sys, f, h, spec);
        older.restore_history(y, history);
        EXPECT_TRUE(older.choice().articulated());
        history.push_back(1.0); // neither layout: refused
        EXPECT_THROW(older.restore_history(y, history), std::invalid_argument);
    }
}

// A robot's step starts from the jerk where it continues the last step; in a violent motion that
// start can be out of Newton's reach where the second-order one is not (measured: a 50-link chain
// whipping at 130 rad/s after 4.5 s). Such a step is taken again from the second-order start, and
// is then a fresh stepper's step, bit for bit. The history here says the last step ended at x with
// an acceleration 10¹⁰ off: the jerk's start is far out (negative control: Newton from it fails
// within its 25 iterations, seen as more iterations than the fresh step's and the retake's).
TEST(JerkStart, AStepNewtonCannotTakeFromTheJerkIsTakenFromTheSecondOrderStart) {
    const robot_system sys(multibody::robot_lagrangian(
        std::make_shared<const multibody::tree>(test::random_tree(21))));
    const int n = sys.dimension();
    const scheme_spec spec(scheme_kind::gauss, 2);
    const newton_options o = iteration_of(iteration_kind::newton);
    const phase_state<dynamic> x{Eigen::VectorXd::LinSpaced(n, -0.8, 0.9),
                                 Eigen::VectorXd::LinSpaced(n, 1.0, -0.7)};
    std::vector<double> history{1.0}; // continues: a0, then where the last step ended
    for (int i = 0; i < n; ++i)
        history.push_back(1e10 * (i % 2 ? 1.0 : -1.0));
    history.insert(history.end(), x.q.data(), x.q.data() + n);
    history.insert(history.end(), x.p.data(), x.p.data() + n);
    general::stepper<multibody::robot_lagrangian> jerked(sys, 1e-3, spec, o),
        fresh(sys, 1e-3, spec, o);
    jerked.restore_history(x, history);
    phase_state<dynamic> y = x, z = x;
    const newton_report a = jerked.step(y), b = fresh.step(z);
    ASSERT_TRUE(a.converged);
    ASSERT_TRUE(b.converged);
    EXPECT_GT(a.iterations, b.iterations + 20); // the failed solve's iterations, then the retake's
    EXPECT_EQ(y.q, z.q);
    EXPECT_EQ(y.p, z.p);
    // A step that fails from both starts (a step of 0.5 s, one iteration allowed) leaves the
    // history as it was.
    newton_options one = o;
    one.max_iterations = 1;
    general::stepper<multibody::robot_lagrangian> failing(sys, 0.5, spec, one);
    failing.restore_history(x, history);
    std::vector<double> before, after;
    failing.save_history(before);
    phase_state<dynamic> w = x;
    ASSERT_FALSE(failing.step(w).converged);
    failing.save_history(after);
    EXPECT_EQ(after, before);
    EXPECT_EQ(before[0], 1.0); // the jerk's history, kept
}

// The contact step takes a step several times from one state: its inner stepper keeps Newton.
TEST(AutomaticIteration, TheContactStepKeepsNewton) {
    const robot_system sys = hanging_chain(30);
    general::stepper<multibody::robot_lagrangian> inner(sys, 1e-3,
                                                        scheme_spec(scheme_kind::gauss, 2));
    ASSERT_TRUE(inner.choice().on());
    const contact::contact_stepper<general::stepper<multibody::robot_lagrangian>> touching(
        inner, sys.lagrangian().shared(), {contact::ground(-20.0, 0.0, 1.0)});
    EXPECT_FALSE(touching.choice().on());
    EXPECT_FALSE(touching.with_step_size(5e-4).choice().on());
}

} // namespace
