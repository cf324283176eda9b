// models/src/robot.cpp: the model `urdf`, a robot read from a URDF file (urdf.cpp), run by the
// general engine on the recursive multibody derivatives (varsym/multibody/lagrangian.hpp). Its
// forces: the URDF's joint damping, a joint PD controller tracking a minimum-jerk move to a
// target (optionally with gravity compensation), and constant joint torques. One stepper type
// with forces and one without serve every robot: nothing is compiled per robot. The model is
// put together from named parts: its parameters (declared once, read into robot_parameters),
// its description, its simulation, its controlled system and its limits.
#include <cstdio>
#include <string>
#include <vector>

#include "simulation_of.hpp"
#include "varsym/models/parameters.hpp"
#include "varsym/models/robot.hpp"
#include "varsym/multibody/lagrangian.hpp"
#include "varsym/optimal/input_system.hpp"
#include "varsym/problems/arm.hpp"
#include "varsym/systems/expression_force.hpp"

namespace varsym::models {

namespace {

using robot = multibody::robot_lagrangian;
using robot_system = lagrangian_system<robot>;
/// Damping, the PD controller, and the joint torques typed as expressions (constant torques
/// are expressions too).
using robot_force = force_sum<rayleigh_damping<dynamic>, pd_controller<dynamic>, expression_force>;

/// Every robot's parameters.
struct robot_parameters {
    double gravity, no_damping, move_time, no_gravity_compensation;
    std::vector<double> kp, kd, target, torque;
};

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
           .flag = true}}},
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
         {&rp::torque,
          {.name = "torque", .unit = "N m", .doc = "constant joint torques (0 each)"}}}};
    return set;
}

/// The parameters only a simulation uses: the controller's and the constant torques.
const std::vector<std::string> simulation_only = {
    "move_time", "no_gravity_compensation", "kp", "kd", "target", "torque"};

/// The description: name, summary, text, coordinates, run lengths, default start.
void describe(model& m, const multibody::tree& r) {
    const int n = r.dof();
    m.name = "urdf";
    m.summary = "a robot read from a URDF file: joint damping, PD control, joint torques";
    m.description =
        "  The robot " + r.name + " (" + std::to_string(n) +
        " joints): L = 1/2 qdot' M(q) qdot - V(q) from its links' masses and\n"
        "  inertia tensors, derivatives by the recursive algorithms (docs/robots.md). q are the\n"
        "  joint positions [rad, m] in depth-first order from the root; gravity along -z.\n"
        "  Forces: the URDF's joint damping (--no-damping drops it); a PD controller on every\n"
        "  joint when --kp is given, tracking a minimum-jerk move from the start to --target\n"
        "  over --move-time, with gravity compensation unless --no-gravity-compensation;\n"
        "  constant joint torques --torque, or torques typed as expressions in t, the joints'\n"
        "  names and NAME_dot. Columns: energy, work (of the forces since t = 0),\n"
        "  energy_balance (energy - E0 - work: the scheme's error), limit_violations (joints\n"
        "  outside their URDF position limits). Conserved without forces: energy. No period.";
    m.dim = n;
    for (int i = 0; i < n; ++i) // the coordinates' joints (mimic joints come after them)
        m.coordinates += (i ? ", " : "") + r.bodies[static_cast<std::size_t>(i)].name;
    m.time = 5.0;
    m.steps = 5000;
    m.ensemble_time = 5.0;
    m.ensemble_steps = 1000;
    m.q0.assign(static_cast<std::size_t>(n), 0.0);
    m.p0 = m.q0;
}

