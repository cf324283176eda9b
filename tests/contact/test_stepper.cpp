// Hard contact inside the variational step (contact/stepper.hpp): classical rigid-body contact
// problems against their closed forms, a free body on the ground (gauss-2 between contacts).
// Across contact events the step is of order one (its impulses act once per step), so the
// tolerances are a step's worth of the motion, C h with C from the problem, and the order is
// measured where the closed form is smooth (the slide down an incline).
//
// The state's momentum is the step's end momentum p_{j+1} = D₂L_d, before the next step's
// impulse (stepper.hpp, (K1)): a body held still on the ground by one impulse a step has, under
// gravity, the velocity −g h/2 along the normal there (4.9 mm/s at h = 1 ms), which the next
// impulse takes away; its position does not move. The checks of velocities at rest say so.
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "test_support.hpp"
#include "varsym/contact/stepper.hpp"
#include "varsym/multibody/floating.hpp"
#include "varsym/schemes/constrained.hpp"

namespace {

using namespace varsym;
using multibody::mat3;
using multibody::vec3;
using inner_stepper =
    general::constrained_stepper<multibody::free_robot, multibody::unit_quaternion>;
using touching = contact::contact_stepper<inner_stepper>;
constexpr double g0 = 9.81;

/// A free body of 1 kg with one collision shape, on the ground z = x tan(slope).
struct scene {
    std::shared_ptr<const multibody::tree> tree;
    lagrangian_system<multibody::free_robot> sys;
    touching stepper;
    phase_state<dynamic> x;
    double e0;

    scene(multibody::collision_shape shape, const mat3& inertia, double slope, double mu,
          const vec<dynamic>& q, const vec<dynamic>& v, double h,
          std::vector<contact::obstacle> more = {})
        : tree(make(shape, inertia)), sys(multibody::free_robot(tree)),
          stepper(inner_stepper(sys, multibody::unit_quaternion{7}, h, {scheme_kind::gauss, 2}),
                  tree, with_ground(std::move(more), slope, mu)),
          x{q, sys.momentum(q, v)}, e0(sys.energy(x)) {}

    static std::vector<contact::obstacle> with_ground(std::vector<contact::obstacle> more,
                                                      double slope, double mu) {
        more.insert(more.begin(), contact::ground(0.0, slope, mu));
        return more;
    }

