// models/src/slider_crank.cpp: the slider-crank mechanism, a closed loop of one degree of freedom
// (problems/mechanisms.hpp), run by the general engine with its two loop constraints.
#include "constrained_of.hpp"
#include "varsym/models/parameters.hpp"

namespace varsym::models::defs {

using detail::crank_torque_parameter, detail::gravity_parameter, detail::positive_value,
    detail::project_parameter;

namespace {

struct slider_crank_parameters {
    double crank_length, rod_length, rod_mass, slider_mass, crank_inertia, gravity, torque, project;
};

} // namespace

model slider_crank() {
    const mechanisms::slider_crank p0;
    model m;
    m.name = "slider-crank";
    m.summary = "slider-crank mechanism, a closed loop of one degree of freedom";
    m.description =
        "  Crank OA (r, moment of inertia J about O) at th, uniform rod AB (l, m_rod) at phi,\n"
        "  slider B (m_slider) at x on the x axis; gravity g along -y. q = (th, phi, x) [rad,\n"
        "  rad, m]; constraints r cos th + l cos phi = x, r sin th + l sin phi = 0 (l > r).\n"
        "  q0: th alone (phi, x close the loop) or all three; v0: th' alone or all three.\n"
        "  Conserved: energy (with torque 0), else energy - work. No period.\n";
    m.description += detail::constrained_columns;
    m.dim = 3;
    m.coordinates = "th, phi, x";
    m.short_start = {1};
    m.short_start_doc = "1 (th alone)";
    const parameter_set<slider_crank_parameters> set{
        {{&slider_crank_parameters::crank_length,
          positive_value("crank_length", p0.r, "m", "crank length r", "lengths", 0)},
         {&slider_crank_parameters::rod_length,
          positive_value("rod_length", p0.l, "m", "rod length l (> r)", "lengths", 1)},
         {&slider_crank_parameters::rod_mass,
          positive_value("rod_mass", p0.m_rod, "kg", "rod mass m_rod", "masses", 0)},
         {&slider_crank_parameters::slider_mass,
          positive_value("slider_mass", p0.m_slider, "kg", "slider mass m_slider", "masses", 1)},
         {&slider_crank_parameters::crank_inertia,
          positive_value("crank_inertia", p0.j, "kg m^2",
                         "crank's moment of inertia J about its pivot", "inertias", 0)},
         {&slider_crank_parameters::gravity, gravity_parameter(p0.g)},
         {&slider_crank_parameters::torque, crank_torque_parameter()},
         {&slider_crank_parameters::project, project_parameter()}}};
    set.declare(m);
    m.time = 5.0;
    m.steps = 10000;
    m.ensemble_time = 5.0;
    m.ensemble_steps = 2000;
    m.ensemble_note = "The slider's stroke: --event 'q3 - 1.9' (x passes 1.9 m).";
    m.make = set.make([](const slider_crank_parameters& par, const start& s) {
        mechanisms::slider_crank p;
        p.r = par.crank_length, p.l = par.rod_length, p.m_rod = par.rod_mass;
        p.m_slider = par.slider_mass, p.j = par.crank_inertia, p.g = par.gravity;
        p.validate();
        const mechanisms::slider_crank_loop loop{p};
        const auto [q, qdot] = detail::loop_start(
            s, loop, [&](double th) { return p.assemble(th); }, 0.3, 10.0);
        const lagrangian_system<mechanisms::slider_crank_lagrangian> sys({p});
        return detail::constrained_problem(sys, loop, detail::crank_torque(par.torque),
                                           detail::state_of(sys, s, q, qdot), par.project != 0.0,
                                           detail::no_columns());
    });
    return m;
}

} // namespace varsym::models::defs
