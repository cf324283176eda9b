// URDF robots (varsym/models/robot.hpp): real robots load with their joints, limits and damping;
// the parser's frames, axes, inertial origins and fixed-joint merging against an independent
// Lagrangian (the planar linked pendulum, problems/linked_pendulum.hpp); the recursive
// derivatives on the real robots against AD of the second implementation; every refusal.
// Deep trees and mimic joints: test_urdf_trees.cpp.
#include <cmath>
#include <fstream>
#include <iterator>
#include <numbers>
#include <random>
#include <sstream>

#include <boost/numeric/odeint.hpp>
#include <gtest/gtest.h>

#include "multibody/reference_lagrangian.hpp"
#include "urdf_helpers.hpp"
#include "varsym/integrate.hpp"
#include "varsym/models/robot.hpp"
#include "varsym/multibody/lagrangian.hpp"
#include "varsym/problems/linked_pendulum.hpp"
#include "varsym/schemes/variational_failure.hpp"

namespace {

using namespace varsym;
using namespace urdf_test;

TEST(Urdf, RealRobotsLoadWithTheirJointsLimitsAndDamping) {
    const auto iiwa = models::load_urdf(data("iiwa14_no_collision.urdf"));
    ASSERT_EQ(iiwa->dof(), 7); // the <joint> elements inside <transmission> are not joints
    EXPECT_EQ(iiwa->bodies[0].name, "iiwa_joint_1");
    EXPECT_EQ(iiwa->bodies[6].name, "iiwa_joint_7");
    EXPECT_EQ(iiwa->bodies[1].limits.effort, 320.0);
    EXPECT_EQ(iiwa->bodies[6].limits.upper, 3.05432619099);
    EXPECT_EQ(iiwa->bodies[3].limits.damping, 0.5);
    EXPECT_DOUBLE_EQ(iiwa->bodies[6].mass, 1.2); // the massless ee links merged in: no change
    const auto ur5 = models::load_urdf(data("ur5_robot.urdf"));
    ASSERT_EQ(ur5->dof(), 6);
    EXPECT_EQ(ur5->bodies[2].name, "elbow_joint");
    EXPECT_EQ(ur5->bodies[0].limits.velocity, 3.15);
}

/// A planar pendulum of three links as URDF: revolute joints about y, each link a mass m_i
/// split into two halves δ above and below its end (the second half a fixed child link whose
/// frame is turned by 90° about z, its inertia given in that frame), hanging along −z. Its
/// Lagrangian in absolute angles θ = B⁻¹φ is the linked pendulum's with masses m_i, lengths
/// l_i and rotational inertias J_i = a_i + b_i + m_i δ² (a_i: the link's own iyy; b_i: the
/// child's ixx, which the turn makes its iyy).
std::string planar_pendulum_urdf(bool joints_first) {
    const double m[] = {1.0, 0.8, 0.5}, l[] = {1.0, 0.7, 0.4}, a[] = {0.01, 0.02, 0.005},
                 b[] = {0.03, 0.01, 0.002}, delta = 0.1;
    std::ostringstream links, joints;
    links.precision(17);
    joints.precision(17);
    links << "<link name=\"base\"/>\n";
    for (int i = 0; i < 3; ++i) {
        links << "<link name=\"l" << i << "\"><inertial><origin xyz=\"0 0 " << -l[i] + delta
              << "\"/><mass value=\"" << m[i] / 2 << "\"/><inertia ixx=\"" << a[i] << "\" iyy=\""
              << a[i] << "\" izz=\"" << a[i]
              << "\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial></link>\n"
              << "<link name=\"tip" << i << "\"><inertial><mass value=\"" << m[i] / 2
              << "\"/><inertia ixx=\"" << b[i] << "\" iyy=\"" << 2 * b[i] << "\" izz=\"" << 2 * b[i]
              << "\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial></link>\n";
        joints << "<joint name=\"j" << i << "\" type=\"" << (i == 1 ? "continuous" : "revolute")
               << "\"><parent link=\"" << (i == 0 ? "base" : "l" + std::to_string(i - 1))
               << "\"/><child link=\"l" << i << "\"/><origin xyz=\"0 0 "
               << (i == 0 ? 0.0 : -l[i - 1]) << "\"/><axis xyz=\"0 1 0\"/>"
               << "<limit lower=\"-3\" upper=\"3\" effort=\"10\" velocity=\"5\"/></joint>\n"
               << "<joint name=\"fix" << i << "\" type=\"fixed\"><parent link=\"l" << i
               << "\"/><child link=\"tip" << i << "\"/><origin xyz=\"0 0 " << -l[i] - delta
               << "\" rpy=\"0 0 " << std::numbers::pi / 2 << "\"/></joint>\n";
    }
    const std::string body = joints_first ? joints.str() + links.str() : links.str() + joints.str();
    return "<?xml version=\"1.0\"?>\n<robot name=\"planar3\">\n" + body +
           "<transmission name=\"t\"><joint name=\"j0\"/></transmission>\n"
           "<gazebo reference=\"l0\"><mu1>0.2</mu1></gazebo>\n</robot>\n";
}

TEST(Urdf, FramesAxesInertialOriginsAndFixedMergesMatchTheLinkedPendulum) {
    // Independent reference: the linked pendulum's closed-form L (a_ij cos(θ_i − θ_j) terms),
    // which shares nothing with the parser or the recursive algorithms. Agreement to 1e-13
    // relative: both are sums of a few dozen O(1) terms.
    const double delta = 0.1;
    const linked_pendulum::lagrangian<3> lp({1.0, 0.8, 0.5}, {1.0, 0.7, 0.4}, 9.81,
                                            {0.01 + 0.03 + 1.0 * delta * delta,
                                             0.02 + 0.01 + 0.8 * delta * delta,
                                             0.005 + 0.002 + 0.5 * delta * delta});
    for (const bool joints_first : {false, true}) {
        const multibody::robot_lagrangian robot(
            models::parse_urdf(planar_pendulum_urdf(joints_first)));
        ASSERT_EQ(robot.dimension(), 3);
        EXPECT_EQ(robot.robot().bodies[1].limits.upper, std::numeric_limits<double>::infinity())
            << "a continuous joint has no position limits";
        vec<3> theta(0.4, -0.9, 1.7), omega(1.3, -0.6, 2.1);
        vec<dynamic> phi(3), phid(3); // joint angles φ = Bθ
        phi << theta(0), theta(1) - theta(0), theta(2) - theta(1);
        phid << omega(0), omega(1) - omega(0), omega(2) - omega(1);
        const double expected = lp(theta, omega);
        EXPECT_NEAR(robot(phi, phid), expected, 1e-13 * std::abs(expected));
        // M in joint angles: B⁻ᵀ M_θ B⁻¹ (B⁻¹ the cumulative sums).
        lagrangian_terms<3> t;
        lp.derivatives(theta, omega, t);
        mat<3> binv = mat<3>::Zero();
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j <= i; ++j)
                binv(i, j) = 1.0;
        const mat<3> m_phi = binv.transpose() * t.lvv * binv;
        lagrangian_terms<dynamic> r;
        robot.derivatives(phi, phid, r);
        EXPECT_LT((r.lvv - m_phi).cwiseAbs().maxCoeff(), 1e-13 * m_phi.cwiseAbs().maxCoeff());
        // ∂L/∂φ = B⁻ᵀ ∂L/∂θ at fixed velocities in the same coordinates.
        EXPECT_LT((r.lq - binv.transpose() * t.lq).cwiseAbs().maxCoeff(),
                  1e-12 * t.lq.cwiseAbs().maxCoeff());
    }
}

