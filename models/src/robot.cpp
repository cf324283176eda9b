// models/src/robot.cpp: the model `urdf`, a robot read from a URDF file (urdf.cpp), run by the
// general engine on the recursive multibody derivatives (varsym/multibody/lagrangian.hpp). Its
// forces: the URDF's joint damping, a joint PD controller tracking a minimum-jerk move to a
// target (optionally with gravity compensation), and constant joint torques. One stepper type
// with forces and one without serve every robot: nothing is compiled per robot. The model is
// put together from named parts: its parameters (declared once, read into robot_parameters),
// its description, its simulation, its controlled system and its limits. A planar base is three
// coordinates of the tree like the joints; a free base runs in robot_free.cpp.
#include <cstdio>
#include <string>
#include <vector>

#include "robot_parts.hpp"
#include "varsym/models/parameters.hpp"
#include "varsym/multibody/lagrangian.hpp"
#include "varsym/optimal/input_system.hpp"
#include "varsym/problems/arm.hpp"

namespace varsym::models {

namespace {

using robot_detail::base_columns;
using robot_detail::base_size;
using robot_detail::contact_columns;
using robot_detail::contact_of;
using robot_detail::fill_base;
using robot_detail::fill_contact;
using robot_detail::make_forces;
using robot_detail::robot_force;
using robot_detail::robot_forces;
using robot_detail::robot_parameters;
using robot_detail::simulate_free;
using robot_detail::simulate_robot;
using robot = multibody::robot_lagrangian;
using robot_system = lagrangian_system<robot>;

const parameter_set<robot_parameters>& robot_set() {
    using rp = robot_parameters;
    static const parameter_set<rp> set{
        {{&rp::gravity,
          {.name = "gravity",
           .value = 9.81,
           .unit = "m/s^2",
           .doc = "gravity along -z",
           .lower = 0.0}},
         {&rp::no_damping,
          {.name = "no_damping",
           .value = 0.0,
           .doc = "leave the URDF's joint damping out",
           .lower = 0.0,
           .upper = 1.0,
           .flag = true}},
         {&rp::move_time,
          {.name = "move_time",
           .value = 2.0,
           .unit = "s",
           .doc = "duration of the PD controller's minimum-jerk move to the target",
           .lower = 0.0,
           .lower_open = true}},
         {&rp::no_gravity_compensation,
          {.name = "no_gravity_compensation",
           .value = 0.0,
           .doc = "leave gravity out of the PD controller",
           .lower = 0.0,
           .upper = 1.0,
           .flag = true}},
         {&rp::contact,
          {.name = "contact",
           .value = 0.0,
           .doc = "hard contact of the links' <collision> shapes with the ground (docs/contact.md)",
           .lower = 0.0,
           .upper = 1.0,
           .flag = true}},
         {&rp::friction,
          {.name = "friction",
           .value = 1.0,
           .doc = "Coulomb friction coefficient of the ground and the boxes (with contact)",
           .lower = 0.0,
           .upper = 1000.0}},
         {&rp::ground_height,
          {.name = "ground_height",
           .value = 0.0,
           .unit = "m",
           .doc = "the ground's height at x = 0 (with contact)"}},
         {&rp::ground_slope,
          {.name = "ground_slope",
           .value = 0.0,
           .unit = "rad",
           .doc = "the ground's slope, rising along +x (with contact)",
           .lower = -1.5,
           .upper = 1.5}}},
        {{&rp::kp,
          {.name = "kp",
           .unit = "N m/rad",
           .doc = "PD proportional gain per joint (none: no PD)",
           .lower = 0.0}},
         {&rp::kd,
          {.name = "kd",
           .unit = "N m s/rad",
           .doc = "PD derivative gain per joint (0 each)",
           .lower = 0.0}},
         {&rp::target,
          {.name = "target", .unit = "rad", .doc = "PD target joint positions (the start)"}},
         {&rp::torque, {.name = "torque", .unit = "N m", .doc = "constant joint torques (0 each)"}},
         {&rp::boxes,
          {.name = "boxes",
           .unit = "m",
           .doc = "static boxes on the ground (with contact): centre x, y, z and sides, six "
                  "numbers a box"}}}};
    return set;
}

/// The parameters only a simulation uses: the controller's, the constant torques and contact's
/// (optimal control's transcription has no contact).
const std::vector<std::string> simulation_only = {
    "move_time", "no_gravity_compensation", "kp",           "kd",   "target", "torque", "contact",
    "friction",  "ground_height",           "ground_slope", "boxes"};

/// The description: name, summary, text, coordinates, run lengths, default start.
void describe(model& m, const multibody::tree& r) {
    const std::vector<std::string> names = robot_coordinates(r);
    const auto n = static_cast<int>(names.size());
    const int joints = n - base_size(r);
    const std::string base =
        r.base == multibody::base_kind::free
            ? "\n  Its base is free (docs/robots.md): q starts with base_x, base_y, base_z\n"
              "  [m, world] and the unit quaternion base_qw, base_qx, base_qy, base_qz (world\n"
              "  from the root link; its rate in v0: qdot = 1/2 q * (0, w_body)), a constraint\n"
              "  the scheme keeps. The lists kp, kd, target and torque are per joint after the\n"
              "  base; no gravity compensation. More columns: quaternion_residual (|q|^2 - 1),\n"
              "  base_vx..vz, base_wx..wz (world), momentum_x..z, angular_momentum_x..z\n"
              "  (total, about the world origin: conserved without gravity), com_x..z."
        : r.base == multibody::base_kind::planar
            ? "\n  Its base is planar (docs/robots.md): q starts with base_x, base_z [m] and the\n"
              "  pitch base_ry [rad] about y. The lists kp, kd, target and torque are per joint\n"
              "  after the base; no gravity compensation. More columns: base_vx..vz,\n"
              "  base_wx..wz (world), momentum_x..z, angular_momentum_x..z (total, about the\n"
              "  world origin), com_x..z."
            : "";
    m.name = "urdf";
    m.summary = "a robot read from a URDF file: joint damping, PD control, joint torques";
    m.description =
        "  The robot " + r.name + " (" + std::to_string(joints) +
        " joints): L = 1/2 qdot' M(q) qdot - V(q) from its links' masses and\n"
        "  inertia tensors, derivatives by the recursive algorithms (docs/robots.md). q are the\n"
        "  joint positions [rad, m] in depth-first order from the root; gravity along -z.\n"
        "  Forces: the URDF's joint damping (--no-damping drops it); a PD controller on every\n"
        "  joint when --kp is given, tracking a minimum-jerk move from the start to --target\n"
        "  over --move-time, with gravity compensation unless --no-gravity-compensation;\n"
        "  constant joint torques --torque, or torques typed as expressions in t, the joints'\n"
        "  names and NAME_dot. Columns: energy, work (of the forces since t = 0),\n"
        "  energy_balance (energy - E0 - work: the scheme's error), limit_violations (joints\n"
        "  outside their URDF position limits). Conserved without forces: energy. No period.\n"
        "  Contact (--contact, docs/contact.md): the links' <collision> spheres, boxes,\n"
        "  cylinders and capsules touch the ground z = ground_height + x tan(ground_slope),\n"
        "  hard (no penetration, inelastic) with Coulomb friction (--friction) on the exact\n"
        "  cone, inside the step, and the static boxes --boxes (x,y,z,sx,sy,sz each, axis-\n"
        "  aligned); meshes are refused. More columns: contacts, normal_impulse\n"
        "  and friction_impulse (sums over the contacts in the last step [N s]), penetration\n"
        "  [m], contact_work [J] (included in work)." +
        base;
    m.dim = n;
    for (int i = 0; i < n; ++i) // the coordinates' joints (mimic joints come after them)
        m.coordinates += (i ? ", " : "") + names[static_cast<std::size_t>(i)];
    m.time = 5.0;
    m.steps = 5000;
    m.ensemble_time = 5.0;
    m.ensemble_steps = 1000;
    m.q0.assign(static_cast<std::size_t>(n), 0.0);
    m.p0 = m.q0;
    if (r.base == multibody::base_kind::free) m.q0[3] = 1.0; // the identity quaternion
}

/// The simulation of robot r at parameters p from start s, with the joint torques `typed`.
problem simulate(const std::shared_ptr<const multibody::tree>& r, const expression_force& typed,
                 const std::vector<std::string>& names, const robot_parameters& p, const start& s) {
    if (r->base == multibody::base_kind::free) return simulate_free(r, typed, names, p, s);
    const int n = r->dof();
    const int nb = r->base_coordinates(); // a planar base's first, then the joints
    const robot lag(std::make_shared<const multibody::tree>(r->with_gravity(p.gravity)));
    const robot_system sys(lag);
    const phase_state<dynamic> x0 = detail::general_start(
        sys, s, vec<dynamic>(vec<dynamic>::Zero(n)), vec<dynamic>(vec<dynamic>::Zero(n)));
    const vec<dynamic> damping =
        p.no_damping != 0.0 ? vec<dynamic>(vec<dynamic>::Zero(n)) : r->limits().damping;
    const auto compensation = [lag](pd_controller<dynamic>& pd) { pd.compensate(lag); };
    robot_forces rf =
        make_forces(p, typed, damping, x0.q, nb,
                    nb == 0 ? std::function<void(pd_controller<dynamic>&)>(compensation) : nullptr);
    const double e0 = sys.energy(x0);
    const robot_detail::robot_contact touch = contact_of(p, r, x0.q);
    // Columns: E, the forces' work W (0 without forces; with contact's), E − E0 − W, joints out
    // of range; a planar base's velocity, the momenta and the centre of mass; the contacts.
    std::vector<std::string> cols = {"energy", "work", "energy_balance", "limit_violations"};
    if (nb > 0) cols.insert(cols.end(), base_columns().begin(), base_columns().end());
    const int at = static_cast<int>(cols.size());
    if (touch.on) cols.insert(cols.end(), contact_columns().begin(), contact_columns().end());
    auto columns = [cols, sys, e0, r, names, nb, at] {
        return detail::column_set{
            cols,
            [sys, e0, r, nb, at](double, const phase_state<dynamic>& x, const auto& st,
                                 double* out) {
                out[0] = sys.energy(x);
                out[1] = st.total_work();
                out[2] = out[0] - e0 - out[1];
                out[3] = r->limit_violations(x.q);
                if (nb > 0)
                    fill_base(multibody::tree_motion(*r, x.q, sys.velocity(x.q, x.p)), out + 4);
                fill_contact(st, out + at);
            },
            names};
    };
    problem pr = detail::make_problem(x0, 0.0, {});
    if (!rf.forced) {
        pr.simulate = [sys, x0, columns, touch, r](const step_options& o) {
            detail::check_general(o);
            return simulate_robot(general::stepper<robot>(sys, o.h, o.spec, o.newton), touch, r, x0,
                                  columns());
        };
        return pr;
    }
    pr.simulate = [sys, f = std::move(rf.force), x0, columns, touch, r](const step_options& o) {
        detail::check_general(o);
        return simulate_robot(general::stepper<robot, robot_force>(sys, f, o.h, o.spec, o.newton),
                              touch, r, x0, columns());
    };
    return pr;
}

/// Optimal control keeps to fixed bases (its transcription has no floating base yet).
void refuse_floating(const multibody::tree& r) {
    if (r.base != multibody::base_kind::fixed)
        throw std::invalid_argument(
            "optimal control of a robot with a floating base is not available yet: read the "
            "robot with base fixed");
}

/// The controlled system: the torques (forces) of the actuated joints, those whose URDF effort
/// is positive, with the URDF's joint damping.
std::shared_ptr<const optimal::controlled_system>
control(const std::shared_ptr<const multibody::tree>& r, const robot_parameters& p) {
    refuse_floating(*r);
    const auto actuated = r->actuated();
    if (actuated.empty())
        throw std::invalid_argument("no joint of " + r->name +
                                    " is actuated (its URDF effort is 0 for every joint): "
                                    "nothing to control");
    const int d = r->dof();
    optimal::matrix b = optimal::matrix::Zero(d, static_cast<Eigen::Index>(actuated.size()));
    for (std::size_t j = 0; j < actuated.size(); ++j)
        b(actuated[j], static_cast<Eigen::Index>(j)) = 1.0;
    const optimal::matrix c = p.no_damping != 0.0
                                  ? optimal::matrix(optimal::matrix::Zero(d, d))
                                  : optimal::matrix(r->limits().damping.asDiagonal());
    return std::make_shared<const optimal::input_system<robot>>(
        robot(std::make_shared<const multibody::tree>(r->with_gravity(p.gravity))), std::move(b),
        c);
}

/// The limits: the actuated joints' efforts bound the controls, the joints' position and
/// velocity limits (a URDF velocity of 0: none) bound q and q̇, each where the problem leaves
/// them unbounded.
void limits(const multibody::tree& r, optimal::control_problem& p) {
    refuse_floating(r);
    const auto unbounded = [](const vec<dynamic>& lo, const vec<dynamic>& hi) {
        return (lo.array() == -optimal::unbounded).all() &&
               (hi.array() == optimal::unbounded).all();
    };
    const multibody::tree::limit_vectors l = r.limits();
    if (unbounded(p.control_lower, p.control_upper)) {
        const auto actuated = r.actuated();
        const vec<dynamic> effort = l.effort(actuated);
        p.control_lower = -effort;
        p.control_upper = effort;
    }
    if (unbounded(p.position_lower, p.position_upper)) {
        p.position_lower = l.lower;
        p.position_upper = l.upper;
    }
    if (unbounded(p.velocity_lower, p.velocity_upper)) {
        p.velocity_upper = (l.velocity.array() > 0.0).select(l.velocity, optimal::unbounded);
        p.velocity_lower = -p.velocity_upper;
    }
}

} // namespace

model robot_model(std::shared_ptr<const multibody::tree> r,
                  const std::vector<std::string>& torques) {
    if (!r) throw std::invalid_argument("robot_model: no robot");
    const std::vector<std::string> names = robot_coordinates(*r); // the model's coordinates
    const int n = static_cast<int>(names.size()), nb = base_size(*r);
    if (!torques.empty() && static_cast<int>(torques.size()) != n - nb)
        throw std::invalid_argument("the joint torques need " + std::to_string(n - nb) +
                                    " expressions (one per joint), got " +
                                    std::to_string(torques.size()));
    std::vector<std::string> all(static_cast<std::size_t>(nb), "0"); // none on the base
    all.insert(all.end(), torques.begin(), torques.end());
    // Parsed once here, refusing a bad expression before any run; copied by every problem.
    const expression_force typed =
        torques.empty() ? expression_force(n) : expression_force(all, names, {});
    model m;
    describe(m, *r);
    const auto& set = robot_set();
    set.declare(m);
    m.make = set.make([r, typed, names](const robot_parameters& p, const start& s) {
        return simulate(r, typed, names, p, s);
    });
    m.controls = {"u [N m or N]: the torque (force) at each actuated joint (URDF effort > 0)"};
    m.simulation_only = simulation_only;
    m.control = set.control([r](const robot_parameters& p) { return control(r, p); });
    m.limits =
        set.limits([r](const robot_parameters&, optimal::control_problem& p) { limits(*r, p); });
    return m;
}

std::vector<int> actuated_joints(const multibody::tree& r) {
    std::vector<int> out = r.actuated();      // the tree's coordinates; a free base's model has
    if (r.base == multibody::base_kind::free) // one more (the quaternion) before the joints
        for (int& i : out)
            ++i;
    return out;
}

const model& robot_options() {
    static const model m = [] {
        model out;
        out.name = "urdf";
        out.summary = "a robot read from a URDF file: joint damping, PD control, joint torques";
        robot_set().declare(out);
        out.controls = {
            "u [N m or N]: the torque (force) at each actuated joint (URDF effort > 0)"};
        out.simulation_only = simulation_only;
        return out;
    }();
    return m;
}

std::vector<contact::obstacle> robot_obstacles(std::shared_ptr<const multibody::tree> r,
                                               std::span<const double> values, const lists& given,
                                               const Eigen::VectorXd& q0) {
    if (!r) throw std::invalid_argument("robot_obstacles: no robot");
    return contact_of(robot_set().read(values, given), r, q0).world;
}

} // namespace varsym::models
