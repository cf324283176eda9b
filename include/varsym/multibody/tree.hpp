// varsym/multibody/tree.hpp: a kinematic tree of rigid bodies joined by one-degree-of-freedom
// joints (revolute or prismatic), read once (from a URDF file, models/src/urdf.cpp, or built in
// code) and then constant, and the workspace of one thread's evaluations. The recursive
// algorithms (algorithms.hpp) are free functions over the two, as Pinocchio's Model/Data and
// MuJoCo's mjModel/mjData: one tree serves every thread, each with its own workspace.
//
// Conventions: body i moves by joint i, whose coordinate is q_i (rad or m); body i's parent is
// parent[i] < i, or −1 for the ground. Mimic joints (URDF <mimic>) come last: body dof() + k
// moves by a joint whose position is θ = multiplier · q_master + offset (mimics[k]), not a
// coordinate; so L(q, q̇) = L_θ(θ(q), A q̇) with A = ∂θ/∂q, and every derivative is contracted by
// the chain rule (∂L/∂q = Aᵀ ∂L_θ/∂θ, M = Aᵀ M_θ A), as Pinocchio's and MuJoCo's mimic joints.
// Joint i's frame is at `placement` in its parent body's frame (the ground's: the world) at q_i =
// 0; the joint turns about, or slides along, the unit `axis` of that frame, and the body's frame is
// the joint frame so moved. Mass properties are in the body's frame: mass [kg], centre of mass [m],
// rotational inertia about it [kg m²].
#pragma once

#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "varsym/multibody/spatial.hpp"

namespace varsym::multibody {

enum class joint_kind { revolute, prismatic };

/// How the root link is held: bolted to the ground (fixed), free in space, or free in the x–z
/// plane (x, z and the pitch about y: the tree's first coordinates, base_x, base_z, base_ry).
/// A free base is six virtual joints of the tree (base_dx, base_dy, base_dz along the world's
/// axes, base_drx, base_dry, base_drz about the base's), the coordinates of a chart that the
/// free_robot Lagrangian (floating.hpp) centres at each point it evaluates; its model's
/// coordinates are the position and a unit quaternion.
enum class base_kind { fixed, free, planar };

/// What bounds a joint (from the URDF's <limit> and <dynamics>): position range, effort,
/// velocity and viscous damping [N m s/rad or N s/m]. Unbounded: infinite.
struct joint_limits {
    double lower = -std::numeric_limits<double>::infinity();
    double upper = std::numeric_limits<double>::infinity();
    double effort = std::numeric_limits<double>::infinity();
    double velocity = std::numeric_limits<double>::infinity();
    double damping = 0.0;
};

/// One moving body and the joint that moves it.
struct body {
    std::string name; ///< the joint's name (the coordinate's name)
    std::string link; ///< the body's name (its URDF link)
    int parent = -1;  ///< its parent body, or −1 for the ground
    joint_kind kind = joint_kind::revolute;
    pose placement;            ///< the joint frame in the parent's frame at q = 0
    vec3 axis = vec3::UnitZ(); ///< unit axis in the joint frame
    double mass = 0.0;
    vec3 com = vec3::Zero();
    mat3 inertia = mat3::Zero(); ///< about the centre of mass, in the body frame
    joint_limits limits;
};

/// A named frame fixed to a body (or to the ground, body −1): a URDF link merged into its
/// parent through a fixed joint, or a body's own frame.
struct frame {
    std::string name;
    int body = -1;
    pose offset; ///< in the body's frame
};

/// A collision shape (URDF <collision>) fixed to a body (−1: the ground), in its shape frame at
/// `offset` in the body's frame. sphere: radius size(0); box: side lengths size; cylinder and
/// capsule: radius size(0) and length size(1) along the shape frame's z (a capsule's length
/// between its end spheres' centres); mesh: its file (`mesh`, not read: contact refuses it). A
/// shape the URDF reader could not take keeps the reason in `problem`.
enum class shape_kind { sphere, box, cylinder, capsule, mesh };
struct collision_shape {
    std::string link; ///< the URDF link it belongs to
    int body = -1;
    pose offset;
    shape_kind kind = shape_kind::sphere;
    vec3 size = vec3::Zero(); ///< [m]
    std::string mesh{};       ///< a mesh's filename
    std::string problem{};    ///< why the reader could not take it (contact refuses it)
};

/// A visual shape (URDF <visual>): a collision_shape (a mesh's `size` is its scale) and its
/// material's colour, r, g, b, a in [0, 1] (a < 0: the URDF gave none). Drawn only
/// (models/animation.hpp), never simulated.
struct visual_shape : collision_shape {
    std::array<double, 4> rgba{0.7, 0.7, 0.7, -1.0};
};

/// A mimic joint's coupling: its position is multiplier · q_master + offset [rad or m].
struct mimic {
    int master = 0; ///< the coordinate it follows (a body below dof())
    double multiplier = 1.0;
    double offset = 0.0;
};

/// The constant tree: bodies in tree order (parents first), frames, gravity [m/s²]; the last
/// mimics.size() bodies move by mimic joints.
struct tree {
    std::string name;
    std::vector<body> bodies;
    std::vector<frame> frames;
    vec3 gravity{0.0, 0.0, -9.81};
    std::vector<mimic> mimics;               ///< of bodies dof(), dof() + 1, …
    std::vector<collision_shape> collisions; ///< the links' <collision> shapes
    std::vector<visual_shape> visuals;       ///< the links' <visual> shapes
    base_kind base = base_kind::fixed;
    /// The root link's name and mass properties (with the links fixed to it merged): the ground
    /// of a fixed base, what with_base sets moving (its `link`, `mass`, `com`, `inertia`).
    body root;