/// The simulation of robot r at parameters p from start s, with the joint torques `typed`.
problem simulate(const std::shared_ptr<const multibody::tree>& r, const expression_force& typed,
                 const std::vector<std::string>& joints, const robot_parameters& p,
                 const start& s) {
    const int n = r->dof();
    auto each = [n](const std::vector<double>& given, const char* name) {
        return given.empty()
                   ? vec<dynamic>(vec<dynamic>::Zero(n))
                   : vec<dynamic>(Eigen::Map<const vec<dynamic>>(
                         sized(given, static_cast<std::size_t>(n), name, "joint").data(), n));
    };
    const robot lag(std::make_shared<const multibody::tree>(r->with_gravity(p.gravity)));
    const robot_system sys(lag);
    const phase_state<dynamic> x0 = detail::general_start(
        sys, s, vec<dynamic>(vec<dynamic>::Zero(n)), vec<dynamic>(vec<dynamic>::Zero(n)));
    const vec<dynamic> damping =
        p.no_damping != 0.0 ? vec<dynamic>(vec<dynamic>::Zero(n)) : r->limits().damping;
    const bool controlled = !p.kp.empty();
    if (!controlled && !p.kd.empty())
        throw std::invalid_argument("kd without kp: give the proportional gains too");
    if (!controlled && !p.target.empty())
        throw std::invalid_argument("target without kp: the PD controller needs its gains");
    const vec<dynamic> torque = each(p.torque, "torque");
    if (!p.torque.empty() && !typed.zero())
        throw std::invalid_argument("give constant torques or typed ones, not both");
    const bool forced = controlled || !torque.isZero(0.0) || !damping.isZero(0.0) || !typed.zero();
    const double e0 = sys.energy(x0);
    // Columns: E, the forces' work W (0 without forces), E − E0 − W, joints out of range.
    auto columns = [sys, e0, r, joints] {
        return detail::column_set{
            {"energy", "work", "energy_balance", "limit_violations"},
            [sys, e0, r](double, const phase_state<dynamic>& x, const auto& st, double* out) {
                out[0] = sys.energy(x);
                out[1] = st.total_work();
                out[2] = out[0] - e0 - out[1];
                out[3] = r->limit_violations(x.q);
            },
            joints};
    };
    problem pr = detail::make_problem(x0, 0.0, {});
    if (!forced) {
        pr.simulate = [sys, x0, columns](const step_options& o) {
            detail::check_general(o);
            return detail::simulate_general(general::stepper<robot>(sys, o.h, o.spec, o.newton), x0,
                                            columns());
        };
        return pr;
    }
    pd_controller<dynamic> pd;
    pd.kp = mat<dynamic>::Zero(n, n);
    pd.kd = mat<dynamic>::Zero(n, n);
    if (controlled) {
        pd.kp.diagonal() = each(p.kp, "kp");
        pd.kd.diagonal() = each(p.kd, "kd");
        arm::minimum_jerk ref{x0.q, p.target.empty() ? x0.q : each(p.target, "target"),
                              p.move_time};
        pd.reference = [ref](double t, vec<dynamic>& q, vec<dynamic>& rate) { ref(t, q, rate); };
        if (p.no_gravity_compensation == 0.0) pd.compensate(lag);
    }
    expression_force tau = typed;
    if (!p.torque.empty()) { // constant torques as expressions of their values (17 digits:
        std::vector<std::string> c, names; // the same doubles), over neutral names
        for (double x : p.torque) {
            char buf[32];
            std::snprintf(buf, sizeof buf, "%.17g", x);
            c.emplace_back(buf);
            names.push_back("q" + std::to_string(names.size() + 1));
        }
        tau = expression_force(c, names, {});
    }
    const robot_force f(rayleigh_damping<dynamic>::diagonal(damping), std::move(pd),
                        std::move(tau));
    pr.simulate = [sys, f, x0, columns](const step_options& o) {
        detail::check_general(o);
        return detail::simulate_general(
            general::stepper<robot, robot_force>(sys, f, o.h, o.spec, o.newton), x0, columns());
    };
    return pr;
}

/// The controlled system: the torques (forces) of the actuated joints, those whose URDF effort
/// is positive, with the URDF's joint damping.
std::shared_ptr<const optimal::controlled_system>
control(const std::shared_ptr<const multibody::tree>& r, const robot_parameters& p) {
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
    const int n = r->dof();
    std::vector<std::string> joints; // the coordinates' (mimic joints come after them)
    for (int i = 0; i < n; ++i)
        joints.push_back(r->bodies[static_cast<std::size_t>(i)].name);
    if (!torques.empty() && static_cast<int>(torques.size()) != n)
        throw std::invalid_argument("the joint torques need " + std::to_string(n) +
                                    " expressions (one per joint), got " +
                                    std::to_string(torques.size()));
    // Parsed once here, refusing a bad expression before any run; copied by every problem.
    const expression_force typed =
        torques.empty() ? expression_force(n) : expression_force(torques, joints, {});
    model m;
    describe(m, *r);
    const auto& set = robot_set();
    set.declare(m);
    m.make = set.make([r, typed, joints](const robot_parameters& p, const start& s) {
        return simulate(r, typed, joints, p, s);
    });
    m.controls = {"u [N m or N]: the torque (force) at each actuated joint (URDF effort > 0)"};
    m.simulation_only = simulation_only;
    m.control = set.control([r](const robot_parameters& p) { return control(r, p); });
    m.limits =
        set.limits([r](const robot_parameters&, optimal::control_problem& p) { limits(*r, p); });
    return m;
}

std::vector<int> actuated_joints(const multibody::tree& r) {
    return r.actuated();
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

} // namespace varsym::models
