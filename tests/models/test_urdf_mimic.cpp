// URDF mimic joints (varsym/models/robot.hpp): a mimic joint equals its coupling written out by
// hand, in the Lagrangian and in a swing; the Panda's mimic finger against automatic
// differentiation; mimics that cannot be coupled are refused with the line.
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
                    0.5 * m2 *
                        (l1 * l1 * w1 * w1 + lc2 * lc2 * w2 * w2 +
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
    const multibody::vec3 right = models::frame_pose_at(*r, "panda_rightfinger", q).origin - right0;
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
                  .find("test.urdf:5: <mimic>: joint j2 mimics jx, which is not a joint of this "
                        "robot"),
              std::string::npos)
        << refusal(with("joint=\"j1\"", "joint=\"jx\""));
    EXPECT_NE(refusal(with("type=\"continuous\"", "type=\"fixed\""))
                  .find("test.urdf:5: <mimic>: joint j2 mimics j1, which is not a revolute"),
              std::string::npos)
        << refusal(with("type=\"continuous\"", "type=\"fixed\""));
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
