// Task-space ends (optimal::control_problem::end_target with models::frame_target): a URDF
// link's target pose at T, as a constraint or a terminal cost. Against independent references:
// the transcription's derivatives against finite differences; a non-redundant arm (the UR5, six
// joints, a full pose) reaching the pose of a joint-space problem's end must reproduce that
// problem's optimum and end joints; on the redundant iiwa the optimum can only be lower than the
// joint-space one (whose motion is feasible for it); the terminal cost's optima rise towards the
// constraint's as the weight grows; an unreachable target is infeasible.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "../optimal/fixtures.hpp"
#include "varsym/models/model.hpp"
#include "varsym/models/robot.hpp"
#include "varsym/multibody/spatial.hpp"
#include "varsym/optimize/model.hpp"
#include "varsym/optimize/solve.hpp"

using namespace varsym;

namespace {

std::shared_ptr<const multibody::tree> reach_robot(const std::string& file) {
    return models::load_urdf(VARSYM_TEST_DATA "/urdf/" + file);
}

optimal::control_problem reach_problem(const Eigen::VectorXd& from, const Eigen::VectorXd& to,
                                       int steps) {
    optimal::control_problem p;
    p.time = 2.0;
    p.steps = steps;
    p.q_start = from;
    p.q_end = to;
    p.v_start = p.v_end = Eigen::VectorXd::Zero(from.size());
    return p;
}

const Eigen::VectorXd iiwa_end =
    (Eigen::VectorXd(7) << 0.4, 0.3, 0.2, -0.3, 0.2, 0.3, 0.2).finished();

/// The robot's transcription of p within its URDF limits.
std::unique_ptr<optimal::transcription> limited(const models::model& m,
                                                const optimal::control_problem& p) {
    optimal::control_problem q = p;
    m.limits(m.defaults(), {}, q);
    return optimal::transcribe(m, m.defaults(), {}, q);
}

optimal::nlp_result solve_reach(const models::model& m, const optimal::control_problem& p,
                                const Eigen::VectorXd* start = nullptr) {
    return optimal::solve(*limited(m, p), {}, start);
}

} // namespace

TEST(Reach, FrameTargetJacobianMatchesFiniteDifferences) {
    // φ = (origin miss; 2 sin(θ/2) n) of the iiwa's flange against central differences of φ
    // itself (step 1e-6: error about 1e-10), at a pose 1.2 rad off the target orientation.
    const auto r = reach_robot("iiwa14_no_collision.urdf");
    const auto phi = models::frame_target(r, "iiwa_link_ee", {0.4, 0.1, 0.9},
                                          multibody::roll_pitch_yaw({0.2, 1.0, -0.4}));
    const Eigen::VectorXd q = Eigen::VectorXd::LinSpaced(7, -0.6, 0.9);
    Eigen::VectorXd value, plus, minus;
    Eigen::MatrixXd jac, fd(6, 7);
    phi->evaluate(q, value, &jac);
    for (int j = 0; j < 7; ++j) {
        Eigen::VectorXd qs = q;
        qs(j) += 1e-6;
        phi->evaluate(qs, plus, nullptr);
        qs(j) -= 2e-6;
        phi->evaluate(qs, minus, nullptr);
        fd.col(j) = (plus - minus) / 2e-6;
    }
    EXPECT_LT((jac - fd).cwiseAbs().maxCoeff(), 1e-8);
    EXPECT_GT(value.tail<3>().norm(), 0.5); // not vacuous: far from the target orientation
    // The miss in words agrees with φ: |φ_rot| = 2 sin(θ/2).
    const auto miss = models::frame_target_miss(*r, "iiwa_link_ee", q, {0.4, 0.1, 0.9},
                                                multibody::roll_pitch_yaw({0.2, 1.0, -0.4}));
    EXPECT_NEAR(value.tail<3>().norm(), 2.0 * std::sin(miss.angle / 2.0), 1e-12);
    EXPECT_NEAR(value.head<3>().norm(), miss.distance, 1e-12);
}

