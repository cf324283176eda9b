// models/src/spring_pendulum.cpp: the elastic (spring) pendulum, a bob on a spring swinging in a
// vertical plane, in polar coordinates, run by the general engine: its mass matrix diag(m, m r²)
// depends on q. The radial and swinging motions exchange energy (resonantly near ω_r = 2 ω_θ).
#include <cmath>

#include "simulation_of.hpp"
#include "varsym/models/parameters.hpp"

namespace varsym::models::defs {

namespace {

struct spring_pendulum_parameters {
    double mass, stiffness, rest_length, gravity;
};

/// L(r, θ, ṙ, θ̇) = m/2 (ṙ² + r² θ̇²) − k/2 (r − l0)² + m g r cos θ, θ from the downward vertical.
struct spring_lagrangian {
    static constexpr int dim = 2;
    double m = 1.0, k = 40.0, l0 = 1.0, g = 9.81;

    template <class T>
    T operator()(const tvec<T, 2>& q, const tvec<T, 2>& v) const {
        using std::cos;
        const T stretch = q(0) - l0;
        return 0.5 * m * (v(0) * v(0) + q(0) * q(0) * v(1) * v(1)) - 0.5 * k * stretch * stretch +
               m * g * q(0) * cos(q(1));
    }
};

} // namespace

model spring_pendulum() {
    model m;
    m.name = "spring-pendulum";
    m.summary = "elastic pendulum: a bob on a spring in a vertical plane; M depends on q";
    m.description =
        "  L = m (r'^2 + r^2 th'^2)/2 - k (r - l0)^2/2 + m g r cos th; q = (r [m], th [rad] from\n"
        "  the downward vertical). At rest it hangs at r = l0 + m g/k; small motions have the\n"
        "  radial frequency sqrt(k/m) and the swinging one sqrt(g/(l0 + m g/k)), and exchange\n"
        "  energy near 2:1 resonance. Default start: stretched 0.1 m past rest and swung out\n"
        "  0.5 rad, at rest. Conserved: energy. No exact solution, no period.";
    m.dim = 2;
    m.coordinates = "r, th";
    const parameter_set<spring_pendulum_parameters> set{
        {{&spring_pendulum_parameters::mass,
          {.name = "mass",
           .value = 1.0,
           .unit = "kg",
           .doc = "mass m of the bob",
           .lower = 0.0,
           .lower_open = true}},
         {&spring_pendulum_parameters::stiffness,
          {.name = "stiffness",
           .value = 40.0,
           .unit = "N/m",
           .doc = "spring constant k",
           .lower = 0.0,
           .lower_open = true}},
         {&spring_pendulum_parameters::rest_length,
          {.name = "rest_length",
           .value = 1.0,
           .unit = "m",
           .doc = "the spring's unstretched length l0",
           .lower = 0.0,
           .lower_open = true}},
         {&spring_pendulum_parameters::gravity,
          {.name = "gravity", .value = 9.81, .unit = "m/s^2", .doc = "gravity g", .lower = 0.0}}}};
    set.declare(m);
    m.time = 20.0;
    m.steps = 4000;
    m.ensemble_time = 20.0;
    m.ensemble_steps = 4000;
    m.ensemble_note = "The bob passes under the pivot: --event 'q2'.";
    m.make = set.make([](const spring_pendulum_parameters& par, const start& s) {
        const spring_lagrangian l{par.mass, par.stiffness, par.rest_length, par.gravity};
        const lagrangian_system<spring_lagrangian> sys(l);
        const double hanging = par.rest_length + par.mass * par.gravity / par.stiffness;
        const phase_state<2> x0 =
            detail::general_start(sys, s, vec<2>{hanging + 0.1, 0.5}, vec<2>(vec<2>::Zero()));
        return detail::make_problem(x0, 0.0, [=](const step_options& o) {
            detail::check_general(o);
            return detail::simulate_general(
                general::stepper<spring_lagrangian>(sys, o.h, o.spec, o.newton), x0,
                detail::column_set{{"energy"},
                                   [sys](double, const auto& x, const auto&, double* out) {
                                       out[0] = sys.energy(x);
                                   }});
        });
    });
    return m;
}

} // namespace varsym::models::defs
