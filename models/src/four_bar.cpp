// models/src/four_bar.cpp: the planar four-bar linkage, a closed loop of one degree of freedom
// (problems/mechanisms.hpp), run by the general engine with its two loop constraints.
#include <numbers>

#include "constrained_of.hpp"

namespace varsym::models::defs {

using detail::crank_torque_parameter, detail::gravity_parameter, detail::positive_value,
    detail::project_parameter;

model four_bar() {
    const mechanisms::four_bar p0;
    model m;
    m.name = "four-bar";
    m.summary = "planar four-bar linkage, a closed loop of one degree of freedom";
    m.description =
        "  Crank AB (a, m1) turns about A = (0,0), rocker DC (c, m3) about D = (d,0), coupler BC\n"
        "  (b, m2) closes the loop; uniform bars, gravity g along -y. q = (th1, th2, th3) [rad],\n"
        "  the bars' angles from +x; constraints A + a e(th1) + b e(th2) = D + c e(th3).\n"
        "  The defaults are a crank-rocker. q0: th1 alone (th2, th3 close the loop) or all\n"
        "  three; v0: th1' alone (the others from the loop) or all three. Conserved: energy\n"
        "  (with torque 0), else energy - work. No period.\n";
    m.description += detail::constrained_columns;
    m.dim = 3;
    m.coordinates = "th1, th2, th3";
    m.short_start = {1};
    m.short_start_doc = "1 (th1 alone)";
    m.parameters = {
        positive_value("crank_length", p0.a, "m", "crank length a", "lengths", 0),
        positive_value("coupler_length", p0.b, "m", "coupler length b", "lengths", 1),
        positive_value("rocker_length", p0.c, "m", "rocker length c", "lengths", 2),
        positive_value("ground_length", p0.ground, "m", "ground length d", "lengths", 3),
        positive_value("crank_mass", p0.m1, "kg", "crank mass m1", "masses", 0),
        positive_value("coupler_mass", p0.m2, "kg", "coupler mass m2", "masses", 1),
        positive_value("rocker_mass", p0.m3, "kg", "rocker mass m3", "masses", 2),
        gravity_parameter(p0.g),
        crank_torque_parameter(),
        project_parameter()};
    m.time = 10.0;
    m.steps = 10000;
    m.ensemble_time = 10.0;
    m.ensemble_steps = 2000;
    m.ensemble_note = "The crank's turns: --event 'q1 - 6.2832' (th1 passes 2 pi).";
    m.make = [](std::span<const double> v, const start& s, const lists&) {
        mechanisms::four_bar p;
        p.a = v[0], p.b = v[1], p.c = v[2], p.ground = v[3];
        p.m1 = v[4], p.m2 = v[5], p.m3 = v[6], p.g = v[7];
        p.validate();
        const mechanisms::four_bar_loop loop{p};
        const auto [q, qdot] = detail::loop_start(
            s, loop, [&](double th) { return p.assemble(th); }, std::numbers::pi / 3, 2.0);
        const lagrangian_system<mechanisms::four_bar_lagrangian> sys({p});
        return detail::constrained_problem(sys, loop, detail::crank_torque(v[8]),
                                           detail::state_of(sys, s, q, qdot), v[9] != 0.0,
                                           detail::no_columns());
    };
    return m;
}

} // namespace varsym::models::defs
