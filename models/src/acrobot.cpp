// models/src/acrobot.cpp: the acrobot, a two-link planar arm actuated at the elbow only
// (Spong 1995; Tedrake, Underactuated Robotics, ch. 3). Run by the general engine with the
// elbow torque u as a generalized force on the relative angle q2 (systems/forcing.hpp).
//
// Units and conventions: q = (q1, q2) [rad]: link 1 from the downward vertical, link 2 relative
// to link 1. m1, m2 [kg] the links' masses, l1 [m] link 1's length, lc1, lc2 [m] the distances
// from each link's pivot to its centre of mass, I1, I2 [kg m^2] the moments of inertia about the
// centres of mass. With c2 = cos q2:
//   M11 = m1 lc1^2 + m2 (l1^2 + lc2^2 + 2 l1 lc2 c2) + I1 + I2,
//   M12 = m2 (lc2^2 + l1 lc2 c2) + I2,   M22 = m2 lc2^2 + I2,
//   V = -(m1 lc1 + m2 l1) g cos q1 - m2 lc2 g cos(q1 + q2),   L = q'^T M q' / 2 - V.
#include <cmath>

#include "simulation_of.hpp"
#include "varsym/models/parameters.hpp"
#include "varsym/optimal/input_system.hpp"

namespace varsym::models::defs {

namespace {

struct acrobot_lagrangian {
    static constexpr int dim = 2;
    double m1 = 1.0, m2 = 1.0, l1 = 1.0, lc1 = 0.5, lc2 = 0.5, i1 = 1.0 / 12.0, i2 = 1.0 / 12.0,
           g = 9.81;

    template <class T>
    T operator()(const tvec<T, 2>& q, const tvec<T, 2>& v) const {
        using std::cos;
        const T c2 = cos(q(1));
        const T m11 = m1 * lc1 * lc1 + m2 * (l1 * l1 + lc2 * lc2 + 2.0 * l1 * lc2 * c2) + i1 + i2;
        const T m12 = m2 * (lc2 * lc2 + l1 * lc2 * c2) + i2;
        const double m22 = m2 * lc2 * lc2 + i2;
        const T kinetic = 0.5 * m11 * v(0) * v(0) + m12 * v(0) * v(1) + 0.5 * m22 * v(1) * v(1);
        const T potential = -(m1 * lc1 + m2 * l1) * g * cos(q(0)) - m2 * lc2 * g * cos(q(0) + q(1));
        return kinetic - potential;
    }
};

/// The elbow torque u: the generalized force (0, u).
struct elbow_torque {
    static constexpr int dim = 2, controls = 1;
    template <class T>
    tvec<T, 2> operator()(const tvec<T, 2>&, const tvec<T, 2>&, double, const tvec<T, 1>& u) const {
        return tvec<T, 2>(T(0.0), u(0));
    }
};

struct acrobot_parameters {
    double m1, m2, l1, lc1, lc2, i1, i2, gravity, torque;
};

acrobot_lagrangian lagrangian(const acrobot_parameters& p) {
    return {p.m1, p.m2, p.l1, p.lc1, p.lc2, p.i1, p.i2, p.gravity};
}

} // namespace

model acrobot() {
    model m;
    m.name = "acrobot";
    m.summary = "acrobot: two-link arm driven by an elbow torque u only (underactuated)";
    m.description =
        "  L = q'^T M(q) q'/2 + (m1 lc1 + m2 l1) g cos q1 + m2 lc2 g cos(q1 + q2), torque u on\n"
        "  q2; M11 = m1 lc1^2 + m2 (l1^2 + lc2^2 + 2 l1 lc2 cos q2) + I1 + I2, M12 = m2 (lc2^2\n"
        "  + l1 lc2 cos q2) + I2, M22 = m2 lc2^2 + I2 (Spong 1995). q1 [rad] from the downward\n"
        "  vertical, q2 [rad] relative to link 1. Defaults: uniform links of 1 kg and 1 m.\n"
        "  Default start q0 (1, 0) at rest. Conserved: energy with u = 0, else E - W (work\n"
        "  column). No exact solution, no period.";
    m.dim = 2;
    m.coordinates = "q1, q2";
    const acrobot_lagrangian l0;
    auto positive = [](const char* name, double v, const char* unit, const char* doc) {
        return parameter{
            .name = name, .value = v, .unit = unit, .doc = doc, .lower = 0.0, .lower_open = true};
    };
    const parameter_set<acrobot_parameters> set{
        {{&acrobot_parameters::m1, positive("m1", l0.m1, "kg", "mass of link 1")},
         {&acrobot_parameters::m2, positive("m2", l0.m2, "kg", "mass of link 2")},
         {&acrobot_parameters::l1, positive("l1", l0.l1, "m", "length of link 1")},
         {&acrobot_parameters::lc1,
          positive("lc1", l0.lc1, "m", "pivot to centre of mass, link 1")},
         {&acrobot_parameters::lc2,
          positive("lc2", l0.lc2, "m", "elbow to centre of mass, link 2")},
         {&acrobot_parameters::i1,
          {.name = "I1",
           .value = l0.i1,
           .unit = "kg m^2",
           .doc = "link 1's moment of inertia about its centre of mass",
           .lower = 0.0}},
         {&acrobot_parameters::i2,
          {.name = "I2",
           .value = l0.i2,
           .unit = "kg m^2",
           .doc = "link 2's moment of inertia about its centre of mass",
           .lower = 0.0}},
         {&acrobot_parameters::gravity,
          {.name = "gravity", .value = l0.g, .unit = "m/s^2", .doc = "gravity g", .lower = 0.0}},
         {&acrobot_parameters::torque,
          {.name = "torque", .value = 0.0, .unit = "N m", .doc = "constant elbow torque u"}}}};
    set.declare(m);
    m.time = 10.0;
    m.steps = 10000;
    m.ensemble_time = 20.0;
    m.ensemble_steps = 10000;
    m.make = set.make([](const acrobot_parameters& p, const start& s) {
        using L = acrobot_lagrangian;
        const auto sys = lagrangian_system<L>(lagrangian(p));
        return detail::controlled_problem<L, elbow_torque>(
            sys, p.torque, detail::general_start(sys, s, vec<2>{1.0, 0.0}, vec<2>(vec<2>::Zero())));
    });
    m.pose = set.pose([](const acrobot_parameters& p, std::span<const double> q) {
        const double ex = p.l1 * std::sin(q[0]), ey = -p.l1 * std::cos(q[0]);
        const double l2 = 2.0 * p.lc2; // link 2 drawn uniform: twice lc2
        return std::vector<double>{
            0.0, 0.0, ex, ey, ex + l2 * std::sin(q[0] + q[1]), ey - l2 * std::cos(q[0] + q[1])};
    });
    m.controls = {"u [N m]: torque at the elbow, on q2"};
    m.simulation_only = {"torque"};
    m.control = set.control([](const acrobot_parameters& p) { // u on q2: f = (0, u)
        return std::make_shared<const optimal::input_system<acrobot_lagrangian>>(
            lagrangian(p), optimal::matrix{{0.0}, {1.0}});
    });
    return m;
}

} // namespace varsym::models::defs
