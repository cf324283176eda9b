// tests/models/test_figure.cpp: the built-in models' 3-D figures (varsym/models/figure.hpp) and
// their animation pages. The references are written here from the models' descriptions, not
// from the figure code: the symmetry axis of z-x-z Euler angles (sin θ sin φ, −sin θ cos φ,
// cos θ), a planar chain's joints Σ l_i (sin θ_i, 0, −cos θ_i) from the downward vertical, the
// spherical pendulum's bob at q, and a uniform box's moments of inertia m (b² + c²)/12.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>

#include <unistd.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "models/page_fields.hpp"
#include "varsym/models/animation.hpp"
#include "varsym/models/model.hpp"

namespace {

using namespace varsym;
namespace fs = std::filesystem;
using Eigen::Vector3d;

models::figure figure_of(const std::string& name, const models::lists& lists = {}) {
    const models::model& m = models::get(name);
    EXPECT_TRUE(static_cast<bool>(m.drawing)) << name;
    return m.drawing(m.defaults(), lists.empty() ? models::lists(m.lists.size()) : lists);
}

/// Where part k of figure f is at q.
Vector3d part_at(const models::figure& f, std::size_t k, const std::vector<double>& q) {
    std::vector<multibody::pose> poses(static_cast<std::size_t>(f.bodies));
    f.place(q, poses);
    const models::figure_part& p = f.parts[k];
    return p.body < 0 ? p.offset.origin
                      : poses[static_cast<std::size_t>(p.body)].point(p.offset.origin);
}

/// The index of the first part of kind `kind` and colour `rgba`.
std::size_t find_part(const models::figure& f, const std::string& kind,
                      const std::array<double, 4>& rgba) {
    for (std::size_t k = 0; k < f.parts.size(); ++k)
        if (f.parts[k].kind == kind && f.parts[k].rgba == rgba) return k;
    ADD_FAILURE() << "no " << kind;
    return 0;
}

TEST(Figure, TheHeavyTopsDiscFollowsTheSymmetryAxisOfItsEulerAngles) {
    const models::figure f = figure_of("heavy-top");
    const std::size_t disc = find_part(f, "cylinder", models::figure_colour::body);
    const std::size_t mark = find_part(f, "box", models::figure_colour::blue);
    EXPECT_FALSE(f.scale.empty()); // mgl alone: the drawn length is said
    for (const auto& q : {std::vector<double>{1.0, 0.0, 0.0}, {0.4, 2.1, -0.7}, {2.5, -1.0, 3.0}}) {
        const double th = q[0], phi = q[1];
        const Vector3d axis(std::sin(th) * std::sin(phi), -std::sin(th) * std::cos(phi),
                            std::cos(th));
        EXPECT_LT((part_at(f, disc, q) - axis).norm(), 1e-14); // the centre of mass, l = 1 m
    }
    // The spin ψ turns the rim's mark about the axis by ψ, and only it.
    const Vector3d a = part_at(f, mark, {0.7, 0.3, 0.0}) - part_at(f, disc, {0.7, 0.3, 0.0});
    const Vector3d b = part_at(f, mark, {0.7, 0.3, 1.1}) - part_at(f, disc, {0.7, 0.3, 1.1});
    EXPECT_NEAR(std::acos(a.normalized().dot(b.normalized())), 1.1, 1e-12);
    EXPECT_GT((a - b).norm(), 0.1); // negative control: the mark moved
}

TEST(Figure, TheRigidBodysBoxHasItsInertiaAlongItsPrincipalAxes) {
    // J with products of inertia: the box's axes are J's eigenvectors, and a uniform box of
    // the drawn sides has moments m (b² + c²)/12, ... proportional to J's eigenvalues.
    const std::vector<double> j{2.0, 3.0, 4.0, 0.3, -0.2, 0.1};
    const models::figure f = figure_of("rigid-body", {j});
    ASSERT_EQ(f.parts.front().kind, "box");
    const Vector3d s = f.parts.front().size;
    const Eigen::Matrix3d r = f.parts.front().offset.rotation;
    EXPECT_NEAR(s.maxCoeff(), 1.0, 1e-15);
    const Vector3d box((s(1) * s(1) + s(2) * s(2)) / 12, (s(0) * s(0) + s(2) * s(2)) / 12,
                       (s(0) * s(0) + s(1) * s(1)) / 12);
    Eigen::Matrix3d given;
    given << j[0], j[3], j[4], j[3], j[1], j[5], j[4], j[5], j[2];
    const Eigen::Matrix3d drawn = r * box.asDiagonal() * r.transpose();
    const double m = given.trace() / drawn.trace(); // the mass that makes the box's J
    EXPECT_LT((m * drawn - given).norm(), 1e-12 * given.norm());
    EXPECT_NEAR(r.determinant(), 1.0, 1e-14);
    // The box turns with the attitude: at Euler angles q its first principal axis is R(q) r e1.
    const Eigen::Matrix3d at =
        (Eigen::AngleAxisd(0.5, Vector3d::UnitZ()) * Eigen::AngleAxisd(1.2, Vector3d::UnitX()) *
         Eigen::AngleAxisd(-0.4, Vector3d::UnitZ()))
            .toRotationMatrix();
    std::vector<multibody::pose> poses(1);
    f.place(std::vector<double>{1.2, 0.5, -0.4}, poses);
    EXPECT_LT((poses[0].rotation - at).norm(), 1e-14);
}

TEST(Figure, ADiagonalInertiaKeepsTheBodysOwnAxes) {
    // J = diag(3, 2, 1): sides² ∝ (I₂ + I₃ − I₁, ...) = (0, 2, 4), the longest along body z, the
    // red, green, blue marks on +x, +y, +z whatever the moments' order.
    const models::figure f = figure_of("rigid-body", {{3.0, 2.0, 1.0}});
    EXPECT_TRUE(f.parts[0].offset.rotation.isIdentity(0.0));
    EXPECT_NEAR(f.parts[0].size(2), 1.0, 1e-15);
    EXPECT_NEAR(f.parts[0].size(1), std::sqrt(0.5), 1e-15);
    EXPECT_GT(f.parts[1].offset.origin.x(), 0.0); // red on +x
    EXPECT_GT(f.parts[3].offset.origin.z(), 0.0); // blue on +z
}

TEST(Figure, EveryDrawnModelIsFiniteAtItsDefaultStart) {
    int drawn = 0;
    for (const models::model& m : models::registry()) {
        if (!m.drawing) continue;
        ++drawn;
        const models::figure f = m.drawing(m.defaults(), models::lists(m.lists.size()));
        ASSERT_EQ(f.coordinates, static_cast<int>(m.q0.size())) << m.name;
        for (const models::figure_part& p : f.parts)
            EXPECT_TRUE(p.size.allFinite() && p.offset.origin.allFinite() &&
                        p.offset.rotation.allFinite())
                << m.name << " " << p.kind;
        std::vector<multibody::pose> poses(static_cast<std::size_t>(f.bodies));
        f.place(m.q0, poses);
        for (const multibody::pose& x : poses)
            EXPECT_TRUE(x.origin.allFinite() && x.rotation.allFinite()) << m.name;
        EXPECT_TRUE(std::isfinite(f.floor)) << m.name;
    }
    EXPECT_EQ(drawn, 7); // heavy-top, top, pendulum-3d, rigid-body, spherical and double
                         // pendulums, arm
}

TEST(Figure, TheSphericalPendulumsBobIsAtQEvenStraightDownOrUp) {
    models::figure f = figure_of("spherical-pendulum"); // l = 1
    const std::size_t bob = find_part(f, "sphere", models::figure_colour::red);
    for (const Vector3d& x : {Vector3d(0.6, 0.0, -0.8), Vector3d(0.0, 0.0, -1.0),
                              Vector3d(0.0, 0.0, 1.0), Vector3d(-0.48, 0.6, 0.64)})
        EXPECT_LT((part_at(f, bob, {x(0), x(1), x(2)}) - x).norm(), 1e-15) << x.transpose();
}

TEST(Figure, TheArmsAndDoublePendulumsLinksEndWhereTheirAnglesPutThem) {
    // The arm's default: lengths 1, 0.8, 0.6; th_i from the downward vertical.
    const models::figure f = figure_of("arm");
    ASSERT_EQ(f.bodies, 3);
    const std::vector<double> l{1.0, 0.8, 0.6}, q{0.3, -1.1, 2.0};
    std::vector<multibody::pose> poses(3);
    f.place(q, poses);
    Vector3d joint = Vector3d::Zero();
    for (std::size_t i = 0; i < 3; ++i) {
        EXPECT_LT((poses[i].origin - joint).norm(), 1e-15) << i;
        joint += l[i] * Vector3d(std::sin(q[i]), 0.0, -std::cos(q[i]));
        // the link's far end: its z axis times its length
        EXPECT_LT((poses[i].point(Vector3d(0, 0, l[i])) - joint).norm(), 1e-15) << i;
    }
    EXPECT_LT(f.floor, -2.4); // below the reach, 2.4 m
    const models::figure d = figure_of("double-pendulum");
    std::vector<multibody::pose> two(2);
    d.place(std::vector<double>{std::numbers::pi / 2, 0.0}, two);
    EXPECT_LT((two[1].origin - Vector3d(1.0, 0.0, 0.0)).norm(), 1e-15); // l1 = 1, horizontal
}

TEST(Figure, APageOfTheTopHoldsItsPosesAndRefusesARobotsOptions) {
    const fs::path dir = fs::temp_directory_path() / ("varsym_figure_" + std::to_string(getpid()));
    fs::create_directories(dir);
    const models::figure f = figure_of("top");
    const std::vector<double> t{0.0, 0.5, 1.0};
    Eigen::MatrixXd q(3, 3);
    q << 1.0, 0.0, 0.0, 0.8, 0.4, 2.0, 0.6, 0.9, 4.0;
    models::animation_options o;
    o.fps = 0.0;
    const std::string out = (dir / "top.html").string();
    const models::animation_report r = models::write_animation(f, t, q, out, o, {"a", "b", "c"});
    EXPECT_EQ(r.frames, 3u);
    const std::string page = test::slurp(out);
    EXPECT_NE(page.find("\"names\":[\"a\",\"b\",\"c\"]"), std::string::npos);
    const std::vector<float> poses = test::floats(page, "poses");
    ASSERT_EQ(poses.size(), 3u * 7);
    for (int k = 0; k < 3; ++k) { // the quaternion (x, y, z, w) of from_euler, as float
        const Eigen::Quaterniond u(Eigen::AngleAxisd(q(k, 1), Vector3d::UnitZ()) *
                                   Eigen::AngleAxisd(q(k, 0), Vector3d::UnitX()) *
                                   Eigen::AngleAxisd(q(k, 2), Vector3d::UnitZ()));
        const float* p = &poses[static_cast<std::size_t>(7 * k)];
        const double sign = p[6] * u.w() < 0 ? -1.0 : 1.0;
        EXPECT_NEAR(sign * p[3], u.x(), 1e-7);
        EXPECT_NEAR(sign * p[4], u.y(), 1e-7);
        EXPECT_NEAR(sign * p[5], u.z(), 1e-7);
        EXPECT_NEAR(sign * p[6], u.w(), 1e-7);
    }
    o.mesh_path = {dir.string()};
    EXPECT_THROW(models::write_animation(f, t, q, out, o), std::invalid_argument);
    o.mesh_path.clear();
    EXPECT_THROW(models::write_animation(f, t, q.leftCols(2), out, o), std::invalid_argument);
    fs::remove_all(dir);
}

TEST(Figure, ModelsWithoutAFigureHaveNoDrawing) {
    EXPECT_FALSE(static_cast<bool>(models::get("pendulum").drawing));
    EXPECT_FALSE(static_cast<bool>(models::get("kepler").drawing));
}

} // namespace
