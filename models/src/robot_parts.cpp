// models/src/robot_parts.cpp: the parts of the robot model that robot.cpp (fixed and planar
// bases) and robot_free.cpp (a free base) share: the forces from the parameters, the coordinates'
// names, the floating base's columns, and contact's world and columns.
#include <cstdio>
#include <string>
#include <vector>

#include "robot_parts.hpp"
#include "varsym/models/parameters.hpp"
#include "varsym/problems/arm.hpp"

namespace varsym::models {

std::vector<std::string> robot_coordinates(const multibody::tree& r) {
    std::vector<std::string> out;
    int first = 0; // the tree's first coordinate that is the model's as it is
    if (r.base == multibody::base_kind::free) {
        out = {"base_x", "base_y", "base_z", "base_qw", "base_qx", "base_qy", "base_qz"};
        first = 6;
    }
    for (int i = first; i < r.dof(); ++i) // (mimic joints come after the coordinates)
        out.push_back(r.bodies[static_cast<std::size_t>(i)].name);
    return out;
}

namespace robot_detail {

int base_size(const multibody::tree& r) {
    return r.base == multibody::base_kind::free ? 7 : r.base_coordinates();
}

robot_forces make_forces(const robot_parameters& p, const expression_force& typed,
                         const vec<dynamic>& damping, const vec<dynamic>& q0, int base,
                         const std::function<void(pd_controller<dynamic>&)>& compensation) {
    const auto n = static_cast<int>(q0.size());
    // A list per joint; the base's coordinates take `fill` (0 by default).
    auto each = [n, base](const std::vector<double>& given, const char* name,
                          const vec<dynamic>& fill = vec<dynamic>()) {
        vec<dynamic> out = vec<dynamic>::Zero(n);
        if (fill.size() == n) out.head(base) = fill.head(base);
        if (!given.empty())
            out.tail(n - base) = Eigen::Map<const vec<dynamic>>(
                models::sized(given, static_cast<std::size_t>(n - base), name, "joint").data(),
                n - base);
        return out;
    };
    const bool controlled = !p.kp.empty();
    if (!controlled && !p.kd.empty())
        throw std::invalid_argument("kd without kp: give the proportional gains too");
    if (!controlled && !p.target.empty())
        throw std::invalid_argument("target without kp: the PD controller needs its gains");
    const vec<dynamic> torque = each(p.torque, "torque");
    if (!p.torque.empty() && !typed.zero())
        throw std::invalid_argument("give constant torques or typed ones, not both");
    pd_controller<dynamic> pd;
    pd.kp = mat<dynamic>::Zero(n, n);
    pd.kd = mat<dynamic>::Zero(n, n);
    if (controlled) {
        pd.kp.diagonal() = each(p.kp, "kp");
        pd.kd.diagonal() = each(p.kd, "kd");
        arm::minimum_jerk ref{q0, p.target.empty() ? q0 : each(p.target, "target", q0),
                              p.move_time};
        pd.reference = [ref](double t, vec<dynamic>& q, vec<dynamic>& rate) { ref(t, q, rate); };
        if (p.no_gravity_compensation == 0.0 && compensation) compensation(pd);
    }
    expression_force tau = typed;
    if (!p.torque.empty()) { // constant torques as expressions of their values (17 digits:
        std::vector<std::string> c, names; // the same doubles), over neutral names q1, q2, …
        // Appended, not `"q" + std::to_string(n)`: GCC 12 at -O3 reports a false
        // -Wstringop-overflow on that sum when this file is compiled alone.
        auto next_name = [&names] {
            std::string q = "q";
            q += std::to_string(names.size() + 1);
            names.push_back(std::move(q));
        };
        for (int i = 0; i < base; ++i) { // none on a floating base
            c.emplace_back("0");
            next_name();
        }
        for (double x : p.torque) {
            char buf[32];
            std::snprintf(buf, sizeof buf, "%.17g", x);
            c.emplace_back(buf);
            next_name();
        }
        tau = expression_force(c, names, {});
    }
    const bool forced = controlled || !torque.isZero(0.0) || !damping.isZero(0.0) || !typed.zero();
    return {
        robot_force(rayleigh_damping<dynamic>::diagonal(damping), std::move(pd), std::move(tau)),
        forced};
}

const std::vector<std::string>& base_columns() {
    static const std::vector<std::string> names = {"base_vx",
                                                   "base_vy",
                                                   "base_vz",
                                                   "base_wx",
                                                   "base_wy",
                                                   "base_wz",
                                                   "momentum_x",
                                                   "momentum_y",
                                                   "momentum_z",
                                                   "angular_momentum_x",
                                                   "angular_momentum_y",
                                                   "angular_momentum_z",
                                                   "com_x",
                                                   "com_y",
                                                   "com_z"};
    return names;
}

robot_contact contact_of(const robot_parameters& p, const std::shared_ptr<const multibody::tree>& r,
                         const vec<dynamic>& q0) {
    robot_contact out;
    if (p.contact == 0.0) {
        if (p.friction != 1.0 || p.ground_height != 0.0 || p.ground_slope != 0.0 ||
            !p.boxes.empty())
            throw std::invalid_argument("friction, ground_height, ground_slope and boxes describe "
                                        "contact: give contact too");
        return out;
    }
    const std::vector<contact::contact_point> points =
        contact::contact_points(*r); // (refuses a mesh, naming its link)
    if (points.empty())
        throw std::invalid_argument("contact needs collision shapes, and no moving link of " +
                                    r->name + " has a <collision>: add spheres or boxes");
    out.on = true;
    out.world = {contact::ground(p.ground_height, p.ground_slope, p.friction)};
    if (p.boxes.size() % 6 != 0)
        throw std::invalid_argument("boxes needs six numbers a box (centre x, y, z and sides), "
                                    "got " +
                                    std::to_string(p.boxes.size()));
    for (std::size_t i = 0; i < p.boxes.size(); i += 6) {
        const multibody::vec3 c(p.boxes[i], p.boxes[i + 1], p.boxes[i + 2]);
        const multibody::vec3 sides(p.boxes[i + 3], p.boxes[i + 4], p.boxes[i + 5]);
        const std::string name = "box " + std::to_string(i / 6 + 1);
        if (!(sides.minCoeff() > 0.0) || !sides.allFinite() || !c.allFinite())
            throw std::invalid_argument(name + " of boxes needs positive finite sides");
        out.world.push_back(contact::static_box(c, sides, p.friction, name));
    }
    contact::robot_kinematics kin(r);
    kin.at(q0);
    for (const contact::contact_point& c : points)
        for (const contact::obstacle& w : out.world) {
            multibody::vec3 n;
            const double gap = w.distance(kin.pose(c.body).point(c.point), n) - c.radius;
            if (gap < -1e-9) {
                char buf[200];
                std::snprintf(buf, sizeof buf, "link %s starts %.3g m inside the %s: %s",
                              c.link.c_str(), -gap, w.name.c_str(),
                              r->base == multibody::base_kind::fixed
                                  ? "move the joints' start, the ground or the boxes"
                                  : "raise the start (base_z)");
                throw std::invalid_argument(buf);
            }
        }
    return out;
}

const std::vector<std::string>& contact_columns() {
    static const std::vector<std::string> names = {"contacts", "normal_impulse", "friction_impulse",
                                                   "penetration", "contact_work"};
    return names;
}

void fill_base(const multibody::base_motion& b, double* out) {
    for (const multibody::vec3* v :
         {&b.velocity, &b.angular_velocity, &b.momentum, &b.angular_momentum, &b.centre_of_mass})
        for (int i = 0; i < 3; ++i)
            *out++ = (*v)(i);
}

} // namespace robot_detail

} // namespace varsym::models
