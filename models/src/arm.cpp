// models/src/arm.cpp: an n-link planar robot arm under joint PD control tracking a minimum-jerk
// move to a target, with joint damping (problems/arm.hpp), run by the general engine with forces.
// Its lists (masses, lengths, gains, target) have one value per link; the masses' count is n.
#include <string>

#include "simulation_of.hpp"
#include "varsym/optimal/input_system.hpp"
#include "varsym/problems/arm.hpp"

namespace varsym::models::defs {

model arm() {
    model m;
    m.name = "arm";
    m.summary = "n-link planar robot arm, joint PD control to a target, joint damping";
    m.description =
        "  Link i (from the base) has a point mass m_i at its end, length l_i and an optional\n"
        "  rotational inertia J_i; th_i [rad] is its absolute angle from the downward vertical\n"
        "  (q = th), joint angles phi_1 = th_1, phi_i = th_i - th_(i-1). Each joint's torque\n"
        "  tau = Kp (r - phi) + Kd (r' - phi') - c phi' (+ gravity compensation) tracks a\n"
        "  minimum-jerk move r(t) from the initial joint angles to the target over move_time.\n"
        "  Every list has one value per link; the masses' count is n (3 by default; other n\n"
        "  need the lengths). Default start: hanging (th = 0) at rest.\n"
        "  Columns: energy, work (of damping and controller since t = 0), energy_balance\n"
        "  (energy - E0 - work: the scheme's error), tracking_error (max |phi - r(t)|) [rad].\n"
        "  Not conserved: energy; balanced: energy - work. No period.";
    m.dim = 3;
    m.coordinates = "th_1 ... th_n";
    m.parameters = {
        {.name = "gravity", .value = 9.81, .unit = "m/s^2", .doc = "gravity g", .lower = 0.0},
        {.name = "move_time",
         .value = 2.0,
         .unit = "s",
         .doc = "duration of the minimum-jerk move to the target",
         .lower = 0.0,
         .lower_open = true},
        {.name = "no_gravity_compensation",
         .value = 0.0,
         .doc = "leave gravity out of the controller",
         .lower = 0.0,
         .upper = 1.0,
         .flag = true}};
    auto positive = [](const char* name, std::vector<double> v, const char* unit, const char* doc) {
        return list_parameter{.name = name,
                              .value = std::move(v),
                              .unit = unit,
                              .doc = doc,
                              .lower = 0.0,
                              .lower_open = true};
    };
    auto non_negative = [](const char* name, const char* unit, const char* doc) {
        return list_parameter{.name = name, .unit = unit, .doc = doc, .lower = 0.0};
    };
    m.lists = {
        positive("masses", {1, 1, 1}, "kg", "the links' end masses, one per link (n of them)"),
        positive("lengths", {}, "m", "the links' lengths (1, 0.8, 0.6 for n = 3)"),
        non_negative("inertias", "kg m^2", "each link's rotational inertia (0 each)"),
        non_negative("damping", "N m s/rad", "viscous damping per joint (0.5 each)"),
        non_negative("kp", "N m/rad", "proportional gain per joint (100 each)"),
        non_negative("kd", "N m s/rad", "derivative gain per joint (40 each)"),
        {.name = "target",
         .unit = "rad",
         .doc = "target joint angles (0.8, 0.5, 0.3 for n = 3, else 0.5 each)"}};
    m.lists[0].sets_dimension = true;
    m.dimension = [](std::span<const double>, const lists& l) {
        return l[0].empty() ? 3 : static_cast<int>(l[0].size());
    };
    m.time = 5.0;
    m.steps = 5000;
    m.ensemble_time = 5.0;
    m.ensemble_steps = 1000;
    m.ensemble_note = "The settling of the move: --grid move_time=0.5:3:11.";
    m.make = [](std::span<const double> v, const start& s, const lists& l) {
        const std::vector<double> masses = l[0].empty() ? std::vector<double>{1, 1, 1} : l[0];
        const auto n = masses.size();
        const int d = static_cast<int>(n);
        auto each = [n](const std::vector<double>& given, const char* name,
                        std::vector<double> fallback) {
            if (given.empty()) return fallback;
            if (given.size() != n)
                throw std::invalid_argument(std::string(name) + " needs " + std::to_string(n) +
                                            " values (one per link), got " +
                                            std::to_string(given.size()));
            return given;
        };
        if (l[1].empty() && n != 3)
            throw std::invalid_argument("give the lengths of the " + std::to_string(n) + " links");
        const std::vector<double> lengths = each(l[1], "lengths", {1.0, 0.8, 0.6});
        arm::control c;
        c.damping = each(l[3], "damping", std::vector<double>(n, 0.5));
        c.kp = each(l[4], "kp", std::vector<double>(n, 100.0));
        c.kd = each(l[5], "kd", std::vector<double>(n, 40.0));
        c.gravity_compensation = v[2] == 0.0;
        const std::vector<double> target =
            each(l[6], "target", n == 3 ? std::vector<double>{0.8, 0.5, 0.3} : std::vector(n, 0.5));
        const arm::lagrangian lag(masses, lengths, v[0], each(l[2], "inertias", {}));
        const lagrangian_system<arm::lagrangian> sys(lag);
        auto given = [d](const std::vector<double>& g) {
            return vec<dynamic>(Eigen::Map<const vec<dynamic>>(g.data(), d));
        };
        const vec<dynamic> q0 = s.q0.empty() ? vec<dynamic>::Zero(d) : given(s.q0);
        const vec<dynamic> v0 = s.v0.empty() ? vec<dynamic>::Zero(d) : given(s.v0);
        const vec<dynamic> p0 = s.p0.empty() ? vec<dynamic>(sys.momentum(q0, v0)) : given(s.p0);
        sys.check_regular(q0, sys.velocity(q0, p0));
        const mat<dynamic> b = arm::joint_map(d);
        c.reference.from = b * q0;
        c.reference.to = given(target);
        c.reference.duration = v[1];
        const arm::force f = arm::make_force(lag, c);
        const phase_state<dynamic> x0{q0, p0};
        const double e0 = sys.energy(x0);
        return detail::make_problem(x0, 0.0, [=](const step_options& o) {
            detail::check_general(o);
            return detail::simulate_general(
                general::stepper<arm::lagrangian, arm::force>(sys, f, o.h, o.spec, o.newton), x0,
                detail::column_set{{"energy", "work", "energy_balance", "tracking_error"},
                                   [sys, c, b, e0](double t, const phase_state<dynamic>& x,
                                                   const auto& st, double* out) {
                                       vec<dynamic> r, rate;
                                       c.reference(t, r, rate);
                                       const double e = sys.energy(x), w = st.total_work();
                                       out[0] = e;
                                       out[1] = w;
                                       out[2] = e - e0 - w;
                                       out[3] = (b * x.q - r).lpNorm<Eigen::Infinity>();
                                   }});
        });
    };
    // Optimal control: the joint torques tau (one per joint, on the joint angles phi = B th:
    // the generalized force B^T tau), with the joints' damping B^T C B; the controller's lists
    // and parameters are a simulation's only.
    m.controls = {"tau_i [N m]: the torque at joint i (between links i-1 and i), i = 1 ... n"};
    m.simulation_only = {"move_time", "no_gravity_compensation", "kp", "kd", "target"};
    m.optimal = [](std::span<const double> v, const lists& l, const optimal::control_problem& p) {
        const std::vector<double> masses = l[0].empty() ? std::vector<double>{1, 1, 1} : l[0];
        const auto n = masses.size();
        const int d = static_cast<int>(n);
        if (l[1].empty() && n != 3)
            throw std::invalid_argument("give the lengths of the " + std::to_string(n) + " links");
        for (std::size_t i : {1U, 2U, 3U})
            if (!l[i].empty() && l[i].size() != n)
                throw std::invalid_argument(std::string(i == 1   ? "lengths"
                                                        : i == 2 ? "inertias"
                                                                 : "damping") +
                                            " needs " + std::to_string(n) +
                                            " values (one per link), got " +
                                            std::to_string(l[i].size()));
        const std::vector<double> lengths =
            l[1].empty() ? std::vector<double>{1.0, 0.8, 0.6} : l[1];
        const std::vector<double> damping = l[3].empty() ? std::vector<double>(n, 0.5) : l[3];
        const arm::lagrangian lag(masses, lengths, v[0], l[2]);
        const mat<dynamic> b = arm::joint_map(d);
        const vec<dynamic> c = Eigen::Map<const vec<dynamic>>(damping.data(), d);
        return std::unique_ptr<optimal::transcription>(
            optimal::transcribe_inputs(lag, optimal::matrix(b.transpose()), p,
                                       optimal::matrix(b.transpose() * c.asDiagonal() * b)));
    };
    return m;
}

} // namespace varsym::models::defs
