// models/src/arm.cpp: an n-link planar robot arm under joint PD control tracking a minimum-jerk
// move to a target, with joint damping (problems/arm.hpp), run by the general engine with forces.
// Its lists (masses, lengths, gains, target) have one value per link; the masses' count is n.
#include <string>

#include "simulation_of.hpp"
#include "varsym/models/parameters.hpp"
#include "varsym/optimal/input_system.hpp"
#include "varsym/problems/arm.hpp"

namespace varsym::models::defs {

namespace {

struct arm_parameters {
    double gravity, move_time, no_gravity_compensation;
    std::vector<double> masses, lengths, inertias, damping, kp, kd, target;
};

/// A list of one value per link: the one given (n values, else std::invalid_argument), or where
/// none is given the model's rule for it.
std::vector<double> per_link(const std::vector<double>& given, std::size_t n, const char* name,
                             std::vector<double> otherwise) {
    return given.empty() ? otherwise : sized(given, n, name, "link");
}

/// What a simulation and an optimisation share: the arm's L (n links, n the masses' count) and
/// its joints' viscous damping.
struct links {
    arm::lagrangian lagrangian;
    std::vector<double> damping;
};

/// The links from the lists (where none are given: lengths 1, 0.8, 0.6 for n = 3, inertias 0
/// each, damping 0.5 each), checked: std::invalid_argument where the lengths are missing for
/// n != 3 or a list has another count than n.
links links_of(const arm_parameters& p) {
    const std::size_t n = p.masses.size();
    if (p.lengths.empty() && n != 3)
        throw std::invalid_argument("give the lengths of the " + std::to_string(n) + " links");
    const std::vector<double> lengths = per_link(p.lengths, n, "lengths", {1.0, 0.8, 0.6});
    const std::vector<double> inertias = per_link(p.inertias, n, "inertias", {});
    std::vector<double> damping = per_link(p.damping, n, "damping", std::vector<double>(n, 0.5));
    return {arm::lagrangian(p.masses, lengths, p.gravity, inertias), std::move(damping)};
}

} // namespace

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
    list_parameter masses =
        positive("masses", {1, 1, 1}, "kg", "the links' end masses, one per link (n of them)");
    masses.sets_dimension = true;
    const parameter_set<arm_parameters> set{
        {{&arm_parameters::gravity,
          {.name = "gravity", .value = 9.81, .unit = "m/s^2", .doc = "gravity g", .lower = 0.0}},
         {&arm_parameters::move_time,
          {.name = "move_time",
           .value = 2.0,
           .unit = "s",
           .doc = "duration of the minimum-jerk move to the target",
           .lower = 0.0,
           .lower_open = true}},
         {&arm_parameters::no_gravity_compensation,
          {.name = "no_gravity_compensation",
           .value = 0.0,
           .doc = "leave gravity out of the controller",
           .lower = 0.0,
           .upper = 1.0,
           .flag = true}}},
        {{&arm_parameters::masses, masses},
         {&arm_parameters::lengths,
          positive("lengths", {}, "m", "the links' lengths (1, 0.8, 0.6 for n = 3)")},
         {&arm_parameters::inertias,
          non_negative("inertias", "kg m^2", "each link's rotational inertia (0 each)")},
         {&arm_parameters::damping,
          non_negative("damping", "N m s/rad", "viscous damping per joint (0.5 each)")},
         {&arm_parameters::kp,
          non_negative("kp", "N m/rad", "proportional gain per joint (100 each)")},
         {&arm_parameters::kd,
          non_negative("kd", "N m s/rad", "derivative gain per joint (40 each)")},
         {&arm_parameters::target,
          {.name = "target",
           .unit = "rad",
           .doc = "target joint angles (0.8, 0.5, 0.3 for n = 3, else 0.5 each)"}}}};
    set.declare(m);
    m.dimension =
        set.dimension([](const arm_parameters& p) { return static_cast<int>(p.masses.size()); });
    m.time = 5.0;
    m.steps = 5000;
    m.ensemble_time = 5.0;
    m.ensemble_steps = 1000;
    m.ensemble_note = "The settling of the move: --grid move_time=0.5:3:11.";
    m.make = set.make([](const arm_parameters& p, const start& s) {
        const auto n = p.masses.size();
        const int d = static_cast<int>(n);
        const links body = links_of(p);
        const arm::lagrangian& lag = body.lagrangian;
        arm::control c;
        c.damping = body.damping;
        c.kp = per_link(p.kp, n, "kp", std::vector<double>(n, 100.0));
        c.kd = per_link(p.kd, n, "kd", std::vector<double>(n, 40.0));
        c.gravity_compensation = p.no_gravity_compensation == 0.0;
        const std::vector<double> target =
            per_link(p.target, n, "target",
                     n == 3 ? std::vector<double>{0.8, 0.5, 0.3} : std::vector(n, 0.5));
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
        c.reference.duration = p.move_time;
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
    });
    // Optimal control: the joint torques tau (one per joint, on the joint angles phi = B th:
    // the generalized force B^T tau), with the joints' damping B^T C B; the controller's lists
    // and parameters are a simulation's only.
    m.drawing = set.drawing([](const arm_parameters& p) {
        links_of(p); // the model's own checks and messages (n != 3 needs the lengths)
        return planar_links_figure(per_link(p.lengths, p.masses.size(), "lengths", {1.0, 0.8, 0.6}),
                                   p.masses);
    });
    m.controls = {"tau_i [N m]: the torque at joint i (between links i-1 and i), i = 1 ... n"};
    m.simulation_only = {"move_time", "no_gravity_compensation", "kp", "kd", "target"};
    m.control = set.control([](const arm_parameters& p) {
        const links body = links_of(p);
        const int d = static_cast<int>(p.masses.size());
        const mat<dynamic> b = arm::joint_map(d);
        const vec<dynamic> c = Eigen::Map<const vec<dynamic>>(body.damping.data(), d);
        return std::make_shared<const optimal::input_system<arm::lagrangian>>(
            body.lagrangian, optimal::matrix(b.transpose()),
            optimal::matrix(b.transpose() * c.asDiagonal() * b));
    });
    return m;
}

} // namespace varsym::models::defs
