// bench/bench_support.hpp: what several benchmark files share.
#pragma once

#include <benchmark/benchmark.h>

namespace varsym::bench {

/// Times one step of `stepper` from x per iteration (x advancing), and counts the steps as
/// items; a step that does not converge ends the case with an error.
template <class Stepper, class State>
void run_steps(benchmark::State& state, Stepper&& stepper, State x) {
    for (auto _ : state) {
        if (!stepper.step(x).converged) state.SkipWithError("Newton failed");
        benchmark::DoNotOptimize(x.q.data());
    }
    state.SetItemsProcessed(state.iterations());
}

} // namespace varsym::bench