    /// The number of the base's coordinates (0, 6 or 3): they come first in q.
    [[nodiscard]] int base_coordinates() const {
        return base == base_kind::free ? 6 : base == base_kind::planar ? 3 : 0;
    }
    /// The body whose placement turns with the orientation chart of a free base (floating.hpp):
    /// the first of its rotations; −1 for other bases.
    [[nodiscard]] int chart_body() const { return base == base_kind::free ? 3 : -1; }

    /// The number of coordinates: the bodies but the mimic ones.
    [[nodiscard]] int dof() const { return static_cast<int>(bodies.size() - mimics.size()); }
    [[nodiscard]] int body_count() const { return static_cast<int>(bodies.size()); }
    /// The coordinate that moves body i's joint and ∂θ_i/∂q of it: (i, 1) or (master, multiplier).
    [[nodiscard]] int coordinate(int i) const {
        return i < dof() ? i : mimics[static_cast<std::size_t>(i - dof())].master;
    }
    [[nodiscard]] double weight(int i) const {
        return i < dof() ? 1.0 : mimics[static_cast<std::size_t>(i - dof())].multiplier;
    }
    /// Body i's joint position θ_i from the coordinates q (any scalar).
    template <class Q>
    [[nodiscard]] typename Q::Scalar joint_position(const Q& q, int i) const {
        using S = typename Q::Scalar;
        if (i < dof()) return q(i);
        const mimic& c = mimics[static_cast<std::size_t>(i - dof())];
        return S(c.multiplier) * q(c.master) + S(c.offset);
    }
    /// Body i's joint rate θ̇_i from the coordinates' rates q̇.
    template <class V>
    [[nodiscard]] typename V::Scalar joint_rate(const V& qd, int i) const {
        using S = typename V::Scalar;
        if (i < dof()) return qd(i);
        return S(weight(i)) * qd(coordinate(i));
    }

    /// This tree with gravity of magnitude g [m/s²] along −z (a model's parameter `gravity`).
    [[nodiscard]] tree with_gravity(double g) const {
        tree t = *this;
        t.gravity = vec3(0.0, 0.0, -g);
        return t;
    }
    /// The coordinates' joint data as vectors, one value per coordinate (bodies 0 … dof() − 1):
    /// position bounds [rad or m], effort [N m or N], velocity [rad/s or m/s] (0 or infinite:
    /// none) and viscous damping, as joint_limits holds them.
    struct limit_vectors {
        Eigen::VectorXd lower, upper, effort, velocity, damping;
    };
    [[nodiscard]] limit_vectors limits() const {
        const int n = dof();
        limit_vectors out{Eigen::VectorXd(n), Eigen::VectorXd(n), Eigen::VectorXd(n),
                          Eigen::VectorXd(n), Eigen::VectorXd(n)};
        for (int i = 0; i < n; ++i) {
            const joint_limits& l = bodies[static_cast<std::size_t>(i)].limits;
            out.lower(i) = l.lower;
            out.upper(i) = l.upper;
            out.effort(i) = l.effort;
            out.velocity(i) = l.velocity;
            out.damping(i) = l.damping;
        }
        return out;
    }
    /// The actuated coordinates (their indices): those whose joint effort is positive.
    [[nodiscard]] std::vector<int> actuated() const {
        std::vector<int> out;
        for (int i = 0; i < dof(); ++i)
            if (bodies[static_cast<std::size_t>(i)].limits.effort > 0.0) out.push_back(i);
        return out;
    }
    /// The coordinates outside their position bounds at q.
    template <class Q>
    [[nodiscard]] int limit_violations(const Q& q) const {
        int n = 0;
        for (int i = 0; i < dof(); ++i) {
            const joint_limits& l = bodies[static_cast<std::size_t>(i)].limits;
            n += (q(i) < l.lower || q(i) > l.upper) ? 1 : 0;
        }
        return n;
    }

