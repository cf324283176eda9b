// bench/bench_models.cpp: one step of the schemes on the models beyond the pendulum (Kepler,
// double pendulum, heavy top, the FPU chain at n = 10³, 10⁴, 10⁵), and the cost of one
// evaluation of a Lagrangian's first and second derivatives by automatic differentiation.
#include <benchmark/benchmark.h>

#include "bench_support.hpp"

#include "varsym/integrate.hpp"
#include "varsym/problems/chain.hpp"
#include "varsym/problems/double_pendulum.hpp"
#include "varsym/problems/heavy_top.hpp"
#include "varsym/problems/kepler.hpp"
#include "varsym/schemes/simpson.hpp"
#include "varsym/schemes/variational.hpp"

using namespace varsym;

namespace {

using bench::run_steps;

const kepler::orbit orbit(0.6, 1.0);
const double kepler_h = orbit.period() / 200;

void kepler_simpson_separable(benchmark::State& s) {
    run_steps(s, simpson::stepper(kepler::make_system(), kepler_h), orbit.at(0.0));
}
void kepler_simpson_general_ad(benchmark::State& s) {
    run_steps(
        s,
        general::stepper(lagrangian_system<kepler::lagrangian>({}), kepler_h, scheme_kind::simpson),
        orbit.at(0.0));
}
void kepler_gauss_general_ad(benchmark::State& s) {
    const int degree = static_cast<int>(s.range(0));
    run_steps(s,
              general::stepper(lagrangian_system<kepler::lagrangian>({}), kepler_h,
                               scheme_spec(scheme_kind::gauss, degree)),
              orbit.at(0.0));
}
void double_pendulum_simpson(benchmark::State& s) {
    run_steps(s, general::stepper(double_pendulum::make_system({}), 1e-3, scheme_kind::simpson),
              phase_state<2>{vec<2>{1.5, 1.5}, vec<2>::Zero()});
}
void heavy_top_simpson(benchmark::State& s) {
    const auto sys = heavy_top::make_system({});
    const vec<3> q{1.0, 0.0, 0.0};
    run_steps(s, general::stepper(sys, 0.01, scheme_kind::simpson),
              phase_state<3>{q, sys.momentum(q, vec<3>{0.0, 0.5, 8.0})});
}
/// Time per step should grow linearly with n: the Newton system is tridiagonal.
void chain_simpson(benchmark::State& s) {
    const chain::system sys(static_cast<int>(s.range(0)), 1.0);
    run_steps(s, simpson::stepper(sys, 0.1), sys.lowest_mode(1.0));
    s.counters["ns_per_mass"] =
        benchmark::Counter(static_cast<double>(s.iterations() * s.range(0)),
                           benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

/// Value, gradient and Hessian of L in (q, q̇) by nested AutoDiffScalar (the library's path).
template <class L>
void derivatives(benchmark::State& s, L l, vec<L::dim> q, vec<L::dim> v) {
    lagrangian_terms<L::dim> t;
    for (auto _ : s) {
        evaluate(l, q, v, t);
        benchmark::DoNotOptimize(t.lvv.data());
    }
}
void autodiff_double_pendulum(benchmark::State& s) {
    derivatives(s, double_pendulum::lagrangian{}, vec<2>{0.9, -0.2}, vec<2>{0.3, 0.1});
}
void autodiff_heavy_top(benchmark::State& s) {
    derivatives(s, heavy_top::lagrangian{}, vec<3>{1.0, 0.2, 0.3}, vec<3>{0.1, 0.5, 8.0});
}

} // namespace

BENCHMARK(kepler_simpson_separable);
BENCHMARK(kepler_simpson_general_ad);
BENCHMARK(kepler_gauss_general_ad)->DenseRange(2, 4);
BENCHMARK(double_pendulum_simpson);
BENCHMARK(heavy_top_simpson);
BENCHMARK(chain_simpson)->Arg(1000)->Arg(10000)->Arg(100000);
BENCHMARK(autodiff_double_pendulum);
BENCHMARK(autodiff_heavy_top);
