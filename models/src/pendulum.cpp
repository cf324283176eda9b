// models/src/pendulum.cpp: the paper's nonlinear pendulum, with its exact solution by elliptic
// functions (varsym/problems/pendulum.hpp).
#include <numbers>
#include <optional>

#include "simulation_of.hpp"
#include "varsym/models/parameters.hpp"
#include "varsym/optimal/input_system.hpp"
#include "varsym/problems/pendulum.hpp"

namespace varsym::models::defs {

namespace {

/// The pendulum's L for the optimal control transcription (written for its scalar types).
struct pendulum_under_torque {
    static constexpr int dim = 1;
    double mass = 1.0, omega = 1.0;
    template <class T>
    T operator()(const tvec<T, 1>& q, const tvec<T, 1>& v) const {
        using std::cos;
        return 0.5 * mass * v(0) * v(0) - mass * omega * omega * (1.0 - cos(q(0)));
    }
};

struct pendulum_parameters {
    double mass, omega;
};

} // namespace

model pendulum() {
    model m;
    m.name = "pendulum";
    m.summary = "the paper's nonlinear pendulum, exact solution by elliptic functions";
    m.description =
        "  L = (m/2) qdot^2 - m omega^2 (1 - cos q); q [rad] from the downward vertical,\n"
        "  m the moment of inertia [kg m^2], omega the small-oscillation frequency [rad/s].\n"
        "  Conserved: energy. Exact solution: yes (q_exact, p_exact). Period: the nonlinear\n"
        "  period 4K(k^2)/omega (one revolution in rotation).";
    m.dim = 1;
    m.coordinates = "q";
    const parameter_set<pendulum_parameters> set{{{&pendulum_parameters::mass,
                                                   {.name = "mass",
                                                    .value = 1.0,
                                                    .unit = "kg m^2",
                                                    .doc = "moment of inertia m",
                                                    .lower = 0.0,
                                                    .lower_open = true}},
                                                  {&pendulum_parameters::omega,
                                                   {.name = "omega",
                                                    .value = 2.0 * std::numbers::pi,
                                                    .unit = "rad/s",
                                                    .doc = "small-oscillation angular frequency",
                                                    .lower = 0.0,
                                                    .lower_open = true}}}};
    set.declare(m);
    m.steps_per_period = 50;
    m.ensemble_time = 10.0;
    m.ensemble_steps = 500;
    m.make = set.make([](const pendulum_parameters& par, const start& s) {
        const double mass = par.mass, omega = par.omega;
        const double q0 = s.q0.empty() ? std::numbers::pi / 2 : s.q0[0];
        const double p0 = !s.p0.empty() ? s.p0[0] : !s.v0.empty() ? mass * s.v0[0] : 0.0;
        const pendulum::system sys = pendulum::make_system(mass, omega);
        const phase_state<1> x0{vec<1>{q0}, vec<1>{p0}};
        std::optional<pendulum::exact_solution> exact;
        std::string no_period;
        try {
            exact.emplace(mass, omega, q0, p0);
        } catch (const std::invalid_argument& e) { // on the separatrix: no period
            no_period = e.what();
        }
        problem pr =
            detail::make_problem(x0, exact ? exact->period() : 0.0, [=](const step_options& o) {
                return detail::simulate_family(
                    sys, x0, o,
                    detail::column_set{
                        {"energy", "q_exact", "p_exact"},
                        [sys, exact](double t, const phase_state<1>& x, const auto&, double* out) {
                            out[0] = sys.energy(x);
                            const double nan = std::numeric_limits<double>::quiet_NaN();
                            const phase_state<1> ref =
                                exact ? exact->at(t) : phase_state<1>{vec<1>{nan}, vec<1>{nan}};
                            out[1] = ref.q(0);
                            out[2] = ref.p(0);
                        }});
            });
        pr.no_period = no_period;
        return pr;
    });
    m.controls = {"u [N m]: torque at the pivot"};
    m.control = set.control([](const pendulum_parameters& par) {
        return std::make_shared<const optimal::input_system<pendulum_under_torque>>(
            pendulum_under_torque{par.mass, par.omega}, optimal::matrix{{1.0}});
    });
    return m;
}

} // namespace varsym::models::defs
