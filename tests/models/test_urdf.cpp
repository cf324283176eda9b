// URDF robots (varsym/models/robot.hpp): real robots load with their joints, limits and damping;
// the parser's frames, axes, inertial origins and fixed-joint merging against an independent
// Lagrangian (the planar linked pendulum, problems/linked_pendulum.hpp); the recursive
// derivatives on the real robots against AD of the second implementation; every refusal.
#include <cmath>
#include <fstream>
#include <iterator>
#include <numbers>
#include <random>
#include <sstream>

#include <boost/numeric/odeint.hpp>
#include <gtest/gtest.h>

#include "multibody/reference_lagrangian.hpp"
#include "varsym/integrate.hpp"
#include "varsym/models/robot.hpp"
#include "varsym/multibody/lagrangian.hpp"
#include "varsym/problems/linked_pendulum.hpp"
#include "varsym/schemes/variational_failure.hpp"

namespace {

using namespace varsym;

std::string data(const std::string& file) { return VARSYM_TEST_DATA "/urdf/" + file; }

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
              << "\"/><mass value=\"" << m[i] / 2 << "\"/><inertia ixx=\"" << a[i]
              << "\" iyy=\"" << a[i] << "\" izz=\"" << a[i]
              << "\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial></link>\n"
              << "<link name=\"tip" << i << "\"><inertial><mass value=\"" << m[i] / 2
              << "\"/><inertia ixx=\"" << b[i] << "\" iyy=\"" << 2 * b[i] << "\" izz=\""
              << 2 * b[i] << "\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial></link>\n";
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
    const linked_pendulum::lagrangian<3> lp(
        {1.0, 0.8, 0.5}, {1.0, 0.7, 0.4}, 9.81,
        {0.01 + 0.03 + 1.0 * delta * delta, 0.02 + 0.01 + 0.8 * delta * delta,
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

/// The message of the urdf_error that parsing `xml` throws ("" if none).
std::string refusal(const std::string& xml) {
    try {
        (void)models::parse_urdf(xml, "test.urdf");
    } catch (const models::urdf_error& e) {
        return e.what();
    }
    return "";
}

std::string robot(const std::string& extra, const std::string& joint_type = "revolute",
                  const std::string& inertia = "ixx=\"1\" iyy=\"1\" izz=\"1\"") {
    return "<robot name=\"r\"><link name=\"a\"/><link name=\"b\"><inertial><mass value=\"1\"/>"
           "<inertia " +
           inertia + "/></inertial></link><joint name=\"j\" type=\"" + joint_type +
           "\"><parent link=\"a\"/><child link=\"b\"/><axis xyz=\"0 0 1\"/></joint>" + extra +
           "</robot>";
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

// Issue 60: trees of any size, names, overflowing numbers, limits, a second root, mimic.

/// A chain along z of links l0 (the root, massless) … ln, 1 mm apart: joint i joins l_i to
/// l_{i+1} at z = 1 mm in l_i's frame, about x, revolute where i % every == 0 and fixed else.
/// Each link but the root: 1 g at its origin, isotropic inertia 1e-9 kg m².
std::string chain_urdf(int n, int every) {
    std::string s = "<robot name=\"chain\">\n<link name=\"l0\"/>\n";
    s.reserve(static_cast<std::size_t>(n) * 330);
    for (int i = 1; i <= n; ++i)
        s += "<link name=\"l" + std::to_string(i) +
             "\"><inertial><mass value=\"0.001\"/><inertia ixx=\"1e-9\" iyy=\"1e-9\" "
             "izz=\"1e-9\"/></inertial></link>\n";
    for (int i = 0; i < n; ++i)
        s += "<joint name=\"j" + std::to_string(i) + "\" type=\"" +
             (i % every == 0 ? "revolute" : "fixed") + "\"><parent link=\"l" + std::to_string(i) +
             "\"/><child link=\"l" + std::to_string(i + 1) +
             "\"/><origin xyz=\"0 0 0.001\"/><axis xyz=\"1 0 0\"/></joint>\n";
    return s + "</robot>\n";
}

TEST(UrdfTrees, ATenThousandLinkChainOfRevoluteJointsLoads) {
    // The recursive walk of the tree overflowed the stack here (a segfault at ~8000 links).
    // Reference: at q = 0 the links stand on the z axis, link k at z = k d (d = 1 mm); turning
    // joint 0 at unit rate turns them all rigidly about the x axis through z = d, so
    // L(0, e_0) = ½ Σ_k (m ((k − 1) d)² + 1e-9) − Σ_k m g k d, a sum written out here.
    const int n = 10000;
    const auto r = models::parse_urdf(chain_urdf(n, 1));
    ASSERT_EQ(r->dof(), n);
    EXPECT_EQ(r->bodies[n - 1].parent, n - 2);
    double t = 0.0, v = 0.0;
    for (int k = 1; k <= n; ++k) {
        const double rk = (k - 1) * 1e-3;
        t += 0.5 * (1e-3 * rk * rk + 1e-9);
        v += 1e-3 * 9.81 * k * 1e-3;
    }
    const multibody::robot_lagrangian robot(r);
    vec<dynamic> q = vec<dynamic>::Zero(n), qd = vec<dynamic>::Zero(n);
    qd(0) = 1.0;
    // n terms of O(1e-4) to O(0.05) each, summed in two orders: 1e-12 relative.
    EXPECT_NEAR(robot(q, qd), t - v, 1e-12 * (t + v));
    lagrangian_terms<dynamic> g; // the O(n) first derivatives
    robot.gradient(q, qd, g);
    EXPECT_TRUE(g.lq.allFinite() && g.lv.allFinite());
    EXPECT_NEAR(g.lv(0), 2 * t, 1e-12 * t); // ∂L/∂q̇_0 = M_00 q̇_0 = 2T
}

TEST(UrdfTrees, ATenThousandLinkChainMostlyFixedMergesAndSteps) {
    // 10 000 links, every 1000th joint revolute: 10 bodies of 1000 merged links each. The
    // reference is the same robot written with the merge done by hand: per body mass 1 kg,
    // centre z̄ = 999 d / 2 above its joint's child link, I_xx = I_yy = Σ_j m (j d − z̄)² + 1e-6,
    // I_zz = 1e-6 kg m², the joints 1000 d apart.
    const int n = 10000, every = 1000;
    const auto r = models::parse_urdf(chain_urdf(n, every));
    ASSERT_EQ(r->dof(), n / every);
    EXPECT_EQ(r->frames.size(), static_cast<std::size_t>(n + 1));
    double zbar = 999 * 1e-3 / 2, ixx = 1e-6;
    for (int j = 0; j < every; ++j)
        ixx += 1e-3 * (j * 1e-3 - zbar) * (j * 1e-3 - zbar);
    std::ostringstream hand;
    hand.precision(17);
    hand << "<robot name=\"merged\"><link name=\"b0\"/>";
    for (int i = 1; i <= n / every; ++i)
        hand << "<link name=\"b" << i << "\"><inertial><origin xyz=\"0 0 " << zbar
             << "\"/><mass value=\"1\"/><inertia ixx=\"" << ixx << "\" iyy=\"" << ixx
             << "\" izz=\"1e-6\"/></inertial></link><joint name=\"j" << i - 1
             << "\" type=\"revolute\"><parent link=\"b" << i - 1 << "\"/><child link=\"b" << i
             << "\"/><origin xyz=\"0 0 " << (i == 1 ? 1e-3 : 1.0)
             << "\"/><axis xyz=\"1 0 0\"/></joint>";
    hand << "</robot>";
    const multibody::robot_lagrangian merged(r), by_hand(models::parse_urdf(hand.str()));
    std::mt19937 g(3);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int k = 0; k < 3; ++k) {
        vec<dynamic> q(10), qd(10);
        for (int i = 0; i < 10; ++i) {
            q(i) = u(g);
            qd(i) = u(g);
        }
        // 1000-term sums of the merge against 17 printed digits: 1e-12 relative.
        const double expected = by_hand(q, qd);
        EXPECT_NEAR(merged(q, qd), expected, 1e-12 * std::abs(expected));
    }
    // And it runs: 10 steps of gauss-2 at 1 ms conserve the energy to round-off.
    const models::model m = models::robot_model(r);
    auto sim = m.prepare(m.defaults(), {std::vector<double>(10, 0.3), {}, {}})
                   .simulate({scheme_spec(scheme_kind::gauss, 2), {}, 1e-3});
    const double e0 = sim->watched_energy();
    sim->advance(10);
    EXPECT_EQ(sim->step(), 10U);
    EXPECT_LT(std::abs(sim->watched_energy() - e0), 1e-9 * std::abs(e0));
    EXPECT_NE(sim->q()[0], 0.3); // it moved
}

TEST(UrdfTrees, NamesThatBreakColumnsOrKeysAreRefusedWithTheLine) {
    auto named = [](const std::string& joint, const std::string& link = "b") {
        return "<robot name=\"r\">\n<link name=\"a\"/>\n<link name=\"" + link +
               "\"><inertial><mass value=\"1\"/><inertia ixx=\"1\" iyy=\"1\" izz=\"1\"/>"
               "</inertial></link>\n<joint name=\"" +
               joint + "\" type=\"revolute\"><parent link=\"a\"/><child link=\"" + link +
               "\"/></joint>\n</robot>";
    };
    // Negative controls: a space inside a name and non-ASCII letters are kept.
    EXPECT_EQ(refusal(named("elbow joint")), "");
    EXPECT_EQ(refusal(named("Gelenk_\xC3\xA4", "Glied \xC3\xBC")), "");
    EXPECT_EQ(refusal(named("a,b")),
              "test.urdf:4: <joint>: joint name \"a,b\" has a ',' (names become CSV columns "
              "and keys: give one without , and \")");
    EXPECT_NE(refusal(named("a&quot;b")).find("test.urdf:4: <joint>: joint name \"a\"b\" has a '\"'"),
              std::string::npos);
    EXPECT_NE(refusal(named("a&#10;b")).find("test.urdf:4: <joint>: joint name \"a\\x0Ab\" has a "
                                             "control character"),
              std::string::npos);
    EXPECT_NE(refusal(named("")).find("test.urdf:4: <joint>: a joint with an empty name"),
              std::string::npos);
    EXPECT_NE(refusal(named(" j")).find("begins or ends with a space"), std::string::npos);
    EXPECT_NE(refusal(named("j", "b,c")).find("test.urdf:3: <link>: link name \"b,c\" has a ','"),
              std::string::npos);
    EXPECT_NE(refusal(named("j", "")).find("test.urdf:3: <link>: a link with an empty name"),
              std::string::npos);
    // Two joints of one name: two columns q_j.
    std::string twice = named("j");
    twice.insert(twice.find("</robot>"),
                 "<link name=\"c\"><inertial><mass value=\"1\"/><inertia ixx=\"1\" iyy=\"1\" "
                 "izz=\"1\"/></inertial></link>\n<joint name=\"j\" type=\"revolute\"><parent "
                 "link=\"b\"/><child link=\"c\"/></joint>\n");
    EXPECT_NE(refusal(twice).find("test.urdf:6: <joint>: joint j is defined twice (first at line 4"),
              std::string::npos)
        << refusal(twice);
}

/// The one-joint robot of robot() with joint origin `xyz`, axis `axis` and mass `mass`.
std::string scaled(const std::string& xyz, const std::string& axis, const std::string& mass) {
    return "<robot name=\"r\">\n<link name=\"a\"/>\n<link name=\"b\"><inertial><mass value=\"" +
           mass +
           "\"/><inertia ixx=\"1\" iyy=\"1\" izz=\"1\"/></inertial></link>\n<joint name=\"j\" "
           "type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/><origin xyz=\"" +
           xyz + "\"/><axis xyz=\"" + axis + "\"/></joint>\n</robot>";
}

TEST(UrdfTrees, AxesAreNormalisedAndOverflowsRefusedWithTheLine) {
    // An axis of any length is its direction: 1e200 0 0 and 0 2 0 as 1 0 0 and 0 1 0, to the
    // rounding of the division by the norm (a few 1e-16; 3 0 4 against 0.6 0 0.8: 1.1e-16).
    for (const auto& [given, unit] : {std::pair{"1e200 0 0", "1 0 0"}, {"0 2 0", "0 1 0"},
                                      {"0 0 -1e-300", "0 0 -1"}, {"3 0 4", "0.6 0 0.8"}}) {
        const auto a = models::parse_urdf(scaled("0 0 0", given, "1"));
        const auto b = models::parse_urdf(scaled("0 0 0", unit, "1"));
        EXPECT_LT((a->bodies[0].axis - b->bodies[0].axis).norm(), 3e-16) << given;
    }
    EXPECT_NE(refusal(scaled("0 0 0", "0 0 0", "1")).find("test.urdf:4: <axis>: joint j: zero axis"),
              std::string::npos);
    // Numbers that are finite but whose products overflow: refused with the element's line.
    EXPECT_EQ(refusal(scaled("1 0 0", "1 0 0", "1e10")), "") << "control: large but fine";
    // A mass of 1e308 at the link's origin: m g overflows (the gravity wrench at q = 0).
    EXPECT_NE(refusal(scaled("0 0 0", "1 0 0", "1e308"))
                  .find("test.urdf:4: <joint>: joint j: the pose or the mass properties of its "
                        "link overflow a double at q = 0"),
              std::string::npos)
        << refusal(scaled("0 0 0", "1 0 0", "1e308"));
    // 1e300 kg 1e10 m off its link's origin: m c c overflows in the link's own inertia.
    std::string off = scaled("0 0 0", "1 0 0", "1e300");
    off.insert(off.find("<mass"), "<origin xyz=\"1e10 0 0\"/>");
    EXPECT_NE(refusal(off).find("test.urdf:3: <inertial>: link b: its mass properties overflow"),
              std::string::npos)
        << refusal(off);
    EXPECT_NE(refusal(scaled("1e308 0 0", "1 0 0", "1"))
                  .find("test.urdf:4: <joint>: joint j: the pose or the mass properties of its "
                        "link overflow a double at q = 0"),
              std::string::npos)
        << refusal(scaled("1e308 0 0", "1 0 0", "1"));
    // Two fixed joints of 1e308 each: the composed origin is infinite.
    std::string fixed2 = scaled("0 0 0", "1 0 0", "1");
    fixed2.insert(fixed2.find("</robot>"),
                  "<link name=\"c\"/><link name=\"d\"/>\n<joint name=\"f1\" type=\"fixed\"><parent "
                  "link=\"b\"/><child link=\"c\"/><origin xyz=\"1e308 0 0\"/></joint>\n<joint "
                  "name=\"f2\" type=\"fixed\"><parent link=\"c\"/><child link=\"d\"/><origin "
                  "xyz=\"1e308 0 0\"/></joint>\n");
    EXPECT_NE(refusal(fixed2).find("test.urdf:7: <joint>: joint f2: its <origin> (after the fixed "
                                   "joints above it) overflows"),
              std::string::npos)
        << refusal(fixed2);
}

TEST(UrdfTrees, NegativeEffortOrVelocityAndASecondRootAreRefused) {
    const auto limit = [](const std::string& l) {
        std::string s = robot("");
        return s.insert(s.find("</joint>"), l);
    };
    // Controls: 0 is a documented value of each (unactuated; no velocity limit).
    EXPECT_EQ(refusal(limit("<limit effort=\"0\" velocity=\"0\"/>")), "");
    EXPECT_NE(refusal(limit("<limit effort=\"-5\"/>"))
                  .find("test.urdf:1: <limit>: joint j: negative effort -5"),
              std::string::npos);
    EXPECT_NE(refusal(limit("<limit velocity=\"-2\"/>"))
                  .find("test.urdf:1: <limit>: joint j: negative velocity limit -2"),
              std::string::npos);
    EXPECT_NE(refusal(robot("") + "\n<robot name=\"other\"/>")
                  .find("test.urdf:2: <robot>: a second root element after <robot>"),
              std::string::npos);
    EXPECT_EQ(refusal(robot("") + "\n<!-- a comment after the root is fine -->"), "");
}

TEST(UrdfTrees, MimicOnAFixedJointIsIgnored) {
    // The Panda as TORA.jl ships it: its finger joints are fixed, the second with <mimic>.
    // Reference: the same file with the <mimic> element removed gives the same robot.
    const auto tora = models::load_urdf(data("panda_arm_tora.urdf"));
    ASSERT_EQ(tora->dof(), 7);
    std::ifstream in(data("panda_arm_tora.urdf"));
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::size_t at = text.find("<mimic joint=\"panda_finger_joint1\"/>");
    ASSERT_NE(at, std::string::npos);
    text.erase(at, std::string("<mimic joint=\"panda_finger_joint1\"/>").size());
    const auto plain = models::parse_urdf(text);
    vec<dynamic> q(7), qd(7);
    q << 0.1, -0.4, 0.3, -1.5, 0.2, 1.1, -0.6;
    qd << 0.5, -0.2, 0.3, 0.1, -0.7, 0.4, 0.9;
    EXPECT_EQ(multibody::robot_lagrangian(tora)(q, qd), multibody::robot_lagrangian(plain)(q, qd));
    // Control: the fingers' 30 g are in the model (merged into link 7 through the fixed joints).
    EXPECT_NEAR(tora->bodies[6].mass, 0.735522 + 0.73 + 2 * 0.015, 1e-12);
}

/// L = ½ (2 q̇₁² + m22 q̇₂²): M = diag(2, m22).
struct two_masses {
    static constexpr int dim = 2;
    double m22 = 1.0;
    template <class T>
    T operator()(const tvec<T, 2>&, const tvec<T, 2>& v) const {
        return v(0) * v(0) + 0.5 * m22 * v(1) * v(1);
    }
};

TEST(UrdfTrees, AnIllConditionedMassMatrixIsCalledSoWithItsConditionNumber) {
    // A 2000-link chain's step failed with "singular or not positive definite" while the
    // eigenvalues it printed were all positive. The diagnosis now says which.
    mat<dynamic> m = mat<dynamic>::Zero(2, 2);
    m.diagonal() << 2.0, 1e-13;
    EXPECT_NE(detail::mass_matrix_problem<dynamic>(m).find(
                  "the mass matrix d2L/dqdot2 is ill-conditioned: condition number 2e+13 "
                  "(eigenvalues from 1e-13 to 2)"),
              std::string::npos)
        << detail::mass_matrix_problem<dynamic>(m);
    for (const double lo : {-1e-13, 0.0}) { // controls: indefinite or singular, and regular
        m(1, 1) = lo;
        EXPECT_NE(detail::mass_matrix_problem<dynamic>(m).find(
                      "is singular or not positive definite (eigenvalues from"),
                  std::string::npos);
    }
    m(1, 1) = 1e-3;
    EXPECT_EQ(detail::mass_matrix_problem<dynamic>(m), "");
    // The check of the initial state (lagrangian_system::check_regular), which refused the
    // 2000-link chain (measured: eigenvalues from 3.13e-10 to 1.29e+03), says the same.
    auto refused = [](double m22) {
        try {
            lagrangian_system<two_masses>(two_masses{m22}).check_regular(vec<2>::Zero(),
                                                                         vec<2>::Zero());
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_EQ(refused(2e-13), "the mass matrix d2L/dqdot2 is ill-conditioned at the initial "
                              "state: condition number 1e+13 (eigenvalues from 2e-13 to 2)");
    EXPECT_NE(refused(-1.0).find("is singular or not positive definite at the initial state"),
              std::string::npos);
    EXPECT_EQ(refused(1e-3), "");
}

/// Two links hanging along −z from joints about y: link 1 (m1, centre lc1 below its joint,
/// isotropic inertia i1) and link 2 (m2, lc2, i2) at l1 below; joint 2 mimics joint 1,
/// θ2 = k q + b (k, b as given; `mimic` false: joint 2 independent).
std::string mimic_arm_urdf(bool mimic = true) {
    return "<robot name=\"mimic arm\">\n<link name=\"a\"/>\n"
           "<link name=\"l1\"><inertial><origin xyz=\"0 0 -0.4\"/><mass value=\"1.2\"/><inertia "
           "ixx=\"0.05\" iyy=\"0.05\" izz=\"0.05\"/></inertial></link>\n"
           "<link name=\"l2\"><inertial><origin xyz=\"0 0 -0.35\"/><mass value=\"0.7\"/><inertia "
           "ixx=\"0.02\" iyy=\"0.02\" izz=\"0.02\"/></inertial></link>\n"
           "<joint name=\"j2\" type=\"revolute\"><parent link=\"l1\"/><child link=\"l2\"/>"
           "<origin xyz=\"0 0 -0.9\"/><axis xyz=\"0 1 0\"/>" +
           std::string(mimic ? "<mimic joint=\"j1\" multiplier=\"-0.6\" offset=\"0.3\"/>" : "") +
           "</joint>\n<joint name=\"j1\" type=\"continuous\"><parent link=\"a\"/><child "
           "link=\"l1\"/><axis xyz=\"0 1 0\"/></joint>\n</robot>";
}

/// The same robot's Lagrangian written out by hand in q = θ1 (the coupling substituted): link
/// 1 at absolute angle a1 = q, link 2 at a2 = q + θ2 = (1 + k) q + b; centres
/// c1 = −lc1 (sin a1, 0, cos a1), c2 = −l1 (sin a1, 0, cos a1) − lc2 (sin a2, 0, cos a2), so
/// T = ½ (m1 lc1² + i1) ȧ1² + ½ m2 (l1² ȧ1² + lc2² ȧ2² + 2 l1 lc2 ȧ1 ȧ2 cos(a1 − a2)) + ½ i2 ȧ2²
/// and V = g (m1 c1z + m2 c2z).
struct mimic_arm {
    static constexpr int dim = 1;
    double m1 = 1.2, m2 = 0.7, l1 = 0.9, lc1 = 0.4, lc2 = 0.35, i1 = 0.05, i2 = 0.02, k = -0.6,
           b = 0.3, g = 9.81;
    template <class T>
    T operator()(const tvec<T, 1>& q, const tvec<T, 1>& v) const {
        using std::cos;
        const T a1 = q(0), a2 = (1.0 + k) * q(0) + b;
        const T w1 = v(0), w2 = (1.0 + k) * v(0);
        const T t = 0.5 * (m1 * lc1 * lc1 + i1) * w1 * w1 +
                    0.5 * m2 * (l1 * l1 * w1 * w1 + lc2 * lc2 * w2 * w2 +
                                2.0 * l1 * lc2 * w1 * w2 * cos(a1 - a2)) +
                    0.5 * i2 * w2 * w2;
        const T v_pot = g * (m1 * (-lc1 * cos(a1)) + m2 * (-l1 * cos(a1) - lc2 * cos(a2)));
        return t - v_pot;
    }
};

TEST(UrdfMimic, AMimicJointEqualsItsCouplingWrittenOutByHand) {
    const auto r = models::parse_urdf(mimic_arm_urdf());
    ASSERT_EQ(r->dof(), 1); // j2 is not a coordinate
    ASSERT_EQ(r->mimics.size(), 1U);
    EXPECT_EQ(r->bodies[1].name, "j2");
    const multibody::robot_lagrangian robot(r);
    const mimic_arm hand;
    for (const double q : {0.0, 0.7, -2.1})
        for (const double v : {0.0, 1.3, -0.4}) {
            lagrangian_terms<1> e; // by AD of the hand-written L
            evaluate(hand, vec<1>(q), vec<1>(v), e);
            lagrangian_terms<dynamic> t;
            robot.derivatives(vec<dynamic>::Constant(1, q), vec<dynamic>::Constant(1, v), t);
            // Sums of a dozen O(1–10) terms: 1e-13 of the largest.
            const double tol = 1e-13 * std::max({1.0, std::abs(e.value), std::abs(e.lq(0))});
            EXPECT_NEAR(t.value, e.value, tol) << q << " " << v;
            EXPECT_NEAR(t.lq(0), e.lq(0), tol);
            EXPECT_NEAR(t.lv(0), e.lv(0), tol);
            EXPECT_NEAR(t.lqq(0, 0), e.lqq(0, 0), tol);
            EXPECT_NEAR(t.lqv(0, 0), e.lqv(0, 0), tol);
            EXPECT_NEAR(t.lvv(0, 0), e.lvv(0, 0), tol);
            // The classical algorithms: M by composite bodies, the bias by Newton–Euler equal
            // M and ∂²L/∂q∂q̇ q̇ − ∂L/∂q of the same L.
            multibody::workspace w;
            mat<dynamic> mm(1, 1);
            vec<dynamic> bias(1);
            multibody::mass_matrix(*r, w, vec<dynamic>::Constant(1, q), mm);
            multibody::bias_forces(*r, w, vec<dynamic>::Constant(1, q),
                                   vec<dynamic>::Constant(1, v), bias);
            EXPECT_NEAR(mm(0, 0), e.lvv(0, 0), tol);
            EXPECT_NEAR(bias(0), e.lqv(0, 0) * v - e.lq(0), tol);
        }
    // Negative control: with the mimic's offset left out (b = 0) the hand-written L differs.
    mimic_arm no_offset;
    no_offset.b = 0.0;
    EXPECT_GT(std::abs(robot(vec<dynamic>::Constant(1, 0.7), vec<dynamic>::Constant(1, 1.3)) -
                       no_offset(vec<1>(0.7), vec<1>(1.3))),
              1e-3);
}

TEST(UrdfMimic, AMimicArmSwingsAsItsHandWrittenLagrangian) {
    // The robot through the models layer (robot_model: the general engine on the recursive
    // derivatives) against the hand-written L through the same scheme: gauss-2, h = 1 ms, 1 s
    // from rest at q = 0.8. Equal Lagrangians to 1e-13 give equal motions to Newton's
    // tolerance: 1e-10 rad.
    const auto r = models::parse_urdf(mimic_arm_urdf());
    const models::model m = models::robot_model(r);
    EXPECT_EQ(m.dim, 1);
    EXPECT_EQ(m.coordinates, "j1");
    auto sim = m.prepare(m.defaults(), {{0.8}, {}, {}})
                   .simulate({scheme_spec(scheme_kind::gauss, 2), {}, 1e-3});
    sim->advance(1000);
    const mimic_arm hand;
    general::stepper<mimic_arm> st(lagrangian_system<mimic_arm>(hand), 1e-3,
                                   scheme_spec(scheme_kind::gauss, 2));
    phase_state<1> x{vec<1>(0.8), vec<1>(0.0)};
    integrate(st, x, 0.0, 1000, [](auto, auto, const auto&) {});
    EXPECT_NEAR(sim->q()[0], x.q(0), 1e-10);
    EXPECT_NEAR(sim->p()[0], x.p(0), 1e-9);
    EXPECT_GT(std::abs(x.q(0) - 0.8), 0.1); // it swung
    // Negative control: joint 2 free (no <mimic>), started where the mimic put it, at rest:
    // joint 1 moves otherwise.
    const models::model free = models::robot_model(models::parse_urdf(mimic_arm_urdf(false)));
    EXPECT_EQ(free.dim, 2);
    auto other = free.prepare(free.defaults(), {{0.3 - 0.6 * 0.8, 0.8}, {}, {}})
                     .simulate({scheme_spec(scheme_kind::gauss, 2), {}, 1e-3});
    other->advance(1000);
    EXPECT_GT(std::abs(other->q()[1] - x.q(0)), 1e-3);
}

TEST(UrdfMimic, ThePandasMimicFingerAgainstAutomaticDifferentiation) {
    // panda.urdf: panda_finger_joint2 mimics panda_finger_joint1 (multiplier 1): 8 coordinates.
    // Reference: AD of the second implementation (reference_lagrangian.hpp), which takes the
    // mimic joint's θ = q_master and computes everything else its own way.
    const auto r = models::load_urdf(data("panda.urdf"));
    ASSERT_EQ(r->dof(), 8);
    EXPECT_EQ(r->bodies[8].name, "panda_finger_joint2");
    check_against_reference<8>("panda.urdf");
    // The fingers open symmetrically: the right finger's frame moves by −y as the left by +y.
    vec<dynamic> q = vec<dynamic>::Zero(8);
    const multibody::vec3 left0 = models::frame_pose_at(*r, "panda_leftfinger", q).origin;
    const multibody::vec3 right0 = models::frame_pose_at(*r, "panda_rightfinger", q).origin;
    q(7) = 0.03;
    const multibody::vec3 left = models::frame_pose_at(*r, "panda_leftfinger", q).origin - left0;
    const multibody::vec3 right =
        models::frame_pose_at(*r, "panda_rightfinger", q).origin - right0;
    EXPECT_NEAR(left.norm(), 0.03, 1e-15);
    EXPECT_NEAR((left + right).norm(), 0.0, 1e-15);
}

TEST(UrdfMimic, MimicsThatCannotBeCoupledAreRefusedWithTheLine) {
    const std::string arm = mimic_arm_urdf();
    auto with = [&](const std::string& from, const std::string& to) {
        std::string s = arm;
        s.replace(s.find(from), from.size(), to);
        return s;
    };
    EXPECT_EQ(refusal(arm), "");
    EXPECT_NE(refusal(with("joint=\"j1\"", "joint=\"jx\""))
                  .find("test.urdf:5: <mimic>: joint j2 mimics jx, which is not a revolute"),
              std::string::npos)
        << refusal(with("joint=\"j1\"", "joint=\"jx\""));
    // A coordinate below a mimic joint: a third link under l2.
    std::string below = arm;
    below.insert(below.find("</robot>"),
                 "<link name=\"l3\"><inertial><mass value=\"1\"/><inertia ixx=\"1\" iyy=\"1\" "
                 "izz=\"1\"/></inertial></link>\n<joint name=\"j3\" type=\"revolute\"><parent "
                 "link=\"l2\"/><child link=\"l3\"/></joint>\n");
    EXPECT_NE(refusal(below).find("test.urdf:8: <joint>: joint j3 moves below the mimic joint j2"),
              std::string::npos)
        << refusal(below);
    // ... and mimicking it: a mimic of a mimic.
    std::string chained = below;
    chained.insert(chained.find("</joint>\n</robot>"), "<mimic joint=\"j2\"/>");
    EXPECT_NE(refusal(chained).find("joint j3 mimics j2, which is a mimic joint itself"),
              std::string::npos)
        << refusal(chained);
    EXPECT_NE(refusal(with("multiplier=\"-0.6\"", "multiplier=\"x\""))
                  .find("attribute multiplier=\"x\" needs 1 finite number"),
              std::string::npos);
}

} // namespace