    static std::shared_ptr<const multibody::tree> make(multibody::collision_shape s,
                                                       const mat3& inertia) {
        multibody::tree m;
        m.root.link = m.root.name = s.link = "body";
        m.root.mass = 1.0;
        m.root.inertia = inertia;
        m.gravity = vec3(0.0, 0.0, -g0);
        m.collisions = {s};
        return std::make_shared<const multibody::tree>(m.with_base(multibody::base_kind::free));
    }
    /// Steps to time t; returns the largest penetration seen.
    double run(double t) {
        double deepest = 0.0;
        const auto n = std::lround(t / stepper.step_size());
        for (long j = 0; j < n; ++j) {
            const newton_report r = stepper.step(x);
            EXPECT_TRUE(r.converged) << stepper.diagnose(x);
            if (!r.converged) break;
            deepest = std::max(deepest, stepper.last_contact().penetration);
        }
        return deepest;
    }
    [[nodiscard]] vec<dynamic> velocity() const { return sys.velocity(x.q, x.p); }
    [[nodiscard]] double balance() const { return sys.energy(x) - e0 - stepper.total_work(); }
};

const double side = 0.2, radius = 0.1;
multibody::collision_shape box() {
    return {"", -1, {}, multibody::shape_kind::box, vec3::Constant(side), ""};
}
multibody::collision_shape ball() {
    return {"", -1, {}, multibody::shape_kind::sphere, vec3(radius, 0.0, 0.0), ""};
}
mat3 cube_inertia() {
    return vec3::Constant(side * side / 6.0).asDiagonal();
}
mat3 ball_inertia() {
    return vec3::Constant(0.4 * radius * radius).asDiagonal();
}

/// The box resting on the incline of `slope` (rotated by −slope about y), at rest.
vec<dynamic> on_incline(double slope) {
    vec<dynamic> q = vec<dynamic>::Zero(7);
    q(0) = -std::sin(slope) * side / 2;
    q(2) = std::cos(slope) * side / 2;
    q(3) = std::cos(-slope / 2);
    q(5) = std::sin(-slope / 2);
    return q;
}

TEST(Contact, ASlidingBoxStopsAtItsStoppingDistance) {
    // v0²/(2μg) = 0.40775 m for v0 = 2 m/s, μ = 0.5. The stop's time is off by less than a step
    // and the box is then slow: the distance's error is far below v0 h (2e-3); measured 1.6e-7
    // at h = 1 ms. It rests on its four bottom corners: normal impulse m g h per step.
    const double mu = 0.5, v0 = 2.0, h = 1e-3;
    vec<dynamic> q = vec<dynamic>::Zero(7), v = vec<dynamic>::Zero(7);
    q(2) = side / 2;
    q(3) = 1.0;
    v(0) = v0;
    scene s(box(), cube_inertia(), 0.0, mu, q, v, h);
    EXPECT_LE(s.run(0.6), 1e-12); // never below the ground (round-off of q: 4e-15)
    EXPECT_NEAR(s.x.q(0), v0 * v0 / (2 * mu * g0), 2e-6);
    EXPECT_LT((s.velocity().head<3>() - vec3(0.0, 0.0, -g0 * h / 2)).norm(), 1e-9);
    EXPECT_EQ(s.stepper.last_contact().active, 4);
    EXPECT_NEAR(s.stepper.last_contact().normal, g0 * h, 1e-12);
    EXPECT_NEAR(s.x.q(2), side / 2, 1e-9);
    // The contact's work is what friction took, v0²/2 J, less the resting state's ½ m (g h/2)²;
    // the scheme's own error is round-off.
    EXPECT_NEAR(s.stepper.contact_work(), -v0 * v0 / 2 + 0.5 * std::pow(g0 * h / 2, 2), 1e-9);
    EXPECT_LT(std::abs(s.balance()), 1e-12);
}

TEST(Contact, ABoxOnAnInclineSticksBelowTheFrictionAngle) {
    // tan 0.4 = 0.423 < μ = 0.5: no creep at all. Over 10 s at h = 1 ms the box's centre moves
    // less than 1e-6 m (measured 1.2e-8 m: the interior point's tolerance, 1e-12 m a step).
    const double slope = 0.4;
    const vec<dynamic> q = on_incline(slope);
    scene s(box(), cube_inertia(), slope, 0.5, q, vec<dynamic>::Zero(7), 1e-3);
    EXPECT_LE(s.run(10.0), 1e-12);
    EXPECT_LT((s.x.q.head<3>() - q.head<3>()).norm(), 1e-6);
}

TEST(Contact, ABoxSlidesDownASteeperInclineAtTheCoulombAcceleration) {
    // tan 0.6 = 0.684 > μ = 0.5: a = g (sin θ − μ cos θ) = 1.4909 m/s² along the slope. The
    // speed at t = 1 s converges to a t at order one (the impulses act once per step): the
    // error halves with h (measured 2.02e-3 and 1.01e-3 m/s at h = 1 and 0.5 ms).
    const double slope = 0.6, mu = 0.5, a = g0 * (std::sin(slope) - mu * std::cos(slope));
    double error[2];
    const vec3 down(-std::cos(slope), 0.0, -std::sin(slope)),
        normal(-std::sin(slope), 0.0, std::cos(slope));
    for (const int i : {0, 1}) {
        const double h = i == 0 ? 1e-3 : 5e-4;
        scene s(box(), cube_inertia(), slope, mu, on_incline(slope), vec<dynamic>::Zero(7), h);
        EXPECT_LE(s.run(1.0), 1e-12);
        const vec3 v = s.velocity().head<3>();
        error[i] = std::abs(v.dot(down) - a * 1.0);
        // The error is the end momentum's half step of friction, μ g cos θ h/2 (the impulse the
        // next step applies), to round-off: measured 8e-12 m/s off it at h = 1 ms.
        EXPECT_NEAR(v.dot(down), a * 1.0 + mu * g0 * std::cos(slope) * h / 2, 1e-9);
        EXPECT_NEAR(v.dot(normal), -g0 * std::cos(slope) * h / 2, 1e-9); // held on the slope
        EXPECT_NEAR(v.dot(vec3::UnitY()), 0.0, 1e-12);
        EXPECT_LT(std::abs(s.balance()), 1e-11);
    }
    EXPECT_NEAR(error[0] / error[1], 2.0, 0.01) << error[0] << " " << error[1];
}

TEST(Contact, ASlidingBallEndsRollingAtFiveSeventhsOfItsSpeed) {
    // A ball thrown without spin slides; friction slows it and spins it up until v = ω r, at
    // 5/7 of v0 (I = 2/5 m r²), after 2 v0/(7 μ g) = 0.29 s. Then it rolls: no friction acts.
    const double v0 = 2.0, mu = 0.2, h = 1e-3;
    vec<dynamic> q = vec<dynamic>::Zero(7), v = vec<dynamic>::Zero(7);
    q(2) = radius;
    q(3) = 1.0;
    v(0) = v0;
    scene s(ball(), ball_inertia(), 0.0, mu, q, v, h);
    EXPECT_LE(s.run(1.0), 1e-12);
    const vec<dynamic> rate = s.velocity();
    const auto motion = s.sys.lagrangian().motion(s.x.q, rate);
    // The speed: O(h) off 5/7 v0 (the step's impulses), measured 1.4e-5 m/s at h = 1 ms.
    EXPECT_NEAR(rate(0), 5.0 / 7.0 * v0, 1.5e-4);
    // Rolling without slip: the contact point's material point does not slide over a step,
    // v h = r sin(ω h), so ω r = v (1 + (ωh)²/6 + …): 4.9e-5 m/s at ω = 14.3 rad/s.
    const double omega = motion.angular_velocity.y();
    EXPECT_NEAR(omega * radius, rate(0) * (1.0 + std::pow(omega * h, 2) / 6), 1e-8);
    EXPECT_LT(s.stepper.last_contact().friction, 1e-9);
    EXPECT_LT(std::abs(s.balance()), 1e-11);
}

TEST(Contact, ADroppedBallComesToRestAtItsRadiusNeverBelow) {
    // Dropped from 0.3 m: free fall (no contact: the step is gauss-2's, exact for a parabola),
    // an inelastic impact, then rest on the ground at z = r.
    const double h = 1e-3;
    vec<dynamic> q = vec<dynamic>::Zero(7);
    q(2) = radius + 0.3;
    q(3) = 1.0;
    scene s(ball(), ball_inertia(), 0.0, 1.0, q, vec<dynamic>::Zero(7), h);
    s.run(0.2);
    EXPECT_EQ(s.stepper.last_contact().iterations, 0); // still falling
    EXPECT_NEAR(s.x.q(2), radius + 0.3 - 0.5 * g0 * 0.04, 1e-12);
    EXPECT_LE(s.run(0.8), 1e-12);
    EXPECT_NEAR(s.x.q(2), radius, 1e-9);
    EXPECT_GE(s.x.q(2), radius - 1e-15);
    EXPECT_LT((s.velocity().head<3>() - vec3(0.0, 0.0, -g0 * h / 2)).norm(), 1e-9);
    // The impact took the kinetic energy m g 0.3 J (less the resting state's ½ m (g h/2)²).
    EXPECT_NEAR(s.stepper.contact_work(), -g0 * 0.3 + 0.5 * std::pow(g0 * h / 2, 2), 1e-9);
}

TEST(Contact, TheTangentMapIsGivenInFlightAndRefusedAcrossAContact) {
    // In flight the step is gauss-2's own, exact for a parabola: the centre's position moves by
    // h p/m, so ∂x_{j+1}/∂p_j = (h/m) I for the translation (m = 1 kg). On the ground the step
    // is not differentiable (the impulses switch on and off): both maps are refused.
    const double h = 1e-3;
    vec<dynamic> q = vec<dynamic>::Zero(7);
    q(2) = radius + 0.3;
    q(3) = 1.0;
    scene s(ball(), ball_inertia(), 0.0, 1.0, q, vec<dynamic>::Zero(7), h);
    s.run(0.1);
    const phase_state<dynamic> from = s.x;
    s.run(h);
    ASSERT_EQ(s.stepper.last_contact().iterations, 0); // in flight
    Eigen::MatrixXd sq, j;
    s.stepper.position_sensitivity(from, sq);
    ASSERT_EQ(sq.rows(), 7);
    ASSERT_EQ(sq.cols(), 7);
    EXPECT_LE(
        (sq.topLeftCorner<3, 3>() - h * Eigen::Matrix3d::Identity()).lpNorm<Eigen::Infinity>(),
        1e-15);
    s.stepper.step_jacobian(from, j);
    EXPECT_LE((sq - j.block(0, 7, 7, 7)).lpNorm<Eigen::Infinity>(), 1e-15);
    s.run(0.5);
    ASSERT_GT(s.stepper.last_contact().iterations, 0); // resting on the ground
    EXPECT_THROW(s.stepper.position_sensitivity(s.x, sq), std::invalid_argument);
    EXPECT_THROW(s.stepper.step_jacobian(s.x, j), std::invalid_argument);
}

TEST(Contact, ABallLandsOnAStepAndStopsAtAWall) {
    // A step 0.2 m high (a box from x = 1 to 3): a ball dropped on it rests at 0.2 + r; a
    // frictionless ball sliding at 1 m/s into its side stops there, its centre at x = 1 − r (the
    // impact is inelastic: the normal velocity is removed, not reversed).
    const contact::obstacle step =
        contact::static_box(vec3(2.0, 0.0, 0.1), vec3(2.0, 2.0, 0.2), 0.0, "step");
    vec<dynamic> q = vec<dynamic>::Zero(7), v = vec<dynamic>::Zero(7);
    q(0) = 1.5;
    q(2) = 0.5;
    q(3) = 1.0;
    scene on(ball(), ball_inertia(), 0.0, 0.0, q, v, 1e-3, {step});
    EXPECT_LE(on.run(1.0), 1e-12);
    EXPECT_NEAR(on.x.q(2), 0.2 + radius, 1e-9);
    q(0) = 0.0;
    q(2) = radius;
    v(0) = 1.0;
    scene wall(ball(), ball_inertia(), 0.0, 0.0, q, v, 1e-3, {step});
    EXPECT_LE(wall.run(1.5), 1e-12);
    // Against the wall without pressing, the contact is degenerate (γ = 0 and φ = 0): the
    // interior point leaves impulses of the order of its tolerance's square root there, which
    // purification removes where the gap is open; what is left moved the ball 4e-9 m in 1 s.
    EXPECT_NEAR(wall.x.q(0), 1.0 - radius, 1e-7);
    EXPECT_NEAR(wall.velocity()(0), 0.0, 1e-7);
    EXPECT_NEAR(wall.x.q(2), radius, 1e-9);
}

/// The box dropped 1 cm onto the ground (μ = 0.5) sliding at 1 m/s and spinning at 0.4 rad/s
/// about its vertical axis, h = 1 ms: it lands, slides and comes to rest within 0.6 s.
scene spinning_box() {
    vec<dynamic> q = vec<dynamic>::Zero(7), v = vec<dynamic>::Zero(7);
    q(2) = side / 2 + 0.01;
    q(3) = 1.0;
    v(0) = 1.0;
    v(5) = 0.4;
    return {box(), cube_inertia(), 0.0, 0.5, q, v, 1e-3};
}

TEST(Contact, AResumedStepperTakesTheSameSteps) {
    // The history (the inner stepper's matrix kept across steps and its multipliers, the warm
    // start, the contact's work, the last report) carries a run across a checkpoint: 300 steps
    // straight, and 150 + a copy restored from the saved history + 150, while the box slides
    // and spins (from 150 and 300 steps) and again from 600 steps, where it rests. The warm
    // steps iterate with the kept matrix: a copy restored without it ends elsewhere
    // (mutation-checked).
    std::vector<double> history;
    for (const double split : {0.15, 0.3, 0.6}) {
        SCOPED_TRACE("resumed at t = " + std::to_string(split));
        scene straight = spinning_box();
        straight.run(split + 0.15);
        scene first = spinning_box();
        first.run(split);
        if (split > 0.5) {
            ASSERT_LT(first.velocity().norm(), 1e-2); // at rest on the ground
            ASSERT_GT(first.stepper.last_contact().iterations, 0);
        }
        history.clear();
        first.stepper.save_history(history);
        scene second = spinning_box();
        second.stepper.summation().restore(first.x, first.stepper.summation().carry_q(),
                                           first.stepper.summation().carry_p());
        second.stepper.restore_history(first.x, history);
        second.stepper.set_time(first.stepper.time());
        second.x = first.x;
        second.run(0.15);
        EXPECT_EQ(second.x.q, straight.x.q);
        EXPECT_EQ(second.x.p, straight.x.p);
        EXPECT_EQ(second.stepper.contact_work(), straight.stepper.contact_work());
    }
    // A history this stepper did not write is refused, not misread.
    scene other = spinning_box();
    ASSERT_GE(history.size(), 10U);
    std::vector<double> short_one{1.0, 2.0, 3.0}, counted = history, untagged = history,
                                                  older = history, old = history, kept = history;
    counted[history.size() - 10] = 1e9; // more contacts than numbers
    untagged[history.size() - 9] = 0.0; // not the tag
    older[history.size() - 9] = 6.2e7;  // the layout before the kept matrix
    old[history.size() - 9] = 6.3e7;    // the layout before the kept miss
    const auto contacts = static_cast<std::size_t>(history[history.size() - 10]);
    ASSERT_GT(contacts, 0U);
    const std::size_t kept_count = history.size() - 10 - 4 * contacts - 1;
    ASSERT_GT(history[kept_count], 0.0); // the box rests: its matrix is kept
    kept[kept_count] += 1.0;             // not this stepper's size
    // The two earlier layouts' tags get their own message; an unknown tag would be refused
    // anyway, so the message is what tells the older-layout branch ran.
    const auto refusal = [&](const std::vector<double>& bad) -> std::string {
        try {
            other.stepper.restore_history(other.x, bad);
        } catch (const std::invalid_argument& e) {
            return e.what();
        }
        return "accepted";
    };
    for (const auto* bad : {&short_one, &counted, &untagged, &kept}) {
        const std::string said = refusal(*bad);
        EXPECT_NE(said, "accepted");
        EXPECT_EQ(said.find("older layout"), std::string::npos) << said;
    }
    for (const auto* bad : {&older, &old})
        EXPECT_NE(refusal(*bad).find("older layout"), std::string::npos) << refusal(*bad);
}

/// The inner stepper, recording the momentum each of its steps starts from: a contact step's
/// free step starts from p_j itself, the others from p_j + Jᵀλ.
struct recording : inner_stepper {
    explicit recording(inner_stepper s) : inner_stepper(std::move(s)) {}
    std::vector<vec<dynamic>> starts;
    newton_report step(phase_state<dynamic>& x) {
        starts.push_back(x.p);
        return inner_stepper::step(x);
    }
};

TEST(Contact, AWarmStartedStepEndsWhereAColdOneEnds) {
    // With the last step's contacts, a step takes no free step: the step with the last impulses
    // comes first and estimates the free step's end (stepper.hpp). A stepper without that
    // history, from the same state, takes the free step and starts from λ = 0. Where the
    // contacts are closed at q_j (no onset within the step: the box on its corners) both solve
    // the same equations, so their ends agree to the contact tolerance: 1e-12 m on the gaps and
    // slips, so about 1e-12 in q and, through S ~ h/m, 1e-9 N s in p. While the box slides and
    // spins (t = 0.15 s) and at rest (0.6 s).
    for (const double t : {0.15, 0.6}) {
        SCOPED_TRACE("at t = " + std::to_string(t));
        scene before = spinning_box();
        before.run(t);
        ASSERT_GE(before.stepper.last_contact().active, 3); // pressing: the next step is warm
        // The warm stepper: that run's history (its contacts, impulses and predictor) restored.
        std::vector<double> history;
        before.stepper.save_history(history);
        contact::contact_stepper<recording> warm(
            recording(inner_stepper(before.sys, multibody::unit_quaternion{7}, 1e-3,
                                    {scheme_kind::gauss, 2})),
            before.tree, scene::with_ground({}, 0.0, 0.5));
        warm.restore_history(before.x, history);
        warm.set_time(before.stepper.time());
        scene cold = spinning_box();
        cold.x = before.x;
        cold.stepper.set_time(before.stepper.time());
        phase_state<dynamic> x = before.x;
        ASSERT_TRUE(warm.step(x).converged);
        ASSERT_TRUE(cold.stepper.step(cold.x).converged);
        // No free step: the first inner step had the last impulses (a negative control of the
        // comparison below, which a fall back to the cold path would also pass).
        ASSERT_FALSE(warm.starts.empty());
        EXPECT_GT((warm.starts.front() - before.x.p).norm(), 1e-4);
        EXPECT_GE(cold.stepper.last_contact().active, 3);
        const double dq = (x.q - cold.x.q).lpNorm<Eigen::Infinity>(),
                     dp = (x.p - cold.x.p).lpNorm<Eigen::Infinity>();
        RecordProperty("warm_cold_q_at_" + test::sci(t), test::sci(dq));
        RecordProperty("warm_cold_p_at_" + test::sci(t), test::sci(dp));
        EXPECT_LT(dq, 1e-11);
        EXPECT_LT(dp, 1e-8);
        EXPECT_NEAR(warm.last_contact().normal, cold.stepper.last_contact().normal, 1e-8);
    }
}

TEST(Contact, AStepThatDoesNotConvergeSaysByHowMuchAndKeepsTheState) {
    // One linearisation allowed: the box's landing (from λ = 0 at the free step's end) needs
    // more. The step fails, leaves the state as it was, and names the miss in metres in a form
    // that shows it (std::to_string printed 1e-10 as 0.000000).
    scene s = spinning_box();
    touching one(inner_stepper(s.sys, multibody::unit_quaternion{7}, 1e-3, {scheme_kind::gauss, 2}),
                 s.tree, scene::with_ground({}, 0.0, 0.5), {1e-12, 1});
    newton_report r;
    phase_state<dynamic> before = s.x;
    for (int j = 0; j < 200; ++j) {
        before = s.x;
        if (!(r = one.step(s.x)).converged) break;
    }
    ASSERT_FALSE(r.converged) << "200 steps converged in one linearisation each";
    EXPECT_EQ(s.x.q, before.q);
    EXPECT_EQ(s.x.p, before.p);
    const std::string why = one.diagnose(s.x);
    const std::size_t at = why.find("off their linearisation by ");
    ASSERT_NE(at, std::string::npos) << why;
    EXPECT_NE(why.find("did not converge in 1 linearisations"), std::string::npos) << why;
    const double miss = std::stod(why.substr(at + 27));
    EXPECT_GT(miss, 1e-12) << why;
    EXPECT_EQ(why.find("0.000000"), std::string::npos) << why;
}

TEST(Contact, WithoutFrictionTheBoxDoesNotStop) {
    // Negative control for the sliding box: μ = 0 keeps its speed.
    vec<dynamic> q = vec<dynamic>::Zero(7), v = vec<dynamic>::Zero(7);
    q(2) = side / 2;
    q(3) = 1.0;
    v(0) = 2.0;
    scene s(box(), cube_inertia(), 0.0, 0.0, q, v, 1e-3);
    s.run(0.6);
    EXPECT_NEAR(s.velocity()(0), 2.0, 1e-9);
    EXPECT_NEAR(s.x.q(0), 1.2, 1e-9);
}

} // namespace
