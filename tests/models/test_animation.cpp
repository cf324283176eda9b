// tests/models/test_animation.cpp: the animation page of a robot (varsym/models/animation.hpp):
// the URDF's visuals and colours as read, the rows kept, the poses in the page against forward
// kinematics (decoded from its base64 data), meshes found by the search path or warned about,
// and what is refused (bad rows, the URDF as the page's name).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>

#include "models/page_fields.hpp"
#include "urdf_helpers.hpp"
#include "varsym/models/animation.hpp"

namespace {

using namespace varsym;
namespace fs = std::filesystem;
using varsym::test::field;
using varsym::test::slurp;

const std::string arm_urdf = R"(<robot name="arm">
  <material name="green"><color rgba="0 1 0 0.5"/></material>
  <link name="base"><visual><geometry><cylinder radius="0.1" length="0.05"/></geometry></visual></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 1 0"/></joint>
  <link name="l1"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial>
    <visual><origin xyz="0.25 0 0"/><geometry><box size="0.5 0.1 0.1"/></geometry><material name="green"/></visual></link>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0.5 0 0"/><axis xyz="0 1 0"/></joint>
  <link name="l2"><inertial><origin xyz="0.2 0 0"/><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial>
    <visual><geometry><mesh filename="package://pkg/meshes/part.stl" scale="2 2 2"/></geometry>
      <material name="own"><color rgba="0.2 0.3 0.4 1"/></material></visual></link>
</robot>)";

struct AnimationTest : ::testing::Test {
    fs::path dir = fs::temp_directory_path() / ("varsym_anim_" + std::to_string(::getpid()));
    void SetUp() override { fs::create_directories(dir); }
    void TearDown() override { fs::remove_all(dir); }
};

TEST(AnimationVisuals, ColoursNamedInlineAndNoneAndTheMeshScaleAreRead) {
    const auto r = models::parse_urdf(arm_urdf, "arm.urdf");
    ASSERT_EQ(r->visuals.size(), 3u);
    EXPECT_EQ(r->visuals[0].body, -1); // the base: fixed to the ground
    EXPECT_EQ(r->visuals[0].kind, multibody::shape_kind::cylinder);
    EXPECT_LT(r->visuals[0].rgba[3], 0.0); // no material
    EXPECT_EQ(r->visuals[1].rgba[1], 1.0); // named at the top: green, half transparent
    EXPECT_EQ(r->visuals[1].rgba[3], 0.5);
    EXPECT_DOUBLE_EQ(r->visuals[1].offset.origin.x(), 0.25);
    EXPECT_EQ(r->visuals[2].kind, multibody::shape_kind::mesh);
    EXPECT_EQ(r->visuals[2].rgba[2], 0.4); // its own
    EXPECT_EQ(r->visuals[2].size, Eigen::Vector3d(2, 2, 2));
    // A visual that cannot be read is kept with its problem, the robot is still read.
    std::string broken = arm_urdf;
    const std::string box = "<box size=\"0.5 0.1 0.1\"/>";
    broken.replace(broken.find(box), box.size(), "<box size=\"0.5 -1 0.1\"/>");
    const auto bad = models::parse_urdf(broken, "arm.urdf");
    ASSERT_EQ(bad->visuals.size(), 3u);
    EXPECT_NE(bad->visuals[1].problem.find("positive sides"), std::string::npos)
        << bad->visuals[1].problem;
}

