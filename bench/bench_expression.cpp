// bench/bench_expression.cpp: one step for a Lagrangian given as an expression at run time
// (systems/expression_lagrangian.hpp: symbolic derivatives compiled to straight-line code, the
// general engine at run-time d) against the built-in model of the same system, in one run:
// the double pendulum (built in: the general engine, fixed d = 2, automatic derivatives) and
// Kepler (built in: the separable fast path `varsym run --model kepler` takes, and the general
// engine with automatic derivatives), the expression Kepler by the general engine and by the
// separable steppers that models::simulate_expression picks for it (expression_separable.hpp), at
// its fixed size 2 (as the models layer runs one to three coordinates) and at run-time size.
// Simpson (arg 0) and gauss-4 (arg 1); docs/python.md.
#include <benchmark/benchmark.h>

#include "bench_support.hpp"

#include "varsym/problems/double_pendulum.hpp"
#include "varsym/problems/kepler.hpp"
#include "varsym/schemes/variational.hpp"
#include "varsym/systems/expression_separable.hpp"

using namespace varsym;

namespace {

scheme_spec member(benchmark::State& s) {
    const scheme_spec spec =
        s.range(0) == 0 ? scheme_spec(scheme_kind::simpson) : scheme_spec(scheme_kind::gauss, 4);
    s.SetLabel(spec.label());
    return spec;
}

using bench::run_steps;

const expression_lagrangian double_pendulum_expression(
    "0.5*(m1+m2)*l1**2*th1_dot**2 + 0.5*m2*l2**2*th2_dot**2"
    " + m2*l1*l2*th1_dot*th2_dot*cos(th1-th2) + (m1+m2)*g*l1*cos(th1) + m2*g*l2*cos(th2)",
    {"th1", "th2"}, {{"m1", 1.0}, {"m2", 1.0}, {"l1", 1.0}, {"l2", 1.0}, {"g", 9.81}});
const phase_state<2> double_pendulum_start{vec<2>{1.5, 1.5}, vec<2>::Zero()};

void double_pendulum_builtin(benchmark::State& s) {
    general::stepper stepper(double_pendulum::make_system({}), 1e-3, member(s));
    run_steps(s, stepper, double_pendulum_start);
}
void double_pendulum_expression_step(benchmark::State& s) {
    general::stepper stepper(lagrangian_system<expression_lagrangian>(double_pendulum_expression),
                             1e-3, member(s));
    run_steps(s, stepper, phase_state<dynamic>{double_pendulum_start.q, double_pendulum_start.p});
}

const kepler::orbit orbit(0.6, 1.0);
const double kepler_h = orbit.period() / 200;

void kepler_builtin_separable(benchmark::State& s) {
    with_stepper(member(s), kepler::make_system(), kepler_h, {},
                 [&](auto& stepper) { run_steps(s, stepper, orbit.at(0.0)); });
}
void kepler_builtin_general(benchmark::State& s) {
    general::stepper stepper(lagrangian_system<kepler::lagrangian>({}), kepler_h, member(s));
    run_steps(s, stepper, orbit.at(0.0));
}
const expression_lagrangian kepler_l("0.5*(x_dot**2 + y_dot**2) + mu/sqrt(x**2 + y**2)", {"x", "y"},
                                     {{"mu", 1.0}});

void kepler_expression(benchmark::State& s) {
    general::stepper stepper(lagrangian_system<expression_lagrangian>(kepler_l), kepler_h,
                             member(s));
    const phase_state<2> x0 = orbit.at(0.0);
    run_steps(s, stepper, phase_state<dynamic>{x0.q, x0.p});
}
void kepler_expression_separable(benchmark::State& s) { // at d = 2, as simulate_expression runs it
    with_stepper(member(s), separable_system_of<2>(kepler_l), kepler_h, {},
                 [&](auto& stepper) { run_steps(s, stepper, orbit.at(0.0)); });
}
void kepler_expression_separable_dynamic(benchmark::State& s) { // d known at run time (d > 3)
    const phase_state<2> x0 = orbit.at(0.0);
    with_stepper(member(s), separable_system_of(kepler_l), kepler_h, {}, [&](auto& stepper) {
        run_steps(s, stepper, phase_state<dynamic>{x0.q, x0.p});
    });
}

} // namespace

BENCHMARK(double_pendulum_builtin)->Arg(0)->Arg(1);
BENCHMARK(double_pendulum_expression_step)->Arg(0)->Arg(1);
BENCHMARK(kepler_builtin_separable)->Arg(0)->Arg(1);
BENCHMARK(kepler_builtin_general)->Arg(0)->Arg(1);
BENCHMARK(kepler_expression)->Arg(0)->Arg(1);
BENCHMARK(kepler_expression_separable)->Arg(0)->Arg(1);
BENCHMARK(kepler_expression_separable_dynamic)->Arg(0)->Arg(1);
