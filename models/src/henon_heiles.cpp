// models/src/henon_heiles.cpp: the Hénon–Heiles system (varsym/problems/henon_heiles.hpp), its
// initial p_x chosen from an energy.
#include <cmath>

#include "simulation_of.hpp"
#include "varsym/models/parameters.hpp"
#include "varsym/problems/henon_heiles.hpp"

namespace varsym::models::defs {

namespace {

struct henon_heiles_parameters {
    double energy; ///< NaN: p0 as given
};

} // namespace

model henon_heiles() {
    model m;
    m.name = "henon-heiles";
    m.summary = "Henon-Heiles: two coupled oscillators, ordered and chaotic orbits";
    m.description =
        "  L = (x'^2 + y'^2)/2 - V, V = (x^2 + y^2)/2 + x^2 y - y^3/3 (Henon and Heiles 1964;\n"
        "  dimensionless, unit mass, p = q'). Bounded below the escape energy 1/6. The energy E\n"
        "  sets p_x >= 0 from E at the initial q and p_y, replacing the first p0 value (a state\n"
        "  outside that energy surface is refused). Conserved: energy. No exact solution, no\n"
        "  period. The section x = 0 of an ensemble: vary q0_2 and p0_2 at a fixed energy.";
    m.dim = 2;
    m.coordinates = "x, y";
    const parameter_set<henon_heiles_parameters> set{{{&henon_heiles_parameters::energy,
                                                       {.name = "energy",
                                                        .value = 0.125,
                                                        .doc = "energy E, sets p_x >= 0",
                                                        .nan_means = "use p0 as given"}}}};
    set.declare(m);
    m.velocities = false;
    m.time = 200.0;
    m.steps = 4000;
    m.ensemble_time = 1000.0;
    m.ensemble_steps = 20000;
    m.make = set.make([](const henon_heiles_parameters& par, const start& s) {
        const auto sys = henon_heiles::make_system();
        vec<2> q{0.0, 0.1}, p{0.0, 0.0};
        if (!s.q0.empty()) q = vec<2>{s.q0[0], s.q0[1]};
        if (!s.p0.empty()) p = vec<2>{s.p0[0], s.p0[1]};
        if (const double energy = par.energy; std::isfinite(energy)) {
            const double px2 = 2.0 * (energy - henon_heiles::potential{}.value(q)) - p(1) * p(1);
            if (!(px2 >= 0.0))
                throw std::invalid_argument(
                    "the initial q and p_y lie outside the energy surface E = " +
                    std::to_string(energy));
            p(0) = std::sqrt(px2);
        }
        const phase_state<2> x0{q, p};
        return detail::make_problem(x0, 0.0, [=](const step_options& o) {
            return detail::simulate_family(
                sys, x0, o,
                detail::column_set{{"energy"},
                                   [sys](double, const auto& x, const auto&, double* out) {
                                       out[0] = sys.energy(x);
                                   }});
        });
    });
    return m;
}

} // namespace varsym::models::defs
