// Contact geometry (contact/geometry.hpp): the shapes' points and the point Jacobians in the
// model's coordinates, against central differences of the positions.
#include <cmath>
#include <memory>
#include <numbers>

#include <gtest/gtest.h>

#include "varsym/contact/geometry.hpp"

namespace {

using varsym::contact::contact_points;
using varsym::contact::robot_kinematics;
using varsym::multibody::collision_shape;
using varsym::multibody::shape_kind;
using varsym::multibody::vec3;

/// A root link with a box, and an arm on a revolute joint about y with a sphere at its end.
varsym::multibody::tree arm_on_a_box() {
    varsym::multibody::tree m;
    m.name = "arm_on_a_box";
    m.root.link = m.root.name = "base";
    m.root.mass = 2.0;
    m.root.inertia = vec3(0.1, 0.2, 0.25).asDiagonal();
    varsym::multibody::body b;
    b.name = "elbow";
    b.link = "arm";
    b.placement.origin = vec3(0.1, 0.05, 0.2);
    b.axis = vec3(0.0, 0.6, 0.8);
    b.mass = 0.5;
    b.com = vec3(0.0, 0.0, 0.15);
    b.inertia = vec3(0.01, 0.01, 0.002).asDiagonal();
    m.add_body(-1, b);
    m.frames.push_back({"base", -1, {}});
    m.frames.push_back({"arm", 0, {}});
    collision_shape box{"base", -1, {}, shape_kind::box, vec3(0.3, 0.2, 0.1), ""};
    collision_shape ball{"arm", 0, {}, shape_kind::sphere, vec3(0.04, 0.0, 0.0), ""};
    ball.offset.origin = vec3(0.0, 0.02, 0.3);
    m.collisions = {box, ball};
    return m;
}

TEST(ContactGeometry, ShapesBecomePoints) {
    varsym::multibody::tree m = arm_on_a_box();
    const auto fixed = contact_points(m); // the base's box is the ground's: left out
    ASSERT_EQ(fixed.size(), 1U);
    EXPECT_EQ(fixed[0].link, "arm");
    EXPECT_DOUBLE_EQ(fixed[0].radius, 0.04);
    const auto floating = contact_points(m.with_base(varsym::multibody::base_kind::free));
    EXPECT_EQ(floating.size(), 9U); // eight corners and the sphere
    m.collisions.push_back({"arm", 0, {}, shape_kind::cylinder, vec3(0.1, 0.2, 0.0), ""});
    m.collisions.push_back({"arm", 0, {}, shape_kind::capsule, vec3(0.1, 0.2, 0.0), ""});
    EXPECT_EQ(contact_points(m).size(), 1U + 32U + 2U);
    // A cylinder's rim points lie on the circumscribed polygon's circle, r / cos(π/16).
    EXPECT_NEAR(contact_points(m)[1].point.head<2>().norm(), 0.1 / std::cos(std::numbers::pi / 16),
                1e-15);
    m.collisions.push_back({"arm", 0, {}, shape_kind::mesh, vec3::Zero(), "arm.stl"});
    try {
        (void)contact_points(m);
        FAIL() << "a mesh was accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("link arm"), std::string::npos) << e.what();
    }
}

/// ∂P/∂q against central differences (step 1e-6: error ~1e-12 · |P'''|), for every base.
void expect_jacobians(varsym::multibody::base_kind base, const Eigen::VectorXd& q) {
    const auto t = std::make_shared<const varsym::multibody::tree>(arm_on_a_box().with_base(base));
    robot_kinematics kin(t);
    ASSERT_EQ(kin.dimension(), q.size());
    const auto points = contact_points(*t);
    for (const auto& p : points) {
        kin.at(q);
        const vec3 x = kin.pose(p.body).point(p.point);
        Eigen::Matrix<double, 3, Eigen::Dynamic> jac(3, q.size());
        kin.jacobian(p.body, x, jac);
        for (int j = 0; j < q.size(); ++j) {
            const double e = 1e-6;
            Eigen::VectorXd plus = q, minus = q;
            plus(j) += e;
            minus(j) -= e;
            kin.at(plus);
            const vec3 xp = kin.pose(p.body).point(p.point);
            kin.at(minus);
            const vec3 xm = kin.pose(p.body).point(p.point);
            EXPECT_LT((jac.col(j) - (xp - xm) / (2 * e)).norm(), 1e-8)
                << "coordinate " << j << " of " << p.link;
        }
    }
}

TEST(ContactGeometry, PointJacobiansMatchDifferences) {
    Eigen::VectorXd fixed(1);
    fixed << 0.7;
    expect_jacobians(varsym::multibody::base_kind::fixed, fixed);
    Eigen::VectorXd planar(4);
    planar << 0.3, 0.5, -0.4, 0.7;
    expect_jacobians(varsym::multibody::base_kind::planar, planar);
    // Free: x, a quaternion off unit length (the positions depend on u/|u| only), the joint.
    Eigen::VectorXd free(8);
    free << 0.3, -0.2, 0.5, 0.9, 0.2, -0.3, 0.4, 0.7;
    expect_jacobians(varsym::multibody::base_kind::free, free);
}

TEST(ContactGeometry, ABoxsDistanceAndNormal) {
    // A box of sides (2, 1, 0.5) at (1, 0, 0.25): its faces x = 0, 2; y = ±0.5; z = 0, 0.5.
    const auto b =
        varsym::contact::static_box(vec3(1.0, 0.0, 0.25), vec3(2.0, 1.0, 0.5), 0.5, "step");
    vec3 n;
    EXPECT_NEAR(b.distance(vec3(1.5, 0.2, 0.8), n), 0.3, 1e-15); // above its top
    EXPECT_EQ(n, vec3::UnitZ());
    EXPECT_NEAR(b.distance(vec3(2.3, 0.9, 0.25), n), 0.5, 1e-15); // by an edge: √(0.3² + 0.4²)
    EXPECT_LT((n - vec3(0.6, 0.8, 0.0)).norm(), 1e-15);
    EXPECT_NEAR(b.distance(vec3(1.9, 0.0, 0.3), n), -0.1, 1e-15); // inside, nearest x = 2
    EXPECT_EQ(n, vec3::UnitX());
    // The normal is the distance's gradient (central differences) outside, edges included.
    for (const vec3& p : {vec3(2.3, 0.9, 0.25), vec3(-0.2, -0.7, 0.9), vec3(0.5, 0.1, 0.6)}) {
        b.distance(p, n);
        vec3 g, unused;
        for (int k = 0; k < 3; ++k) {
            const vec3 e = 1e-6 * vec3::Unit(k);
            g(k) = (b.distance(p + e, unused) - b.distance(p - e, unused)) / 2e-6;
        }
        EXPECT_LT((g - n).norm(), 1e-8) << p.transpose();
    }
}

TEST(ContactGeometry, TheGroundsSlopeTiltsItsNormal) {
    const auto g = varsym::contact::ground(0.1, 0.3, 0.5);
    // The plane z = 0.1 + x tan 0.3 contains (1, 0, 0.1 + tan 0.3): its gap is 0.
    vec3 n;
    EXPECT_NEAR(g.distance(vec3(1.0, 0.0, 0.1 + std::tan(0.3)), n), 0.0, 1e-15);
    EXPECT_NEAR(g.normal.norm(), 1.0, 1e-15);
    EXPECT_GT(g.normal.z(), 0.0);
}

} // namespace