TEST(Reach, TranscriptionDerivativesWithATargetMatchFiniteDifferences) {
    // The target's rows (constraint) and its terminal cost (weight 50) in the transcription's
    // Jacobian and Hessian, against central differences (fixtures.hpp).
    const auto r = reach_robot("iiwa14_no_collision.urdf");
    const auto m = models::robot_model(r);
    for (const double weight : {0.0, 50.0}) {
        auto p = reach_problem(Eigen::VectorXd::Zero(7), iiwa_end, 2);
        p.end_target = models::frame_target(r, "iiwa_link_ee", {0.4, 0.2, 1.1},
                                            multibody::roll_pitch_yaw({0.4, -0.7, 0.6}));
        p.end_target_weight = weight;
        const auto tr = optimal::transcribe(m, m.defaults(), {}, p);
        const Eigen::VectorXd x =
            0.5 * Eigen::VectorXd::LinSpaced(tr->variables(), 0.3, 2.9).array().sin();
        const auto e = optimal_test::check_derivatives(
            *tr, x, 0.7, Eigen::VectorXd::LinSpaced(tr->constraints(), -1.0, 2.0));
        EXPECT_LT(e.jacobian, 1e-6 * e.largest_jacobian) << "weight " << weight;
        EXPECT_LT(e.hessian, 1e-6 * e.largest_hessian) << "weight " << weight;
        // The cost's gradient, the target's terminal cost included (measured 1.5e-10 and
        // 1.3e-8 of gradients up to 0.33 and 38: the differences' round-off); budget 1e-8
        // relative, 30× the larger.
        EXPECT_LT(e.gradient, 1e-8 * std::max(1.0, e.largest_gradient)) << "weight " << weight;
    }
}

namespace {

/// The UR5's flange pose by its Denavit–Hartenberg table as Universal Robots publish it
/// (standard DH: T_i = Rz(θ_i) Tz(d_i) Tx(a_i) Rx(α_i)), in the DH base frame.
multibody::pose ur5_dh(const Eigen::VectorXd& q, double alpha_4 = std::numbers::pi / 2) {
    const double pi = std::numbers::pi;
    const double d[6] = {0.089159, 0, 0, 0.10915, 0.09465, 0.0823},
                 a[6] = {0, -0.425, -0.39225, 0, 0, 0},
                 alpha[6] = {pi / 2, 0, 0, alpha_4, -pi / 2, 0};
    multibody::pose t;
    for (int i = 0; i < 6; ++i) {
        multibody::pose link;
        link.rotation = (Eigen::AngleAxisd(q(i), Eigen::Vector3d::UnitZ()) *
                         Eigen::AngleAxisd(alpha[i], Eigen::Vector3d::UnitX()))
                            .toRotationMatrix();
        link.origin =
            Eigen::AngleAxisd(q(i), Eigen::Vector3d::UnitZ()) * Eigen::Vector3d(a[i], 0.0, d[i]);
        t = t * link;
    }
    return t;
}

} // namespace

TEST(Reach, Ur5ToolPoseIsItsPublishedDenavitHartenbergKinematics) {
    // An independent reading of a real URDF's rotations, axes and offsets, run in every make
    // test: tool0 of ur5_robot.urdf against the UR5's published DH table (d1 = 0.089159,
    // a2 = −0.425, a3 = −0.39225, d4 = 0.10915, d5 = 0.09465, d6 = 0.0823 m; α = π/2, 0, 0, π/2,
    // −π/2, 0), which shares nothing with the URDF or its parser. ur_description puts the DH base
    // frame at the link "base" (base_link turned by π about z) and makes tool0 the DH flange.
    // Budget: the URDF writes π/2 and π to 12 digits (5e-12 rad each), times lengths ≤ 1 m over
    // six joints: 1e-10.
    const auto r = reach_robot("ur5_robot.urdf");
    const Eigen::Matrix3d turn = Eigen::AngleAxisd(std::numbers::pi, Eigen::Vector3d::UnitZ())
                                     .toRotationMatrix(); // world (base_link) from base
    for (const Eigen::VectorXd& q :
         {Eigen::VectorXd(Eigen::VectorXd::Zero(6)),
          Eigen::VectorXd((Eigen::VectorXd(6) << 0.5, -1.2, 0.6, -1.4, 0.4, 0.3).finished()),
          Eigen::VectorXd((Eigen::VectorXd(6) << -2.1, 0.7, 2.4, 1.9, -1.1, 2.8).finished())}) {
        const multibody::pose urdf = models::frame_pose_at(*r, "tool0", q), dh = ur5_dh(q);
        EXPECT_LT((urdf.origin - turn * dh.origin).cwiseAbs().maxCoeff(), 1e-10) << q.transpose();
        EXPECT_LT((urdf.rotation - turn * dh.rotation).cwiseAbs().maxCoeff(), 1e-10)
            << q.transpose();
        // Negative control: the DH table with α4 = −π/2 (one axis reversed) is far off.
        const multibody::pose wrong = ur5_dh(q, -std::numbers::pi / 2);
        EXPECT_GT((urdf.rotation - turn * wrong.rotation).cwiseAbs().maxCoeff(), 0.1);
    }
}

