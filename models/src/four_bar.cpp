// models/src/four_bar.cpp: the planar four-bar linkage, a closed loop of one degree of freedom
// (problems/mechanisms.hpp), run by the general engine with its two loop constraints.
#include <numbers>

#include "constrained_of.hpp"
#include "varsym/models/parameters.hpp"

namespace varsym::models::defs {

using detail::crank_torque_parameter, detail::gravity_parameter, detail::positive_value,
    detail::project_parameter;

namespace {

struct four_bar_parameters {
    double crank_length, coupler_length, rocker_length, ground_length;
    double crank_mass, coupler_mass, rocker_mass, gravity, torque, project;
};

} // namespace

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
    const parameter_set<four_bar_parameters> set{
        {{&four_bar_parameters::crank_length,
          positive_value("crank_length", p0.a, "m", "crank length a", "lengths", 0)},
         {&four_bar_parameters::coupler_length,
          positive_value("coupler_length", p0.b, "m", "coupler length b", "lengths", 1)},
         {&four_bar_parameters::rocker_length,
          positive_value("rocker_length", p0.c, "m", "rocker length c", "lengths", 2)},
         {&four_bar_parameters::ground_length,
          positive_value("ground_length", p0.ground, "m", "ground length d", "lengths", 3)},
         {&four_bar_parameters::crank_mass,
          positive_value("crank_mass", p0.m1, "kg", "crank mass m1", "masses", 0)},
         {&four_bar_parameters::coupler_mass,
          positive_value("coupler_mass", p0.m2, "kg", "coupler mass m2", "masses", 1)},
         {&four_bar_parameters::rocker_mass,
          positive_value("rocker_mass", p0.m3, "kg", "rocker mass m3", "masses", 2)},
         {&four_bar_parameters::gravity, gravity_parameter(p0.g)},
         {&four_bar_parameters::torque, crank_torque_parameter()},
         {&four_bar_parameters::project, project_parameter()}}};
    set.declare(m);
    m.time = 10.0;
    m.steps = 10000;
    m.ensemble_time = 10.0;
    m.ensemble_steps = 2000;
    m.ensemble_note = "The crank's turns: --event 'q1 - 6.2832' (th1 passes 2 pi).";
    m.make = set.make([](const four_bar_parameters& par, const start& s) {
        mechanisms::four_bar p;
        p.a = par.crank_length, p.b = par.coupler_length, p.c = par.rocker_length;
        p.ground = par.ground_length;
        p.m1 = par.crank_mass, p.m2 = par.coupler_mass, p.m3 = par.rocker_mass;
        p.g = par.gravity;
        p.validate();
        const mechanisms::four_bar_loop loop{p};
        const auto [q, qdot] = detail::loop_start(
            s, loop, [&](double th) { return p.assemble(th); }, std::numbers::pi / 3, 2.0);
        const lagrangian_system<mechanisms::four_bar_lagrangian> sys({p});
        return detail::constrained_problem(sys, loop, detail::crank_torque(par.torque),
                                           detail::state_of(sys, s, q, qdot), par.project != 0.0,
                                           detail::no_columns());
    });
    return m;
}

} // namespace varsym::models::defs