// at() skips the kinematics where q equals the last at()'s entry for entry: a vector changed in
// place (the same object, the same address) must move the bodies, and a return to an earlier q
// must give that q's poses. The arm's ball (on the last body: the free base's six virtual bodies
// come first) against a fresh object at each q, and against the q before each change.
TEST(ContactGeometry, TheKinematicsFollowsAVectorChangedInPlace) {
    const auto t = std::make_shared<const varsym::multibody::tree>(
        arm_on_a_box().with_base(varsym::multibody::base_kind::free));
    const auto ball = contact_points(*t).back();
    ASSERT_EQ(ball.link, "arm");
    robot_kinematics kin(t);
    Eigen::VectorXd q(8);
    q << 0.3, -0.2, 0.5, 0.9, 0.2, -0.3, 0.4, 0.7;
    const auto where = [&t, &ball](const Eigen::VectorXd& at) {
        robot_kinematics fresh(t);
        fresh.at(at);
        return fresh.pose(ball.body).point(ball.point);
    };
    const vec3 first = where(q);
    kin.at(q);
    EXPECT_EQ(kin.pose(ball.body).point(ball.point), first);
    vec3 before = first;
    for (const int j : {0, 4, 7}) { // the base's position, its quaternion, the joint
        q(j) += 0.25;
        kin.at(q);
        const vec3 moved = kin.pose(ball.body).point(ball.point);
        EXPECT_EQ(moved, where(q)) << "coordinate " << j;
        EXPECT_GT((moved - before).norm(), 1e-2) << "coordinate " << j;
        before = moved;
    }
    q << 0.3, -0.2, 0.5, 0.9, 0.2, -0.3, 0.4, 0.7;
    kin.at(q);
    EXPECT_EQ(kin.pose(ball.body).point(ball.point), first);
}