TEST(Reach, SixJointArmReachingAJointProblemsEndPoseReproducesItsOptimum) {
    // The UR5 has six joints: its tool pose fixes the joints up to a discrete choice of branch.
    // Reaching the pose of q_end, started near q_end, must give the joint-space problem's
    // optimum and end joints to IPOPT's tolerance.
    const auto r = reach_robot("ur5_robot.urdf");
    const auto m = models::robot_model(r);
    const Eigen::VectorXd from = (Eigen::VectorXd(6) << 0, -1.57, 0, -1.57, 0, 0).finished(),
                          to = (Eigen::VectorXd(6) << 0.5, -1.2, 0.6, -1.4, 0.4, 0.3).finished();
    const auto joints = solve_reach(m, reach_problem(from, to, 20));
    ASSERT_EQ(joints.verdict, optimal::status::solved) << joints.message;
    auto p = reach_problem(from, to + Eigen::VectorXd::Constant(6, 0.05), 20); // the guess
    const multibody::pose target = models::frame_pose_at(*r, "tool0", to);
    p.end_target = models::frame_target(r, "tool0", target.origin, target.rotation);
    const auto reach = solve_reach(m, p);
    ASSERT_EQ(reach.verdict, optimal::status::solved) << reach.message;
    EXPECT_NEAR(reach.cost, joints.cost, 1e-8 * joints.cost);
    const auto end = reach.x.segment(20 * 2 * 6, 6); // Simpson: Q_{2N}
    EXPECT_LT((end - to).cwiseAbs().maxCoeff(), 1e-7);
}

TEST(Reach, RedundantArmReachesAtNoMoreCostAndTheTerminalCostApproachesIt) {
    // The iiwa's flange to the position of the joint problem's end (3 rows on 7 joints): the
    // joint problem's motion meets the target, so the reach optimum is at most its cost (and
    // lower: the redundancy is used). With the terminal cost w/2 |φ|² instead, started from the
    // constrained optimum (to stay on its branch: the problem has other local optima), the
    // optimum is below the constrained one and rises towards it as w grows, the miss falling
    // like 1/w (the torques are O(100) N m: the weights that matter are large).
    const auto r = reach_robot("iiwa14_no_collision.urdf");
    const auto m = models::robot_model(r);
    const Eigen::VectorXd from = Eigen::VectorXd::Zero(7);
    const auto joints = solve_reach(m, reach_problem(from, iiwa_end, 20));
    ASSERT_EQ(joints.verdict, optimal::status::solved) << joints.message;
    auto p = reach_problem(from, from, 20); // the end guessed by the target's own search
    const Eigen::Vector3d goal = models::frame_pose_at(*r, "iiwa_link_ee", iiwa_end).origin;
    p.end_target = models::frame_target(r, "iiwa_link_ee", goal);
    const auto exact = solve_reach(m, p);
    ASSERT_EQ(exact.verdict, optimal::status::solved) << exact.message;
    EXPECT_LT(exact.cost, joints.cost * (1.0 - 1e-3));
    const auto path = limited(m, p)->unpack(exact);
    EXPECT_LT(models::frame_target_miss(*r, "iiwa_link_ee", path.q.col(20), goal).distance, 1e-10);
    double previous_cost = 0.0, previous_miss = 1.0;
    for (const double w : {1e5, 1e6, 1e7}) {
        p.end_target_weight = w;
        const auto soft = solve_reach(m, p, &exact.x);
        ASSERT_TRUE(soft.converged()) << soft.message;
        const double miss = models::frame_target_miss(*r, "iiwa_link_ee",
                                                      limited(m, p)->unpack(soft).q.col(20), goal)
                                .distance;
        EXPECT_GT(soft.cost, previous_cost) << w;
        EXPECT_LT(soft.cost, exact.cost) << w;
        EXPECT_LT(miss, previous_miss / 5.0) << w;
        previous_cost = soft.cost;
        previous_miss = miss;
    }
    EXPECT_NEAR(previous_cost, exact.cost, 1e-2 * exact.cost);
}

TEST(Reach, UnreachableTargetIsInfeasibleAndBadTargetsAreRefused) {
    // 2 m in front of a robot whose flange reaches about 1.3 m from its base: infeasible, and
    // the last iterate ends the flange well away from it.
    const auto r = reach_robot("iiwa14_no_collision.urdf");
    const auto m = models::robot_model(r);
    auto p = reach_problem(Eigen::VectorXd::Zero(7), Eigen::VectorXd::Zero(7), 20);
    p.end_target = models::frame_target(r, "iiwa_link_ee", {2.0, 0.0, 1.0});
    const auto out = solve_reach(m, p);
    EXPECT_EQ(out.verdict, optimal::status::infeasible) << out.message;
    const auto path = limited(m, p)->unpack(out);
    EXPECT_GT(
        models::frame_target_miss(*r, "iiwa_link_ee", path.q.col(20), {2.0, 0.0, 1.0}).distance,
        0.5);
    EXPECT_THROW((void)models::frame_target(r, "no_such_link", {0, 0, 1}), std::invalid_argument);
    EXPECT_THROW((void)models::frame_target(r, "base", {0, 0, 1}), std::invalid_argument);
    EXPECT_THROW(
        (void)models::frame_target(r, "iiwa_link_ee", {0, 0, 1}, Eigen::Matrix3d::Constant(0.5)),
        std::invalid_argument);
}