TEST(Urdf, FramesAreWrongIfTheMergedChildIsNotTurned) {
    // Negative control for the test above: without its 90° turn the fixed child contributes its
    // iyy = 2b instead of b, and L differs.
    std::string text = planar_pendulum_urdf(false);
    ASSERT_NE(text.find("rpy=\"0 0 1.5707963267948966\""), std::string::npos);
    std::size_t at;
    while ((at = text.find("rpy=\"0 0 1.5707963267948966\"")) != std::string::npos)
        text.replace(at, 28, "rpy=\"0 0 0\"");
    const multibody::robot_lagrangian robot(models::parse_urdf(text));
    const multibody::robot_lagrangian right(models::parse_urdf(planar_pendulum_urdf(false)));
    vec<dynamic> phi(3), phid(3);
    phi << 0.4, -1.3, 2.6;
    phid << 1.3, -1.9, 2.7;
    EXPECT_GT(std::abs(robot(phi, phid) - right(phi, phid)), 1e-3);
}

template <int D>
void check_against_reference(const std::string& file) {
    const auto model = models::load_urdf(data(file));
    ASSERT_EQ(model->dof(), D);
    const multibody::robot_lagrangian robot(model);
    const test::reference_lagrangian<D> ref{model.get()};
    std::mt19937 g(5);
    std::uniform_real_distribution<double> u(-2.5, 2.5);
    for (int k = 0; k < 4; ++k) {
        vec<D> q, v;
        for (int i = 0; i < D; ++i) {
            q(i) = u(g);
            v(i) = u(g);
        }
        lagrangian_terms<D> e;
        evaluate(ref, q, v, e);
        lagrangian_terms<dynamic> t;
        robot.derivatives(q, v, t);
        auto gap = [](const auto& a, const auto& b) {
            return (a - b).cwiseAbs().maxCoeff() / std::max(1.0, b.cwiseAbs().maxCoeff());
        };
        // Round-off of O(10²) operations on O(1–100) numbers: 1e-12 relative.
        EXPECT_LT(gap(t.lq, e.lq), 1e-12) << file << " dL/dq";
        EXPECT_LT(gap(t.lv, e.lv), 1e-12) << file << " dL/dqdot";
        EXPECT_LT(gap(t.lqq, e.lqq), 1e-12) << file << " d2L/dq2";
        EXPECT_LT(gap(t.lqv, e.lqv), 1e-12) << file << " d2L/dqdqdot";
        EXPECT_LT(gap(t.lvv, e.lvv), 1e-12) << file << " M(q)";
    }
}

