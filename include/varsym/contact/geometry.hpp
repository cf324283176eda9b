// varsym/contact/geometry.hpp: what touches and what it touches. A robot's collision shapes
// (tree::collisions, from the URDF's <collision>) become contact points fixed to its bodies,
// each with a radius; the world is a set of obstacles, each with a friction coefficient: the
// half-space n·x ≥ offset (a ground plane, its height and slope) and static boxes (steps,
// tables). Every pair of a point and an obstacle is a potential contact; its gap is
// φ = dist(P) − r [m], dist the obstacle's signed distance (n·P − offset for the plane).
//
// Shapes: a sphere is its centre with its radius, a capsule its two end spheres (exact against a
// plane: the lowest point of a segment is an end), a box its eight corners (exact against a
// plane: the lowest point of a box is a corner), a cylinder its two rim circles as 16 points each
// with radius 0 on the circle of radius r / cos(π/16), circumscribed so that the cylinder never
// sinks (it may stand off the plane by at most r (1/cos(π/16) − 1) = 0.019 r when it rests on its
// rim). A mesh is refused, naming its link: give the link a primitive in a copy of the URDF.
// Collisions between the robot's own links are not detected (docs/contact.md).
//
// Kinematics in the model's coordinates (free base: position, quaternion, joints; planar and
// fixed: the tree's): world positions of body points and their Jacobians ∂P/∂q (3 × d). For a
// free base, the tree is evaluated in a chart centred at q as floating.hpp's Lagrangian does; the
// chart's rotation columns map to the quaternion's by A = (2/|u|) P(û), P δ = Im(conj(û) ⊗ δ)
// (floating.hpp, (Q3)).
// contact_points and robot_kinematics' evaluations are templates with a defaulted parameter
// (`template <class = void>`), called as plain functions: a source that includes this header and
// never calls them does not compile them (docs/development.md).
#pragma once

#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "varsym/multibody/algorithms.hpp"

namespace varsym::contact {

using multibody::mat3;
using multibody::vec3;

/// A point fixed to a body (−1: the ground) at `point` in its frame, with a radius [m].
struct contact_point {
    int body = -1;
    vec3 point = vec3::Zero();
    double radius = 0.0;
    std::string link; ///< the URDF link whose shape it is
};

/// What the robot touches, with Coulomb's μ ≥ 0: the half-space n·x ≥ offset [m] (n a unit
/// vector, the surface's outward normal: the ground) or a static box (its centre and half
/// sides [m], axis-aligned: a step, a table). distance() is the signed distance of a point
/// (negative inside) and its gradient, the outward normal there; a box's is continuous outside
/// it (the normal turns round its edges and corners) and takes the nearest face inside.
struct obstacle {
    enum class shape { half_space, box };
    shape kind = shape::half_space;
    vec3 normal = vec3::UnitZ(); ///< a half-space's
    double offset = 0.0;         ///< a half-space's
    vec3 centre = vec3::Zero();  ///< a box's
    vec3 half = vec3::Zero();    ///< a box's half sides
    double friction = 1.0;
    std::string name = "ground";

    double distance(const vec3& p, vec3& n) const {
        if (kind == shape::half_space) {
            n = normal;
            return normal.dot(p) - offset;
        }
        const vec3 d = p - centre;
        const vec3 q = d.cwiseAbs() - half;
        const vec3 sign = d.unaryExpr([](double v) { return v < 0.0 ? -1.0 : 1.0; });
        if (q.maxCoeff() > 0.0) { // outside: to the nearest point of the box
            const vec3 out = q.cwiseMax(0.0);
            const double r = out.norm();
            n = sign.cwiseProduct(out) / r;
            return r;
        }
        Eigen::Index k = 0; // inside: through the nearest face
        const double depth = q.maxCoeff(&k);
        n = vec3::Zero();
        n(k) = sign(k);
        return depth;
    }
};
using half_space = obstacle;

/// The ground: the plane z = height + x tan(slope) (rising along +x for slope > 0 [rad]).
inline obstacle ground(double height, double slope, double friction) {
    obstacle g;
    g.normal = vec3(-std::sin(slope), 0.0, std::cos(slope));
    g.offset = height * std::cos(slope);
    g.friction = friction;
    return g;
}

/// A static box with centre c and sides `sides` [m], axis-aligned.
inline obstacle static_box(const vec3& c, const vec3& sides, double friction, std::string name) {
    obstacle b;
    b.kind = obstacle::shape::box;
    b.centre = c;
    b.half = 0.5 * sides;
    b.friction = friction;
    b.name = std::move(name);
    return b;
}

/// Two unit tangents t1, t2 with (t1, t2, n) right-handed.
inline void tangents(const vec3& n, vec3& t1, vec3& t2) {
    const vec3 e = std::abs(n.x()) < 0.9 ? vec3::UnitX() : vec3::UnitY();
    t1 = (e - n.dot(e) * n).normalized();
    t2 = n.cross(t1);
}

/// The contact points of a tree's moving shapes (those fixed to the ground are the world's, not
/// the robot's, and left out). Throws std::invalid_argument for a mesh, naming its link, and for
/// a shape the URDF reader could not take (collision_shape::problem).
template <class = void>
std::vector<contact_point> contact_points(const multibody::tree& t) {
    std::vector<contact_point> out;
    for (const multibody::collision_shape& s : t.collisions) {
        if (s.body < 0) continue;
        if (!s.problem.empty()) throw std::invalid_argument(s.problem);
        auto add = [&](const vec3& local, double radius) {
            out.push_back({s.body, s.offset.point(local), radius, s.link});
        };
        switch (s.kind) {
        case multibody::shape_kind::sphere:
            add(vec3::Zero(), s.size(0));
            break;
        case multibody::shape_kind::capsule:
            for (const double z : {-0.5, 0.5})
                add(vec3(0.0, 0.0, z * s.size(1)), s.size(0));
            break;
        case multibody::shape_kind::box:
            for (int c = 0; c < 8; ++c)
                add(0.5 * vec3((c & 1) ? s.size(0) : -s.size(0), (c & 2) ? s.size(1) : -s.size(1),
                               (c & 4) ? s.size(2) : -s.size(2)),
                    0.0);
            break;
        case multibody::shape_kind::cylinder: {
            const int n = 16;
            const double r = s.size(0) / std::cos(std::numbers::pi / n);
            for (const double z : {-0.5, 0.5})
                for (int k = 0; k < n; ++k) {
                    const double a = 2.0 * std::numbers::pi * k / n;
                    add(vec3(r * std::cos(a), r * std::sin(a), z * s.size(1)), 0.0);
                }
            break;
        }
        case multibody::shape_kind::mesh:
            throw std::invalid_argument(
                "link " + s.link + ": a mesh collision shape (" + s.mesh +
                ") cannot touch yet: give the link a sphere, box, cylinder or capsule "
                "<collision> in a copy of the URDF");
        }
    }
    return out;
}

/// Body poses and point Jacobians of a robot in its model's coordinates (the header comment).
/// Holds its own workspace: one per thread.
class robot_kinematics {
  public:
    explicit robot_kinematics(std::shared_ptr<const multibody::tree> t) : t_(std::move(t)) {}