TEST(VelocityBounds, NodeVelocitiesAndTheirDerivativesMatchFiniteDifferences) {
    // The iiwa with its URDF limits (m.limits) at gauss-2, N = 3: q and q̇ at the steps' Gauss
    // points (not control values) are rows within the joint ranges and velocity limits; the
    // velocities at the two nodes between steps are unknowns within the velocity limits, each
    // such node's equation split in two (rows of bounds 0). The Jacobian against central
    // differences at a fixed horizon (with the Hessian: the split's ∂L/∂q̇(Q, V) brings L's third
    // derivatives) and at a free one.
    const auto m = models::robot_model(reach_robot("iiwa14_no_collision.urdf"));
    for (const bool free_time : {false, true}) {
        auto p = reach_problem(Eigen::VectorXd::Zero(7), iiwa_end, 3);
        p.scheme = {scheme_kind::gauss, 2};
        if (free_time) {
            p.free_time = true;
            p.cost.time = 1.0;
        }
        const auto tr = limited(m, p);
        const auto plain =
            optimal::transcribe(m, m.defaults(), {}, p); // no limits: no rows, no unknowns
        const int positions = 3 * 2 * 7, velocities = 3 * 2 * 7, splits = 2 * 7;
        ASSERT_EQ(tr->constraints(), plain->constraints() + positions + velocities + splits);
        ASSERT_EQ(tr->variables(), plain->variables() + splits);
        Eigen::VectorXd lower, upper;
        tr->constraint_bounds(lower, upper);
        EXPECT_EQ(lower.tail(splits + velocities + positions)(1), -2.09439510239); // joint 2
        EXPECT_EQ(upper.tail(splits + velocities)(0), 1.4835298641951802);         // joint 1's q̇
        EXPECT_EQ(upper.tail(splits).cwiseAbs().maxCoeff(), 0.0);                  // equations
        tr->bounds(lower, upper);
        const int v1 = plain->variables() - (free_time ? 1 : 0); // V_1 after the unknowns
        EXPECT_EQ(upper(v1), 1.4835298641951802);                // joint 1's URDF velocity
        EXPECT_EQ(lower(v1 + 3), -1.3089969389957472);           // joint 4's
        Eigen::VectorXd x =
            0.5 * Eigen::VectorXd::LinSpaced(tr->variables(), 0.3, 2.9).array().sin();
        if (free_time) x(x.size() - 1) = 1.5; // T
        const auto e = optimal_test::check_derivatives(
            *tr, x, 0.7, Eigen::VectorXd::LinSpaced(tr->constraints(), -1.0, 2.0));
        EXPECT_LT(e.jacobian, 1e-6 * e.largest_jacobian) << "free time " << free_time;
        // Measured 1e-10 and 4.6e-10 (of 0.17 and 1.7): budget 1e-8 relative, 20×.
        EXPECT_LT(e.gradient, 1e-8 * std::max(1.0, e.largest_gradient))
            << "free time " << free_time;
        EXPECT_LT(e.hessian, 1e-6 * e.largest_hessian) << "free time " << free_time;
    }
}

TEST(PositionBounds, HoldAtGaussPointsBetweenControlValues) {
    // gauss-2's quadrature points are not control values: its polynomials could pass a joint
    // limit between them. With the iiwa's joint ranges (velocity limits lifted, so that joint 6
    // rides its range), q at every quadrature point stays within the range, and one touches it.
    const auto m = models::robot_model(reach_robot("iiwa14_no_collision.urdf"));
    auto p = reach_problem(Eigen::VectorXd::Zero(7), iiwa_end, 20);
    p.scheme = {scheme_kind::gauss, 2};
    m.limits(m.defaults(), {}, p);
    p.velocity_lower = Eigen::VectorXd::Constant(7, -100.0);
    p.velocity_upper = Eigen::VectorXd::Constant(7, 100.0);
    const auto tr = optimal::transcribe(m, m.defaults(), {}, p);
    const auto r = optimal::solve(*tr);
    ASSERT_TRUE(r.converged()) << r.message;
    const auto path = tr->unpack(r);
    double closest = 1.0;
    for (Eigen::Index c = 0; c < path.control_times.size(); ++c) {
        const Eigen::VectorXd q = path.position(path.control_times(c));
        for (int i = 0; i < 7; ++i) {
            EXPECT_GE(q(i), p.position_lower(i) - 1e-9) << "joint " << i + 1;
            EXPECT_LE(q(i), p.position_upper(i) + 1e-9) << "joint " << i + 1;
            closest = std::min({closest, q(i) - p.position_lower(i), p.position_upper(i) - q(i)});
        }
    }
    EXPECT_LT(closest, 1e-6); // a range binds at a Gauss point
}
