// models/src/kepler.cpp: the planar two-body problem from pericentre, exact through Kepler's
// equation (varsym/problems/kepler.hpp).
#include "varsym/problems/kepler.hpp"
#include "simulation_of.hpp"
#include "varsym/models/parameters.hpp"

namespace varsym::models::defs {

namespace {

struct kepler_parameters {
    double eccentricity, semi_major_axis, mu;
};

} // namespace

model kepler() {
    model m;
    m.name = "kepler";
    m.summary = "planar two-body problem from pericentre, exact orbit by Kepler's equation";
    m.description =
        "  L = |qdot|^2/2 + mu/|q| per unit reduced mass; q = (x, y) the relative position,\n"
        "  mu = G (m1 + m2). Starts at pericentre (a(1 - e), 0), counter-clockwise.\n"
        "  Conserved: energy -mu/(2a), angular_momentum x p_y - y p_x (exactly, by discrete\n"
        "  Noether). Exact solution: yes. Period: the orbital period 2 pi sqrt(a^3/mu).";
    m.dim = 2;
    m.coordinates = "x, y";
    const parameter_set<kepler_parameters> set{{{&kepler_parameters::eccentricity,
                                                 {.name = "eccentricity",
                                                  .value = 0.6,
                                                  .doc = "eccentricity e",
                                                  .lower = 0.0,
                                                  .upper = 1.0,
                                                  .upper_open = true}},
                                                {&kepler_parameters::semi_major_axis,
                                                 {.name = "semi_major_axis",
                                                  .value = 1.0,
                                                  .doc = "semi-major axis a",
                                                  .lower = 0.0,
                                                  .lower_open = true}},
                                                {&kepler_parameters::mu,
                                                 {.name = "mu",
                                                  .value = 1.0,
                                                  .doc = "gravitational parameter mu = G (m1 + m2)",
                                                  .lower = 0.0,
                                                  .lower_open = true}}}};
    set.declare(m);
    m.fixed_start = "it starts at pericentre: set the orbit with eccentricity and "
                    "semi_major_axis (--eccentricity, --semi-major-axis) instead of q0/p0/v0";
    m.steps_per_period = 200;
    m.ensemble_time = 10.0 * 2.0 * std::numbers::pi;
    m.ensemble_steps = 2000;
    m.make = set.make([](const kepler_parameters& par, const start&) {
        const kepler::orbit orbit(par.eccentricity, par.semi_major_axis, par.mu);
        const auto sys = kepler::make_system(par.mu);
        const phase_state<2> x0 = orbit.at(0.0);
        return detail::make_problem(x0, orbit.period(), [=](const step_options& o) {
            return detail::simulate_family(
                sys, x0, o,
                detail::column_set{{"energy", "angular_momentum", "q_1_exact", "q_2_exact",
                                    "p_1_exact", "p_2_exact"},
                                   [sys, orbit](double t, const auto& x, const auto&, double* out) {
                                       const phase_state<2> y{x.q, x.p};
                                       const auto ref = orbit.at(t);
                                       out[0] = sys.energy(x);
                                       out[1] = kepler::angular_momentum(y);
                                       out[2] = ref.q(0);
                                       out[3] = ref.q(1);
                                       out[4] = ref.p(0);
                                       out[5] = ref.p(1);
                                   }});
        });
    });
    return m;
}

} // namespace varsym::models::defs