TEST(AnimationRows, FrameNIsTheFirstRowAtOrAfterNOverFpsAndZeroKeepsAll) {
    std::vector<double> t;
    for (int k = 0; k <= 1000; ++k)
        t.push_back(k * 1e-3);
    const auto kept = models::animation_rows(t, 60.0);
    ASSERT_EQ(kept.size(), 61u); // 0, 1/60, ..., 60/60 = the last row
    for (std::size_t n = 0; n < kept.size(); ++n) {
        const double due = static_cast<double>(n) / 60.0;
        EXPECT_GE(t[kept[n]], due - 1e-12) << n;
        if (kept[n] > 0) {
            EXPECT_LT(t[kept[n] - 1], due) << n; // the first such row
        }
    }
    EXPECT_EQ(kept.back(), 1000u);
    EXPECT_EQ(models::animation_rows(t, 0.0).size(), t.size());
    // Rows sparser than the frames: every row kept.
    EXPECT_EQ(models::animation_rows(std::vector<double>{0.0, 0.1, 0.2}, 60.0).size(), 3u);
}

TEST_F(AnimationTest, PosesInThePageAreForwardKinematicsAndTheMeshIsFoundOnTheSearchPath) {
    const auto r = models::parse_urdf(arm_urdf, "arm.urdf");
    fs::create_directories(dir / "share" / "pkg" / "meshes");
    std::ofstream(dir / "share" / "pkg" / "meshes" / "part.stl") << "solid x\nendsolid x\n";
    std::vector<double> t{0.0, 0.5, 1.0};
    Eigen::MatrixXd q(3, 2);
    q << 0.0, 0.0, 0.4, -0.7, 1.2, 0.9;
    models::animation_options o;
    o.mesh_path = {(dir / "share").string()};
    o.fps = 0.0;
    const auto rep = models::write_animation(r, t, q, (dir / "a.html").string(), o);
    EXPECT_TRUE(rep.warnings.empty()) << rep.warnings.front();
    EXPECT_EQ(rep.frames, 3u);
    const std::string page = slurp(dir / "a.html");
    EXPECT_EQ(rep.bytes, page.size());
    EXPECT_FALSE(fs::exists(dir / "a.html.tmp"));
    EXPECT_NE(page.find("\"f\":\"stl\""), std::string::npos);
    EXPECT_NE(page.find("data-varsym=\"STLLoader\""), std::string::npos); // its loader inlined
    EXPECT_NE(page.find("\"bodies\":2"), std::string::npos);
    const auto raw = field(page, "poses");
    ASSERT_EQ(raw.size(), 3u * 2 * 7 * sizeof(float));
    std::vector<float> poses(raw.size() / sizeof(float));
    std::memcpy(poses.data(), raw.data(), raw.size());
    for (int k = 0; k < 3; ++k) {
        // Body 2's origin by hand: joints about +y turn x into −z.
        const double a = q(k, 0);
        const Eigen::Vector3d o2(0.5 * std::cos(a), 0.0, -0.5 * std::sin(a));
        const float* p = &poses[static_cast<std::size_t>((k * 2 + 1) * 7)];
        EXPECT_NEAR(p[0], o2.x(), 1e-6);
        EXPECT_NEAR(p[2], o2.z(), 1e-6);
        // The orientation: the quaternion of a turn by q1 + q2 about +y.
        const double half = (q(k, 0) + q(k, 1)) / 2;
        EXPECT_NEAR(std::abs(p[4]), std::abs(std::sin(half)), 1e-6);
        EXPECT_NEAR(std::abs(p[6]), std::abs(std::cos(half)), 1e-6);
    }
}

TEST_F(AnimationTest, AMissingMeshIsWarnedAboutAndItsLinkDrawnAsCapsules) {
    const auto r = models::parse_urdf(arm_urdf, "arm.urdf");
    std::vector<double> t{0.0, 1.0};
    const Eigen::MatrixXd q = Eigen::MatrixXd::Zero(2, 2);
    const auto rep = models::write_animation(r, t, q, (dir / "b.html").string());
    ASSERT_EQ(rep.warnings.size(), 1u);
    EXPECT_NE(rep.warnings[0].find("link l2: mesh 'package://pkg/meshes/part.stl' not found"),
              std::string::npos)
        << rep.warnings[0];
    const std::string page = slurp(dir / "b.html");
    EXPECT_NE(page.find("\"k\":\"capsule\""), std::string::npos);         // l2: joint to its centre
    EXPECT_EQ(page.find("data-varsym=\"STLLoader\""), std::string::npos); // no mesh, no loader
    EXPECT_NE(page.find("part.stl' not found"), std::string::npos);       // on the page too
}

