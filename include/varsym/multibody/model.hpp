// varsym/multibody/model.hpp: a kinematic tree of rigid bodies joined by one-degree-of-freedom
// joints (revolute or prismatic), read once (from a URDF file, models/src/urdf.cpp, or built in
// code) and then constant, and the workspace of one thread's evaluations. The recursive
// algorithms (algorithms.hpp) are free functions over the two, as Pinocchio's Model/Data and
// MuJoCo's mjModel/mjData: one model serves every thread, each with its own workspace.
//
// Conventions: body i moves by joint i, whose coordinate is q_i (rad or m); body i's parent is
// parent[i] < i, or −1 for the ground. Mimic joints (URDF <mimic>) come last: body dof() + k
// moves by a joint whose position is θ = multiplier · q_master + offset (mimics[k]), not a
// coordinate; so L(q, q̇) = L_θ(θ(q), A q̇) with A = ∂θ/∂q, and every derivative is contracted by
// the chain rule (∂L/∂q = Aᵀ ∂L_θ/∂θ, M = Aᵀ M_θ A), as Pinocchio's and MuJoCo's mimic joints. Joint i's frame is at `placement` in its parent body's
// frame (the ground's: the world) at q_i = 0; the joint turns about, or slides along, the unit
// `axis` of that frame, and the body's frame is the joint frame so moved. Mass properties are
// in the body's frame: mass [kg], centre of mass [m], rotational inertia about it [kg m²].
#pragma once

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "varsym/multibody/spatial.hpp"

namespace varsym::multibody {

enum class joint_kind { revolute, prismatic };

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

/// A mimic joint's coupling: its position is multiplier · q_master + offset [rad or m].
struct mimic {
    int master = 0; ///< the coordinate it follows (a body below dof())
    double multiplier = 1.0;
    double offset = 0.0;
};

/// The constant model: bodies in tree order (parents first), frames, gravity [m/s²]; the last
/// mimics.size() bodies move by mimic joints.
struct model {
    std::string name;
    std::vector<body> bodies;
    std::vector<frame> frames;
    vec3 gravity{0.0, 0.0, -9.81};
    std::vector<mimic> mimics; ///< of bodies dof(), dof() + 1, …

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

/// One thread's scratch for the algorithms, sized for a model once (resize) and then reused
/// without allocating. World-frame quantities per body i, over the scalar S (double; a dual
/// number for robot_lagrangian::third).
template <class S>
struct basic_workspace {
    std::vector<basic_pose<S>> x;       ///< body frames in the world
    std::vector<vec6_of<S>> s;          ///< joint motion subspaces S_i
    std::vector<mat6_of<S>> inertia;    ///< body spatial inertias I_i; composite I^c_i after a pass
    std::vector<vec6_of<S>> v;          ///< body velocities v_i
    std::vector<vec6_of<S>> a;          ///< body accelerations (the recursive Newton–Euler pass)
    std::vector<vec6_of<S>> h;          ///< momenta I_i v_i; composite h^c_i after a pass
    std::vector<vec6_of<S>> f;          ///< gravity wrenches I_i a_g; composite F^c_i after a pass
    std::vector<vec6_of<S>> u, alpha;   ///< S_i × v_parent(i) and S_i × a_g
    std::vector<vec6_of<S>> dh, df;     ///< ∂h^c_i/∂q_i and ∂F^c_i/∂q_i
    std::vector<row6_of<S>> r, s_ic, t; ///< per-body rows of the second derivatives

    void resize(int n) {
        const auto k = static_cast<std::size_t>(n);
        if (x.size() == k) return;
        x.resize(k);
        s.resize(k);
        inertia.resize(k);
        v.resize(k);
        a.resize(k);
        h.resize(k);
        f.resize(k);
        u.resize(k);
        alpha.resize(k);
        dh.resize(k);
        df.resize(k);
        r.resize(k);
        s_ic.resize(k);
        t.resize(k);
    }
};
using workspace = basic_workspace<double>;

} // namespace varsym::multibody