TEST(Urdf, RecursiveDerivativesOfRealRobotsEqualAutomaticDifferentiation) {
    check_against_reference<7>("iiwa14_no_collision.urdf");
    check_against_reference<6>("ur5_robot.urdf");
    check_against_reference<9>("panda_fingers_free.urdf");
}

/// The UR5 swinging freely for 1 s from q0 at rest, by the models layer's simulation (the general
/// engine on the recursive derivatives) with scheme `spec` and step h: (q, q̇) at the end.
std::pair<vec<6>, vec<6>> ur5_swing(const scheme_spec& spec, double h, const vec<6>& q0) {
    const auto r = models::load_urdf(data("ur5_robot.urdf"));
    const models::model m = models::robot_model(r);
    const models::problem pr =
        m.prepare(m.defaults(), {std::vector<double>(q0.data(), q0.data() + 6), {}, {}});
    auto sim = pr.simulate({spec, {}, h});
    sim->advance(static_cast<std::size_t>(std::llround(1.0 / h)));
    vec<6> q, p;
    for (int i = 0; i < 6; ++i) {
        q(i) = sim->q()[static_cast<std::size_t>(i)];
        p(i) = sim->p()[static_cast<std::size_t>(i)];
    }
    lagrangian_terms<dynamic> t;
    multibody::robot_lagrangian(r).derivatives(q, vec<dynamic>::Zero(6), t);
    return {q, t.lvv.llt().solve(p)}; // q̇ = M(q)⁻¹ p
}

TEST(Urdf, FreeSwingMatchesAnIndependentHighAccuracyIntegration) {
    // Reference: the Euler–Lagrange equations M q̈ = ∂L/∂q − (∂²L/∂q∂q̇)ᵀ q̇ of the second
    // implementation (reference_lagrangian.hpp, AD: no code shared with the multibody
    // algorithms), integrated by Odeint's Runge–Kutta–Fehlberg 7(8) at tolerance 1e-13.
    const auto r = models::load_urdf(data("ur5_robot.urdf"));
    const test::reference_lagrangian<6> ref{r.get()};
    using state = std::array<double, 12>;
    state y{};
    vec<6> q0;
    q0 << 0.0, -1.0, 1.0, 0.0, 0.5, 0.0;
    for (int i = 0; i < 6; ++i)
        y[static_cast<std::size_t>(i)] = q0(i);
    namespace odeint = boost::numeric::odeint;
    odeint::integrate_adaptive(
        odeint::make_controlled<odeint::runge_kutta_fehlberg78<state>>(1e-13, 1e-13),
        [&](const state& s, state& ds, double) {
            vec<6> q, v;
            for (int i = 0; i < 6; ++i) {
                q(i) = s[static_cast<std::size_t>(i)];
                v(i) = s[static_cast<std::size_t>(i + 6)];
            }
            lagrangian_terms<6> t;
            evaluate(ref, q, v, t);
            const vec<6> a = t.lvv.llt().solve(t.lq - t.lqv.transpose() * v);
            for (int i = 0; i < 6; ++i) {
                ds[static_cast<std::size_t>(i)] = v(i);
                ds[static_cast<std::size_t>(i + 6)] = a(i);
            }
        },
        y, 0.0, 1.0, 1e-4);
    vec<6> q_ref, v_ref;
    for (int i = 0; i < 6; ++i) {
        q_ref(i) = y[static_cast<std::size_t>(i)];
        v_ref(i) = y[static_cast<std::size_t>(i + 6)];
    }
    // gauss-4 (order 8) at h = 5 ms against RKF78 (tolerances 1e-13): measured 1.8e-13 in q and
    // 5.1e-13 in q̇ at 1 s; budget 1e-11 (55× and 20×), where 1e-9 let a lower order pass.
    const auto [q, v] = ur5_swing(scheme_spec(scheme_kind::gauss, 4), 0.005, q0);
    EXPECT_LT((q - q_ref).cwiseAbs().maxCoeff(), 1e-11) << q.transpose() << "\n"
                                                        << q_ref.transpose();
    EXPECT_LT((v - v_ref).cwiseAbs().maxCoeff(), 1e-11);
    // Negative control: the midpoint rule (order 2) at the same step is far off.
    const auto [q2, v2] = ur5_swing(scheme_spec(scheme_kind::gauss, 1), 0.005, q0);
    EXPECT_GT((q2 - q_ref).cwiseAbs().maxCoeff(), 1e-6);
}