TEST_F(AnimationTest, ContactForcesOfTheKeptRowsBecomeArrowsOnOneStatedScale) {
    const auto r = models::parse_urdf(arm_urdf, "arm.urdf");
    const std::vector<double> t{0.0, 0.01, 0.02, 0.5};
    const Eigen::MatrixXd q = Eigen::MatrixXd::Zero(4, 2);
    models::animation_options o;
    o.fps = 10.0; // keeps rows 0 and 3 (0 and 0.5 s)
    o.forces = {{}, {0, 0, 0, 0, 0, 99}, {}, {0.5, 0, 0, 0, 3, 4, 1, 0, 0, 0, 0, 2}};
    models::write_animation(r, t, q, (dir / "f.html").string(), o);
    const std::string page = slurp(dir / "f.html");
    const std::vector<unsigned char> counts = field(page, "arrowCounts");
    ASSERT_EQ(counts.size(), 2 * sizeof(std::uint32_t));
    EXPECT_EQ(counts[0], 0); // row 0: none
    EXPECT_EQ(counts[4], 2); // row 3: two; row 1's 99 N is not a kept row
    const std::vector<float> arrows = varsym::test::floats(page, "arrows");
    ASSERT_EQ(arrows.size(), 12u);
    EXPECT_EQ(arrows[0], 0.5f);
    EXPECT_EQ(arrows[5], 4.0f);
    EXPECT_EQ(arrows[11], 2.0f);
    // The largest kept force, 5 N, is a third of the scene's radius: the note gives 1 m in N.
    EXPECT_NE(page.find("id=\"note\">blue arrows: the contact forces, 1 m for"), std::string::npos);
    const auto number = [&](const std::string& key) {
        return std::stod(page.substr(page.find("\"" + key + "\":") + key.size() + 3));
    };
    EXPECT_NEAR(number("arrowScale"), number("radius") / 3 / 5.0, 1e-15);
    o.forces.pop_back(); // a row without its forces
    EXPECT_THROW(models::write_animation(r, t, q, (dir / "g.html").string(), o),
                 std::invalid_argument);
    EXPECT_FALSE(fs::exists(dir / "g.html"));
}

TEST_F(AnimationTest, BadRowsAndTheUrdfAsThePageAreRefusedAndNothingIsWritten) {
    const auto r = models::parse_urdf(arm_urdf, "arm.urdf");
    const std::string out = (dir / "c.html").string();
    std::vector<double> t{0.0, 1.0};
    Eigen::MatrixXd q = Eigen::MatrixXd::Zero(2, 2);
    EXPECT_THROW(models::write_animation(r, t, Eigen::MatrixXd::Zero(2, 3), out),
                 std::invalid_argument);
    q(1, 1) = std::nan("");
    EXPECT_THROW(models::write_animation(r, t, q, out), std::invalid_argument);
    q(1, 1) = 0.0;
    std::vector<double> back{1.0, 0.0};
    EXPECT_THROW(models::write_animation(r, back, q, out), std::invalid_argument);
    EXPECT_FALSE(fs::exists(out));
    const fs::path urdf = dir / "arm.urdf";
    std::ofstream(urdf) << arm_urdf;
    models::animation_options o;
    o.urdf = urdf.string();
    EXPECT_THROW(models::write_animation(r, t, q, urdf.string(), o), models::animation_error);
    EXPECT_EQ(slurp(urdf), arm_urdf);
    std::ofstream(out + ".tmp") << "someone's"; // never truncated
    EXPECT_THROW(models::write_animation(r, t, q, out), models::animation_error);
    EXPECT_EQ(slurp(out + ".tmp"), "someone's");
}

} // namespace