    [[nodiscard]] const multibody::tree& robot() const { return *t_; }
    /// d: the tree's dof, plus one for a free base's quaternion.
    [[nodiscard]] int dimension() const {
        return t_->dof() + (t_->base == multibody::base_kind::free ? 1 : 0);
    }

    /// Kinematics at the model's coordinates q; nothing to do where the last at() was at a q equal
    /// entry for entry (==; the contact step returns to its iterates' and onsets' positions).
    template <class = void>
    void at(const Eigen::VectorXd& q) {
        if (q_.size() == q.size() && (q_.array() == q.array()).all()) return;
        q_ = q;
        if (t_->base != multibody::base_kind::free) {
            w_.chart.setIdentity();
            multibody::kinematics(*t_, w_, q, false); // poses and subspaces only
            x_.setZero();
            return;
        }
        const int n = t_->dof();
        x_ = q.head<3>();
        const Eigen::Vector4d u = q.segment<4>(3);
        const double norm = u.norm();
        const Eigen::Quaterniond uh(u(0) / norm, u(1) / norm, u(2) / norm, u(3) / norm);
        w_.chart = uh.toRotationMatrix();
        c_.setZero(n);
        c_.tail(n - 6) = q.tail(n - 6);
        multibody::kinematics(*t_, w_, c_, false);
        // A = ∂φ/∂u = (2/|u|) P(û), P δ = Im(conj(û) ⊗ δ) = w δ_v − δ_0 v − v × δ_v.
        const vec3 v(uh.x(), uh.y(), uh.z());
        a_.col(0) = -v;
        a_.rightCols<3>() = uh.w() * mat3::Identity() - multibody::skew(v);
        a_ *= 2.0 / norm;
    }

    /// Body b's pose in the world at the last at().
    template <class = void>
    [[nodiscard]] multibody::pose pose(int b) const {
        multibody::pose p = w_.x[static_cast<std::size_t>(b)];
        p.origin += x_;
        return p;
    }

    /// ∂P/∂q (3 × d) of the point of body b now at world position `p`.
    template <class = void>
    void jacobian(int b, const vec3& p,
                  Eigen::Ref<Eigen::Matrix<double, 3, Eigen::Dynamic>> out) const {
        out.setZero();
        const bool free = t_->base == multibody::base_kind::free;
        const vec3 local = p - x_; // in the chart, the origin is at x
        for (int j = b; j >= 0; j = t_->bodies[static_cast<std::size_t>(j)].parent) {
            const multibody::vec6& s = w_.s[static_cast<std::size_t>(j)];
            const vec3 column = s.tail<3>() + s.head<3>().cross(local);
            const int c = t_->coordinate(j);
            const double wgt = t_->weight(j);
            if (!free)
                out.col(c) += wgt * column;
            else if (c < 3)
                out.col(c) += column;
            else if (c < 6)
                out.middleCols<4>(3) += column * a_.row(c - 3);
            else
                out.col(c + 1) += wgt * column;
        }
    }

  private:
    std::shared_ptr<const multibody::tree> t_;
    multibody::workspace w_;
    Eigen::VectorXd c_, q_; // q_: the last at()'s
    vec3 x_ = vec3::Zero();
    Eigen::Matrix<double, 3, 4> a_ = Eigen::Matrix<double, 3, 4>::Zero();
};

} // namespace varsym::contact