    /// This tree with its root link set free: `free` prepends three prismatic joints along the
    /// world's x, y, z (base_dx, base_dy, base_dz) and three revolute ones about the base's x,
    /// y, z (base_drx, base_dry, base_drz: the orientation is chart · Rx Ry Rz, floating.hpp);
    /// `planar` prepends base_x, base_z and base_ry. The last of them carries the root link's
    /// mass; the others are massless, unlimited and unactuated (effort 0). The tree's bodies
    /// follow, hung from the base; frames fixed to the ground move with it. Throws
    /// std::invalid_argument for a tree already floating or a root link without mass.
    [[nodiscard]] tree with_base(base_kind kind) const {
        if (kind == base_kind::fixed) return *this;
        if (base != base_kind::fixed)
            throw std::invalid_argument("the robot " + name + " already has a floating base");
        if (!(std::isfinite(root.mass) && root.mass > 0.0 && root.com.allFinite() &&
              root.inertia.allFinite()))
            throw std::invalid_argument("the root link " + root.link +
                                        " carries no mass (or an infinite one): a floating base "
                                        "needs the root link's <inertial> (mass and inertia)");
        struct virtual_joint {
            const char* name;
            joint_kind kind;
            vec3 axis;
        };
        const std::vector<virtual_joint> joints =
            kind == base_kind::free
                ? std::vector<virtual_joint>{{"base_dx", joint_kind::prismatic, vec3::UnitX()},
                                             {"base_dy", joint_kind::prismatic, vec3::UnitY()},
                                             {"base_dz", joint_kind::prismatic, vec3::UnitZ()},
                                             {"base_drx", joint_kind::revolute, vec3::UnitX()},
                                             {"base_dry", joint_kind::revolute, vec3::UnitY()},
                                             {"base_drz", joint_kind::revolute, vec3::UnitZ()}}
                : std::vector<virtual_joint>{{"base_x", joint_kind::prismatic, vec3::UnitX()},
                                             {"base_z", joint_kind::prismatic, vec3::UnitZ()},
                                             {"base_ry", joint_kind::revolute, vec3::UnitY()}};
        tree t;
        t.name = name;
        t.gravity = gravity;
        t.base = kind;
        t.root = root;
        const int k = static_cast<int>(joints.size());
        for (int i = 0; i < k; ++i) {
            body b;
            b.name = joints[static_cast<std::size_t>(i)].name;
            b.link = root.link;
            b.kind = joints[static_cast<std::size_t>(i)].kind;
            b.axis = joints[static_cast<std::size_t>(i)].axis;
            b.limits.effort = 0.0; // not actuated
            if (i == k - 1) {
                b.mass = root.mass;
                b.com = root.com;
                b.inertia = root.inertia;
            }
            t.add_body(i - 1, b);
        }
        for (body b : bodies) {
            const int p = b.parent < 0 ? k - 1 : b.parent + k;
            t.add_body(p, std::move(b));
        }
        t.frames = frames;
        for (frame& f : t.frames)
            f.body = f.body < 0 ? k - 1 : f.body + k;
        t.collisions = collisions;
        for (collision_shape& c : t.collisions)
            c.body = c.body < 0 ? k - 1 : c.body + k;
        t.visuals = visuals;
        for (visual_shape& c : t.visuals)
            c.body = c.body < 0 ? k - 1 : c.body + k;
        t.mimics = mimics;
        for (mimic& c : t.mimics)
            c.master += k;
        return t;
    }

    /// Appends body b as the child of body `parent` (−1: the ground), setting b.parent, and
    /// returns its index. Throws std::invalid_argument naming the body unless the parent comes
    /// before it (−1 ≤ parent < the new index).
    int add_body(int parent, body b) {
        const int index = body_count();
        if (parent < -1 || parent >= index)
            throw std::invalid_argument("body " + b.link +
                                        ": its parent must come before it in the tree");
        b.parent = parent;
        bodies.push_back(std::move(b));
        return index;
    }

