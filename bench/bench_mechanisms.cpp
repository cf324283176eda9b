// bench/bench_mechanisms.cpp: one step of the mechanisms (docs/mechanisms.md): the n-link arm
// under joint PD control with damping (n = 2, 6, 20; run-time n, derivatives by hand, Newton)
// and the four-bar linkage (3 coordinates, 2 constraints, automatic derivatives, Newton on the
// saddle-point system), with Simpson and gauss-2. The counter `unknowns` is the size of the
// Newton system (s d for the arm, s (d + m) for the four-bar), whose LU is O(unknowns³).
#include <benchmark/benchmark.h>

#include "varsym/problems/arm.hpp"
#include "varsym/problems/mechanisms.hpp"
#include "varsym/schemes/constrained.hpp"

using namespace varsym;

namespace {

scheme_spec member(benchmark::State& s) {
    const scheme_spec spec =
        s.range(1) == 0 ? scheme_spec(scheme_kind::simpson) : scheme_spec(scheme_kind::gauss, 2);
    s.SetLabel(spec.label());
    return spec;
}

template <class Stepper, class State>
void time_steps(benchmark::State& s, Stepper& stepper, State x, double unknowns) {
    long sweeps = 0;
    for (auto _ : s) {
        const newton_report r = stepper.step(x);
        if (!r.converged) s.SkipWithError("the step did not converge");
        sweeps += r.iterations;
        benchmark::DoNotOptimize(x.q.data());
    }
    s.counters["iterations"] =
        benchmark::Counter(static_cast<double>(sweeps), benchmark::Counter::kAvgIterations);
    s.counters["unknowns"] = unknowns;
}

// The arm of n links of 1 kg and 1/n m (reach 1 m), moving from hanging to 0.5 rad per joint
// over 2 s; h = 1 ms.
void arm_step(benchmark::State& s) {
    const auto n = static_cast<std::size_t>(s.range(0));
    const scheme_spec spec = member(s);
    const arm::lagrangian l(std::vector<double>(n, 1.0),
                            std::vector<double>(n, 1.0 / static_cast<double>(n)), 9.81);
    arm::control c;
    c.kp.assign(n, 100.0);
    c.kd.assign(n, 40.0);
    c.damping.assign(n, 0.5);
    const int d = static_cast<int>(n);
    c.reference = {vec<dynamic>::Zero(d), vec<dynamic>::Constant(d, 0.5), 2.0};
    general::stepper<arm::lagrangian, arm::force> stepper(lagrangian_system<arm::lagrangian>(l),
                                                          arm::make_force(l, c), 1e-3, spec);
    time_steps(s, stepper, phase_state<dynamic>{vec<dynamic>::Zero(d), vec<dynamic>::Zero(d)},
               stepper.table().degree * d);
}

// The default four-bar turning at 2 rad/s from θ1 = π/3; h = 1 ms.
void four_bar_step(benchmark::State& s) {
    const scheme_spec spec = member(s);
    const mechanisms::four_bar p;
    const mechanisms::four_bar_loop loop{p};
    const lagrangian_system<mechanisms::four_bar_lagrangian> sys({p});
    general::constrained_stepper<mechanisms::four_bar_lagrangian, mechanisms::four_bar_loop> st(
        sys, loop, 1e-3, spec);
    const vec<3> q = p.assemble(1.0471975511965976);
    const vec<3> v = mechanisms::loop_rates(loop, q, 2.0);
    time_steps(s, st, phase_state<3>{q, sys.momentum(q, v)}, st.table().degree * 5);
}

} // namespace

BENCHMARK(arm_step)->ArgsProduct({{2, 6, 20}, {0, 1}})->Unit(benchmark::kMicrosecond);
BENCHMARK(four_bar_step)->ArgsProduct({{0}, {0, 1}})->Unit(benchmark::kMicrosecond);
