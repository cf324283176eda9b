// models/src/double_pendulum.cpp: the planar double pendulum with optional joint springs
// (varsym/problems/double_pendulum.hpp), run by the general engine: its mass matrix depends on q.
#include <numbers>

#include "simulation_of.hpp"
#include "varsym/models/parameters.hpp"
#include "varsym/problems/double_pendulum.hpp"

namespace varsym::models::defs {

namespace {

struct double_pendulum_parameters {
    double m1, m2, l1, l2, g, k;
};

} // namespace

model double_pendulum() {
    model m;
    m.name = "double-pendulum";
    m.summary = "two-link arm (double pendulum) with optional joint springs; M depends on q";
    m.description =
        "  L = (m1+m2) l1^2 th1'^2/2 + m2 l2^2 th2'^2/2 + m2 l1 l2 th1' th2' cos(th1 - th2)\n"
        "      + (m1+m2) g l1 cos th1 + m2 g l2 cos th2 - k (th1^2 + (th2 - th1)^2)/2\n"
        "  q = (th1, th2) [rad] from the downward vertical; p = dL/dqdot. Default start: both\n"
        "  links horizontal at rest, a chaotic energy. Conserved: energy. No exact solution, no\n"
        "  period. A flip of the second link in an ensemble: --event 'q2^2 - pi^2'.";
    m.dim = 2;
    m.coordinates = "th1, th2";
    const double_pendulum::lagrangian l0;
    const parameter_set<double_pendulum_parameters> set{{{&double_pendulum_parameters::m1,
                                                          {.name = "m1",
                                                           .value = l0.m1,
                                                           .unit = "kg",
                                                           .doc = "mass at the end of link 1",
                                                           .lower = 0.0,
                                                           .lower_open = true,
                                                           .option = "masses",
                                                           .option_index = 0}},
                                                         {&double_pendulum_parameters::m2,
                                                          {.name = "m2",
                                                           .value = l0.m2,
                                                           .unit = "kg",
                                                           .doc = "mass at the end of link 2",
                                                           .lower = 0.0,
                                                           .lower_open = true,
                                                           .option = "masses",
                                                           .option_index = 1}},
                                                         {&double_pendulum_parameters::l1,
                                                          {.name = "l1",
                                                           .value = l0.l1,
                                                           .unit = "m",
                                                           .doc = "length of link 1",
                                                           .lower = 0.0,
                                                           .lower_open = true,
                                                           .option = "lengths",
                                                           .option_index = 0}},
                                                         {&double_pendulum_parameters::l2,
                                                          {.name = "l2",
                                                           .value = l0.l2,
                                                           .unit = "m",
                                                           .doc = "length of link 2",
                                                           .lower = 0.0,
                                                           .lower_open = true,
                                                           .option = "lengths",
                                                           .option_index = 1}},
                                                         {&double_pendulum_parameters::g,
                                                          {.name = "g",
                                                           .value = l0.g,
                                                           .unit = "m/s^2",
                                                           .doc = "gravity",
                                                           .lower = 0.0,
                                                           .option = "gravity"}},
                                                         {&double_pendulum_parameters::k,
                                                          {.name = "k",
                                                           .value = l0.k,
                                                           .unit = "N m/rad",
                                                           .doc = "joint spring stiffness",
                                                           .lower = 0.0,
                                                           .option = "joint-stiffness"}}}};
    set.declare(m);
    m.time = 10.0;
    m.steps = 10000;
    m.ensemble_time = 20.0;
    m.ensemble_steps = 10000;
    m.make = set.make([](const double_pendulum_parameters& par, const start& s) {
        using L = double_pendulum::lagrangian;
        const auto sys =
            double_pendulum::make_system(L{par.m1, par.m2, par.l1, par.l2, par.g, par.k});
        const double half_pi = std::numbers::pi / 2;
        const phase_state<2> x0 =
            detail::general_start(sys, s, vec<2>{half_pi, half_pi}, vec<2>(vec<2>::Zero()));
        return detail::make_problem(x0, 0.0, [=](const step_options& o) {
            detail::check_general(o);
            return detail::simulate_general(
                general::stepper<L>(sys, o.h, o.spec, o.newton), x0,
                detail::column_set{{"energy"},
                                   [sys](double, const auto& x, const auto&, double* out) {
                                       out[0] = sys.energy(x);
                                   }});
        });
    });
    m.drawing = set.drawing([](const double_pendulum_parameters& par) {
        return planar_links_figure({par.l1, par.l2}, {par.m1, par.m2});
    });
    return m;
}

} // namespace varsym::models::defs