TEST(Urdf, EnergyStaysBoundedOverAMillionStepsOfAPassiveArm) {
    // The UR5 swinging freely by gauss-2 at h = 1 ms for 10⁶ steps (1000 s): the relative energy
    // error stays below 1e-9 (measured max 6.9e-11, no trend). MuJoCo's RK4, of the same order,
    // drifts to 1.7e-8 over the same run (make bench-robots, docs/robots.md): a drift would
    // fail this bound.
    const models::model m = models::robot_model(models::load_urdf(data("ur5_robot.urdf")));
    std::vector<double> q0(6);
    for (std::size_t i = 0; i < 6; ++i)
        q0[i] = 0.4 + 0.3 * std::sin(1.7 * static_cast<double>(i));
    auto sim = m.prepare(m.defaults(), {q0, {}, {}})
                   .simulate({scheme_spec(scheme_kind::gauss, 2), {}, 1e-3});
    const double e0 = sim->watched_energy();
    double worst = 0.0;
    for (std::size_t k = 1000; k <= 1000000; k += 1000) {
        sim->advance(k); // to step k
        worst = std::max(worst, std::abs(sim->watched_energy() - e0) / std::abs(e0));
    }
    EXPECT_EQ(sim->step(), 1000000U);
    EXPECT_LT(worst, 1e-9);
    EXPECT_GT(worst, 0.0); // it was measured
}

TEST(Urdf, EachRefusalNamesTheElementAndWhatIsWrong) {
    EXPECT_EQ(refusal(robot("")), "") << "the good file behind every case below";
    EXPECT_NE(refusal(robot("", "floating")).find("floating joints are not supported"),
              std::string::npos);
    EXPECT_NE(refusal(robot("", "planar")).find("planar joints are not supported"),
              std::string::npos);
    EXPECT_NE(refusal(robot("", "screw")).find("unknown type 'screw'"), std::string::npos);
    EXPECT_NE(refusal(robot("", "revolute", "ixx=\"1\" iyy=\"1\" izz=\"-1\""))
                  .find("link b: the inertia tensor is not positive definite"),
              std::string::npos);
    EXPECT_NE(refusal(robot("", "revolute", "ixx=\"1\" iyy=\"1\" izz=\"3\""))
                  .find("link b: principal moments 1, 1, 3 kg m^2 break the triangle inequality "
                        "(the largest exceeds the sum of the others by 1"),
              std::string::npos);
    EXPECT_NE(refusal(robot("<link name=\"c\"/><joint name=\"k\" type=\"revolute\"><parent "
                            "link=\"b\"/><child link=\"c\"/></joint>"))
                  .find("test.urdf:1: <link>: link c moves (joint k) but has no <inertial>"),
              std::string::npos);
    EXPECT_NE(refusal(robot("<joint name=\"k\" type=\"revolute\"><parent link=\"a\"/><child "
                            "link=\"b\"/></joint>"))
                  .find("link b is already the child of joint j (a closed loop"),
              std::string::npos);
    EXPECT_NE(refusal(robot("<link name=\"c\"/>")).find("links a and c both have no parent"),
              std::string::npos);
    EXPECT_NE(refusal(robot("<joint name=\"k\" type=\"fixed\"><parent link=\"b\"/><child "
                            "link=\"zz\"/></joint>"))
                  .find("names link zz, which is not defined"),
              std::string::npos);
    EXPECT_NE(refusal("<robot name=\"r\"><link name=\"a\"></robot>").find("malformed XML"),
              std::string::npos);
    EXPECT_NE(refusal(robot("", "revolute", "ixx=\"1\" iyy=\"one\" izz=\"1\""))
                  .find("attribute iyy=\"one\" needs 1 finite number"),
              std::string::npos);
    try {
        (void)models::load_urdf(data("no_such_robot.urdf"));
        ADD_FAILURE() << "a missing file";
    } catch (const models::urdf_error& e) {
        // "cannot open the URDF file" before the reads of regular files only (issue 60, item 7).
        const std::string what = e.what();
        EXPECT_TRUE(what.find("cannot open the URDF file") != std::string::npos ||
                    what.find("cannot read URDF file") != std::string::npos)
            << what;
    }
}

} // namespace
