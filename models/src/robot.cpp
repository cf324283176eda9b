// models/src/robot.cpp: the model `urdf`, a robot read from a URDF file (urdf.cpp), run by the
// general engine on the recursive multibody derivatives (varsym/multibody/lagrangian.hpp). Its
// forces: the URDF's joint damping, a joint PD controller tracking a minimum-jerk move to a
// target (optionally with gravity compensation), and constant joint torques. One stepper type
// with forces and one without serve every robot: nothing is compiled per robot.
#include <cstdio>
#include <string>
#include <vector>

#include "simulation_of.hpp"
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

/// The joints outside their position limits at q.
int limit_violations(const multibody::model& m, const vec<dynamic>& q) {
    int n = 0;
    for (int i = 0; i < m.dof(); ++i) {
        const auto& l = m.bodies[static_cast<std::size_t>(i)].limits;
        n += (q(i) < l.lower || q(i) > l.upper) ? 1 : 0;
    }
    return n;
}

} // namespace

model robot_model(std::shared_ptr<const multibody::model> r,
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
    m.name = "urdf";
    m.summary = "a robot read from a URDF file: joint damping, PD control, joint torques";
    m.description =
        "  The robot " + r->name + " (" + std::to_string(n) +
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
    for (const std::string& name : joints)
        m.coordinates += (m.coordinates.empty() ? "" : ", ") + name;
    m.parameters = {{.name = "gravity",
                     .value = 9.81,
                     .unit = "m/s^2",
                     .doc = "gravity along -z",
                     .lower = 0.0},
                    {.name = "no_damping",
                     .value = 0.0,
                     .doc = "leave the URDF's joint damping out",
                     .lower = 0.0,
                     .upper = 1.0,
                     .flag = true},
                    {.name = "move_time",
                     .value = 2.0,
                     .unit = "s",
                     .doc = "duration of the PD controller's minimum-jerk move to the target",
                     .lower = 0.0,
                     .lower_open = true},
                    {.name = "no_gravity_compensation",
                     .value = 0.0,
                     .doc = "leave gravity out of the PD controller",
                     .lower = 0.0,
                     .upper = 1.0,
                     .flag = true}};
    m.lists = {{.name = "kp",
                .unit = "N m/rad",
                .doc = "PD proportional gain per joint (none: no PD)",
                .lower = 0.0},
               {.name = "kd",
                .unit = "N m s/rad",
                .doc = "PD derivative gain per joint (0 each)",
                .lower = 0.0},
               {.name = "target", .unit = "rad", .doc = "PD target joint positions (the start)"},
               {.name = "torque", .unit = "N m", .doc = "constant joint torques (0 each)"}};
    m.time = 5.0;
    m.steps = 5000;
    m.ensemble_time = 5.0;
    m.ensemble_steps = 1000;
    m.q0.assign(static_cast<std::size_t>(n), 0.0);
    m.p0 = m.q0;
    m.make = [r, n, typed, joints](std::span<const double> v, const start& s, const lists& l) {
        auto each = [n](const std::vector<double>& given, const char* name) {
            if (!given.empty() && static_cast<int>(given.size()) != n)
                throw std::invalid_argument(std::string(name) + " needs " + std::to_string(n) +
                                            " values (one per joint), got " +
                                            std::to_string(given.size()));
            return given.empty() ? vec<dynamic>(vec<dynamic>::Zero(n))
                                 : vec<dynamic>(Eigen::Map<const vec<dynamic>>(given.data(), n));
        };
        auto robot_at = std::make_shared<multibody::model>(*r);
        robot_at->gravity = multibody::vec3(0.0, 0.0, -v[0]);
        const robot lag(robot_at);
        const robot_system sys(lag);
        const phase_state<dynamic> x0 = detail::general_start(
            sys, s, vec<dynamic>(vec<dynamic>::Zero(n)), vec<dynamic>(vec<dynamic>::Zero(n)));
        vec<dynamic> damping(n);
        for (int i = 0; i < n; ++i)
            damping(i) = v[1] != 0.0 ? 0.0 : r->bodies[static_cast<std::size_t>(i)].limits.damping;
        const bool controlled = !l[0].empty();
        if (!controlled && !l[1].empty())
            throw std::invalid_argument("kd without kp: give the proportional gains too");
        if (!controlled && !l[2].empty())
            throw std::invalid_argument("target without kp: the PD controller needs its gains");
        const vec<dynamic> torque = each(l[3], "torque");
        if (!l[3].empty() && !typed.zero())
            throw std::invalid_argument("give constant torques or typed ones, not both");
        const bool forced =
            controlled || !torque.isZero(0.0) || !damping.isZero(0.0) || !typed.zero();
        const double e0 = sys.energy(x0);
        // Columns: E, the forces' work W (0 without forces), E − E0 − W, joints out of range.
        auto columns = [sys, e0, r, joints] {
            return detail::column_set{
                {"energy", "work", "energy_balance", "limit_violations"},
                [sys, e0, r](double, const phase_state<dynamic>& x, const auto& st, double* out) {
                    out[0] = sys.energy(x);
                    out[1] = st.total_work();
                    out[2] = out[0] - e0 - out[1];
                    out[3] = limit_violations(*r, x.q);
                },
                joints};
        };
        problem pr = detail::make_problem(x0, 0.0, {});
        if (!forced) {
            pr.simulate = [sys, x0, columns](const step_options& o) {
                detail::check_general(o);
                return detail::simulate_general(general::stepper<robot>(sys, o.h, o.spec, o.newton),
                                                x0, columns());
            };
            return pr;
        }
        pd_controller<dynamic> pd;
        pd.kp = mat<dynamic>::Zero(n, n);
        pd.kd = mat<dynamic>::Zero(n, n);
        if (controlled) {
            pd.kp.diagonal() = each(l[0], "kp");
            pd.kd.diagonal() = each(l[1], "kd");
            arm::minimum_jerk ref{x0.q, l[2].empty() ? x0.q : each(l[2], "target"), v[2]};
            pd.reference = [ref](double t, vec<dynamic>& q, vec<dynamic>& rate) {
                ref(t, q, rate);
            };
            if (v[3] == 0.0) pd.compensate(lag);
        }
        expression_force tau = typed;
        if (!l[3].empty()) { // constant torques as expressions of their values (17 digits:
            std::vector<std::string> c, names; // the same doubles), over neutral names
            for (double x : l[3]) {
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
    };
    // Optimal control: the torques (forces) of the actuated joints, those whose URDF effort is
    // positive, with the URDF's joint damping; its effort and position limits are the bounds.
    m.controls = {"u [N m or N]: the torque (force) at each actuated joint (URDF effort > 0)"};
    m.simulation_only = {"move_time", "no_gravity_compensation", "kp", "kd", "target", "torque"};
    m.optimal = [r](std::span<const double> v, const lists&, const optimal::control_problem& p) {
        const auto actuated = actuated_joints(*r);
        if (actuated.empty())
            throw std::invalid_argument("no joint of " + r->name +
                                        " is actuated (its URDF effort is 0 for every joint): "
                                        "nothing to control");
        const int d = r->dof();
        optimal::matrix b = optimal::matrix::Zero(d, static_cast<Eigen::Index>(actuated.size()));
        optimal::matrix c = optimal::matrix::Zero(d, d);
        for (std::size_t j = 0; j < actuated.size(); ++j)
            b(actuated[j], static_cast<Eigen::Index>(j)) = 1.0;
        for (int i = 0; i < d && v[1] == 0.0; ++i)
            c(i, i) = r->bodies[static_cast<std::size_t>(i)].limits.damping;
        auto robot_at = std::make_shared<multibody::model>(*r);
        robot_at->gravity = multibody::vec3(0.0, 0.0, -v[0]);
        return std::unique_ptr<optimal::transcription>(
            optimal::transcribe_inputs(robot(robot_at), std::move(b), p, std::move(c)));
    };
    m.limits = [r](std::span<const double>, optimal::control_problem& p) {
        const auto actuated = actuated_joints(*r);
        const int d = r->dof(), inputs = static_cast<int>(actuated.size());
        const auto unbounded = [](const vec<dynamic>& lo, const vec<dynamic>& hi) {
            return (lo.array() == -optimal::unbounded).all() &&
                   (hi.array() == optimal::unbounded).all();
        };
        if (unbounded(p.control_lower, p.control_upper)) {
            p.control_lower.resize(inputs);
            p.control_upper.resize(inputs);
            for (int j = 0; j < inputs; ++j) {
                const double e =
                    r->bodies[static_cast<std::size_t>(actuated[static_cast<std::size_t>(j)])]
                        .limits.effort;
                p.control_lower(j) = -e;
                p.control_upper(j) = e;
            }
        }
        if (unbounded(p.position_lower, p.position_upper)) {
            p.position_lower.resize(d);
            p.position_upper.resize(d);
            for (int i = 0; i < d; ++i) {
                const auto& l = r->bodies[static_cast<std::size_t>(i)].limits;
                p.position_lower(i) = l.lower;
                p.position_upper(i) = l.upper;
            }
        }
        if (unbounded(p.velocity_lower, p.velocity_upper)) { // a velocity of 0: no limit
            p.velocity_lower.resize(d);
            p.velocity_upper.resize(d);
            for (int i = 0; i < d; ++i) {
                const double v = r->bodies[static_cast<std::size_t>(i)].limits.velocity;
                p.velocity_upper(i) = v > 0.0 ? v : optimal::unbounded;
                p.velocity_lower(i) = -p.velocity_upper(i);
            }
        }
    };
    return m;
}

std::vector<int> actuated_joints(const multibody::model& r) {
    std::vector<int> out;
    for (int i = 0; i < r.dof(); ++i)
        if (r.bodies[static_cast<std::size_t>(i)].limits.effort > 0.0) out.push_back(i);
    return out;
}

const model& robot_options() {
    static const model m = [] {
        auto one = std::make_shared<multibody::model>();
        one->name = "one joint";
        multibody::body b;
        b.name = "joint";
        b.link = "link";
        b.mass = 1.0;
        b.inertia = multibody::mat3::Identity();
        one->bodies.push_back(b);
        return robot_model(one);
    }();
    return m;
}

} // namespace varsym::models
