// URDF robots (varsym/models/robot.hpp) as trees: chains of ten thousand links load and step,
// names that would break a CSV column or a key are refused, axes are normalised and overflows
// refused with the line, and an ill-conditioned mass matrix is named with its condition number.
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
    EXPECT_NE(
        refusal(named("a&quot;b")).find("test.urdf:4: <joint>: joint name \"a\"b\" has a '\"'"),
        std::string::npos);
    EXPECT_NE(refusal(named("a&#10;b"))
                  .find("test.urdf:4: <joint>: joint name \"a\\x0Ab\" has a "
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
    EXPECT_NE(
        refusal(twice).find("test.urdf:6: <joint>: joint j is defined twice (first at line 4"),
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
    for (const auto& [given, unit] : {std::pair{"1e200 0 0", "1 0 0"},
                                      {"0 2 0", "0 1 0"},
                                      {"0 0 -1e-300", "0 0 -1"},
                                      {"3 0 4", "0.6 0 0.8"}}) {
        const auto a = models::parse_urdf(scaled("0 0 0", given, "1"));
        const auto b = models::parse_urdf(scaled("0 0 0", unit, "1"));
        EXPECT_LT((a->bodies[0].axis - b->bodies[0].axis).norm(), 3e-16) << given;
    }
    EXPECT_NE(
        refusal(scaled("0 0 0", "0 0 0", "1")).find("test.urdf:4: <axis>: joint j: zero axis"),
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
            lagrangian_system<two_masses>(two_masses{m22})
                .check_regular(vec<2>::Zero(), vec<2>::Zero());
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

} // namespace