    /// Checks the tree's order and each body's data; throws std::invalid_argument naming the
    /// body.
    void check() const {
        if (mimics.size() >= bodies.size() && !bodies.empty())
            throw std::invalid_argument("a robot needs a coordinate that no joint mimics");
        for (std::size_t k = 0; k < mimics.size(); ++k) {
            const mimic& c = mimics[k];
            const std::string& who = bodies[static_cast<std::size_t>(dof()) + k].name;
            if (c.master < 0 || c.master >= dof())
                throw std::invalid_argument("joint " + who + ": it mimics no coordinate");
            if (!std::isfinite(c.multiplier) || !std::isfinite(c.offset))
                throw std::invalid_argument("joint " + who +
                                            ": the mimic multiplier and offset must be finite");
        }
        for (int i = 0; i < body_count(); ++i) {
            const body& b = bodies[static_cast<std::size_t>(i)];
            if (b.parent < -1 || b.parent >= i)
                throw std::invalid_argument("body " + b.link +
                                            ": its parent must come before it in the tree");
            if (!(b.axis.allFinite() && std::abs(b.axis.norm() - 1.0) < 1e-9))
                throw std::invalid_argument("joint " + b.name + ": the axis must be a unit vector");
            if (!(std::isfinite(b.mass) && b.mass >= 0.0) || !b.com.allFinite() ||
                !b.inertia.allFinite())
                throw std::invalid_argument("body " + b.link +
                                            ": mass properties must be finite, mass >= 0");
        }
    }
};

/// One thread's scratch for the algorithms, sized for a tree once (resize) and then reused
/// without allocating. World-frame quantities per body i, over the scalar S (double; a dual
/// number for robot_lagrangian::third). Each field has one meaning, set by the pass named:
/// per-body quantities by kinematics and velocities, subtree sums (superscript c) by
/// subtree_sums, the Newton–Euler pass's by bias_forces, the second derivatives' rows by
/// lagrangian_derivatives. A field is valid from its pass until the next kinematics; the
/// spatial inertias (and what is built from them) only after a kinematics that asked for them
/// (`has_inertias`, which the readers assert).
template <class S>
struct basic_workspace {
    std::vector<basic_pose<S>> x;    ///< body frames in the world (kinematics)
    std::vector<vec6_of<S>> s;       ///< joint motion subspaces S_i (kinematics)
    std::vector<mat6_of<S>> inertia; ///< body spatial inertias I_i (kinematics, if asked)
    std::vector<vec6_of<S>> gravity; ///< body gravity wrenches I_i a_g (kinematics)
    std::vector<vec3_of<S>> com;     ///< body centres of mass in the world (kinematics)
    bool has_inertias = false;       ///< `inertia` is the last kinematics' own
    std::vector<vec6_of<S>> v;       ///< body velocities v_i (velocities)
    std::vector<vec6_of<S>> h;       ///< body momenta I_i v_i (velocities)
    /// Subtree sums over body i and its descendants (subtree_sums): the composite inertia
    /// I^c_i (where asked for), momentum h^c_i and gravity wrench F^c_i.
    std::vector<mat6_of<S>> inertia_c;
    std::vector<vec6_of<S>> h_c, gravity_c;
    std::vector<vec6_of<S>> a;          ///< body accelerations at q̈ = 0 (bias_forces)
    std::vector<vec6_of<S>> force;      ///< I_i a_i + v_i ×* h_i summed over the subtree: the
                                        ///< wrench joint i transmits (bias_forces)
    std::vector<vec6_of<S>> u, alpha;   ///< S_i × v_parent(i) and S_i × a_g
    std::vector<vec6_of<S>> dh, df;     ///< ∂h^c_i/∂q_i and ∂F^c_i/∂q_i
    std::vector<row6_of<S>> r, s_ic, t; ///< per-body rows of the second derivatives
    /// A free base's chart: the rotation applied at tree::chart_body's placement (floating.hpp;
    /// the identity for other bases). Set by the Lagrangian before each evaluation.
    mat3 chart = mat3::Identity();

    void resize(int n) {
        const auto k = static_cast<std::size_t>(n);
        if (x.size() == k) return;
        for (auto* f : {&s, &gravity, &v, &h, &h_c, &gravity_c, &a, &force, &u, &alpha, &dh, &df})
            f->resize(k);
        com.resize(k);
        x.resize(k);
        inertia.resize(k);
        inertia_c.resize(k);
        r.resize(k);
        s_ic.resize(k);
        t.resize(k);
    }
};
using workspace = basic_workspace<double>;

} // namespace varsym::multibody
