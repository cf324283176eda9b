// bench/bench_general.cpp: the general engine with automatic derivatives against the same engine
// with derivatives by hand, at d = 2 (Kepler, e = 0.6, 200 steps per orbit), d = 6 (a six-link
// pendulum, h = 0.01) and d = 18 (the outer solar system, 40 steps per Jupiter period), gauss-4,
// for Newton and for the simplified iteration (docs/autodiff.md). Ratios are quoted from one run.
#include <benchmark/benchmark.h>

#include "varsym/problems/kepler.hpp"
#include "varsym/problems/linked_pendulum.hpp"
#include "varsym/problems/solar_system.hpp"
#include "varsym/schemes/variational.hpp"

using namespace varsym;

namespace {

const scheme_spec gauss4{scheme_kind::gauss, 4};

newton_options iteration(benchmark::State& s) {
    newton_options o;
    o.iteration = s.range(0) == 0 ? iteration_kind::newton : iteration_kind::simplified;
    s.SetLabel(s.range(0) == 0 ? "newton" : "simplified");
    return o;
}

template <class L>
void run(benchmark::State& s, const lagrangian_system<L>& sys, double h, phase_state<L::dim> x0) {
    general::stepper<L> stepper(sys, h, gauss4, iteration(s));
    phase_state<L::dim> x = x0;
    long sweeps = 0;
    for (auto _ : s) {
        const newton_report r = stepper.step(x);
        if (!r.converged) s.SkipWithError("the step did not converge");
        sweeps += r.iterations;
        benchmark::DoNotOptimize(x.q.data());
    }
    s.counters["iterations"] =
        benchmark::Counter(static_cast<double>(sweeps), benchmark::Counter::kAvgIterations);
}

const kepler::orbit orbit(0.6, 1.0);
void kepler_ad(benchmark::State& s) {
    run(s, lagrangian_system<kepler::lagrangian>({}), orbit.period() / 200, orbit.at(0.0));
}
void kepler_hand(benchmark::State& s) {
    using lag = separable_lagrangian<kepler::system>;
    run(s, lagrangian_system<lag>({kepler::make_system()}), orbit.period() / 200, orbit.at(0.0));
}

const linked_pendulum::lagrangian<6> arm({1, 1, 1, 1, 1, 1}, {1, 1, 1, 1, 1, 1}, 9.81);
const phase_state<6> arm_x0{vec<6>{-0.5, -0.2, 0.1, 0.4, 0.7, 1.0}, vec<6>::Zero()};
void arm6_ad(benchmark::State& s) {
    run(s, lagrangian_system<linked_pendulum::automatic<6>>({arm}), 0.01, arm_x0);
}
void arm6_hand(benchmark::State& s) {
    run(s, lagrangian_system<linked_pendulum::lagrangian<6>>(arm), 0.01, arm_x0);
}

const double solar_h = solar_system::jupiter_period / 40;
void solar_ad(benchmark::State& s) {
    run(s, lagrangian_system<nbody::gravity_lagrangian<18>>(solar_system::lagrangian()), solar_h,
        solar_system::initial_state());
}
void solar_hand(benchmark::State& s) {
    using lag = separable_lagrangian<solar_system::system>;
    run(s, lagrangian_system<lag>({solar_system::make_system()}), solar_h,
        solar_system::initial_state());
}

} // namespace

BENCHMARK(kepler_ad)->Arg(0)->Arg(1);
BENCHMARK(kepler_hand)->Arg(0)->Arg(1);
BENCHMARK(arm6_ad)->Arg(0)->Arg(1);
BENCHMARK(arm6_hand)->Arg(0)->Arg(1);
BENCHMARK(solar_ad)->Arg(0)->Arg(1);
BENCHMARK(solar_hand)->Arg(0)->Arg(1);
