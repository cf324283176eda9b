// models/src/robot_parts.hpp: what the robot model's files share (robot.cpp: the model, fixed
// and planar bases; robot_free.cpp: a free-floating base): the parameters, the coordinates'
// names, the forces built from the parameters, and the floating base's columns. Private to the
// models layer.
#pragma once

#include <string>
#include <vector>

#include "simulation_of.hpp"
#include "varsym/contact/stepper.hpp"
#include "varsym/models/robot.hpp"
#include "varsym/multibody/floating.hpp"
#include "varsym/systems/expression_force.hpp"

namespace varsym::models::robot_detail {

/// Every robot's parameters.
struct robot_parameters {
    double gravity, no_damping, move_time, no_gravity_compensation;
    double contact, friction, ground_height, ground_slope;
    std::vector<double> kp, kd, target, torque, boxes;
};

/// Damping, the PD controller, and the joint torques typed as expressions (constant torques
/// are expressions too).
using robot_force = force_sum<rayleigh_damping<dynamic>, pd_controller<dynamic>, expression_force>;

/// The number of the model's coordinates that are the base's: 0 (fixed), 3 (planar: base_x,
/// base_z, base_ry) or 7 (free: base_x, base_y, base_z, base_qw, base_qx, base_qy, base_qz).
int base_size(const multibody::tree& r);

/// The forces of parameters p on a robot whose model has `dim` coordinates, the first `base`
/// of them its base's (no force there): damping (per model coordinate), the PD controller from
/// the start q0 (with `compensation` if given), the constant torques or the typed ones. `forced`
/// says whether any of them acts.
struct robot_forces {
    robot_force force;
    bool forced = false;
};
robot_forces make_forces(const robot_parameters& p, const expression_force& typed,
                         const vec<dynamic>& damping, const vec<dynamic>& q0, int base,
                         const std::function<void(pd_controller<dynamic>&)>& compensation);

/// The floating base's columns after energy … limit_violations: base_vx…z, base_wx…z (world),
/// momentum_x…z, angular_momentum_x…z (about the world's origin), com_x…z.
const std::vector<std::string>& base_columns();
void fill_base(const multibody::base_motion& b, double* out);

/// The contact of parameters p (contact, friction, ground_height, ground_slope, boxes) for robot
/// r: off, or on with the ground plane and the static boxes (six numbers each: centre x, y, z
/// and sides [m]), checked: r has collision shapes (no mesh; the message names the link), the
/// world's parameters are not given without contact, every box has positive sides, and the
/// start q0 (the model's coordinates) is not inside the ground or a box by more than 1e-9 m.
struct robot_contact {
    bool on = false;
    std::vector<contact::obstacle> world;
};
robot_contact contact_of(const robot_parameters& p, const std::shared_ptr<const multibody::tree>& r,
                         const vec<dynamic>& q0);

/// The contact columns (after all others): contacts (with a normal impulse in the last step),
/// normal_impulse and friction_impulse (their sums over the contacts in the last step [N s]),
/// penetration (the largest at the step's end [m]) and contact_work (since t = 0 [J]).
const std::vector<std::string>& contact_columns();
template <class St>
void fill_contact(const St& st, double* out) {
    if constexpr (requires { st.last_contact(); }) {
        const contact::contact_report& c = st.last_contact();
        out[0] = c.active;
        out[1] = c.normal;
        out[2] = c.friction;
        out[3] = c.penetration;
        out[4] = st.contact_work();
    }
}

/// The simulation of stepper s from x0, in the contact step when c is on.
template <class S, class Fill>
std::unique_ptr<simulation>
simulate_robot(S s, const robot_contact& c, const std::shared_ptr<const multibody::tree>& r,
               const phase_state<dynamic>& x0, detail::column_set<Fill> cols) {
    if (!c.on) return detail::simulate_general(std::move(s), x0, std::move(cols));
    return detail::simulate_general(contact::contact_stepper<S>(std::move(s), r, c.world), x0,
                                    std::move(cols));
}

/// The simulation of a robot with a free base (robot_free.cpp).
problem simulate_free(const std::shared_ptr<const multibody::tree>& r,
                      const expression_force& typed, const std::vector<std::string>& names,
                      const robot_parameters& p, const start& s);

} // namespace varsym::models::robot_detail
