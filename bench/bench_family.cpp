// bench/bench_family.cpp: the family's run-time-degree stepper (galerkin::stepper, one compiled
// stepper for all 16 members) against the fixed-size members it replaced (bench/legacy, one
// compiled stepper per member), in one process, for s = 1 … 8 on the pendulum (d = 1, N = 50
// steps per period) and Kepler (d = 2, e = 0.6, 200 steps per orbit). Kepler also runs on the
// general engine with derivatives by hand (what the tool used for Kepler's family before).
// `iteration/…`: the run-time stepper's three iterations (Newton, simplified Newton, fixed
// point) on the pendulum, Kepler and the outer solar system (d = 18, 40 steps per Jupiter
// period, docs/library.md), which chose its default.
// Each benchmark reports ns per step and `step_diff`: the largest difference of (q, p) between
// the two implementations' steps from the same 200 states along a trajectory (one step each).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <numbers>
#include <string>
#include <utility>

#include "legacy/fixed_family.hpp"
#include "varsym/problems/kepler.hpp"
#include "varsym/problems/pendulum.hpp"
#include "varsym/problems/solar_system.hpp"
#include "varsym/schemes/galerkin.hpp"
#include "varsym/schemes/variational.hpp"

using namespace varsym;
using galerkin::rule_kind;

namespace {

const auto pendulum_sys = pendulum::make_system(1.0, 2 * std::numbers::pi);
const double pendulum_h =
    pendulum::exact_solution(1.0, 2 * std::numbers::pi, std::numbers::pi / 2, 0.0).period() / 50;
const phase_state<1> pendulum_x0{vec<1>{std::numbers::pi / 2}, vec<1>{0.0}};
const kepler::orbit orbit(0.6, 1.0);
const auto kepler_sys = kepler::make_system();
const double kepler_h = orbit.period() / 200;

template <class Stepper, int D>
void run_steps(benchmark::State& state, Stepper stepper, phase_state<D> x, double diff) {
    long iterations = 0;
    for (auto _ : state) {
        const auto rep = stepper.step(x);
        if (!rep.converged) state.SkipWithError("Newton failed");
        iterations += rep.iterations;
        benchmark::DoNotOptimize(x.q.data());
    }
    state.counters["newton_its"] =
        benchmark::Counter(static_cast<double>(iterations), benchmark::Counter::kAvgIterations);
    state.counters["step_diff"] = diff;
}

/// Largest difference between one step of `a` and one step of `b` from each of 200 states of
/// a trajectory of `a`.
template <class A, class B, int D>
double step_difference(A a, B b, phase_state<D> x) {
    double worst = 0;
    for (int j = 0; j < 200; ++j) {
        phase_state<D> ya = x, yb = x;
        a.step(ya);
        b.step(yb);
        worst = std::max({worst, (ya.q - yb.q).template lpNorm<Eigen::Infinity>(),
                          (ya.p - yb.p).template lpNorm<Eigen::Infinity>()});
        x = ya;
    }
    return worst;
}

template <class System, rule_kind Kind, int S, int D>
void register_member(const std::string& problem, const System& sys, double h,
                     const phase_state<D>& x0) {
    const std::string rule = Kind == rule_kind::lobatto ? "lobatto" : "gauss";
    const std::string name = problem + "/" + rule + "-" + std::to_string(S);
    auto legacy = [=] {
        return legacy::fixed_stepper<System, Kind, S>(sys, h, galerkin::tableau::make(Kind, S));
    };
    auto runtime = [=] { return galerkin::stepper<System>(sys, h, Kind, S); };
    const double diff = step_difference(legacy(), runtime(), x0);
    benchmark::RegisterBenchmark(("fixed_size/" + name).c_str(),
                                 [=](benchmark::State& st) { run_steps(st, legacy(), x0, diff); });
    benchmark::RegisterBenchmark(("run_time/" + name).c_str(),
                                 [=](benchmark::State& st) { run_steps(st, runtime(), x0, diff); });
    if constexpr (D == 2) {
        using lag = separable_lagrangian<System>;
        auto general = [=] {
            return general::stepper<lag>(
                lagrangian_system<lag>({sys}), h,
                scheme_spec(Kind == rule_kind::lobatto ? scheme_kind::lobatto : scheme_kind::gauss,
                            S));
        };
        const double gdiff = step_difference(general(), runtime(), x0);
        benchmark::RegisterBenchmark(
            ("general_by_hand/" + name).c_str(),
            [=](benchmark::State& st) { run_steps(st, general(), x0, gdiff); });
    }
}

template <class System, int D, int... S>
void register_family(const std::string& problem, const System& sys, double h,
                     const phase_state<D>& x0, std::integer_sequence<int, S...>) {
    (register_member<System, rule_kind::lobatto, S + 1>(problem, sys, h, x0), ...);
    (register_member<System, rule_kind::gauss, S + 1>(problem, sys, h, x0), ...);
}

/// The run-time stepper of one member with each iteration, from x0.
template <class System, int D>
void register_iterations(const std::string& problem, const System& sys, double h,
                         const phase_state<D>& x0, rule_kind kind, int degree) {
    const std::string member =
        (kind == rule_kind::lobatto ? "lobatto-" : "gauss-") + std::to_string(degree);
    for (const auto& [label, it] : {std::pair{"newton", iteration_kind::newton},
                                    std::pair{"simplified", iteration_kind::simplified},
                                    std::pair{"fixed-point", iteration_kind::fixed_point}}) {
        newton_options opt;
        opt.iteration = it;
        benchmark::RegisterBenchmark(
            ("iteration/" + problem + "/" + member + "/" + label).c_str(),
            [=](benchmark::State& st) {
                run_steps(st, galerkin::stepper<System>(sys, h, kind, degree, opt), x0, 0.0);
            });
    }
}

} // namespace

int main(int argc, char** argv) {
    for (const auto& [kind, degree] :
         {std::pair{rule_kind::gauss, 2}, std::pair{rule_kind::gauss, 4},
          std::pair{rule_kind::gauss, 6}, std::pair{rule_kind::lobatto, 3}}) {
        register_iterations("pendulum", pendulum_sys, pendulum_h, pendulum_x0, kind, degree);
        register_iterations("kepler", kepler_sys, kepler_h, orbit.at(0.0), kind, degree);
        register_iterations("solar", solar_system::make_system(), solar_system::jupiter_period / 40,
                            solar_system::initial_state(), kind, degree);
    }
    const auto degrees = std::make_integer_sequence<int, galerkin::max_degree>{};
    register_family("pendulum", pendulum_sys, pendulum_h, pendulum_x0, degrees);
    register_family("kepler", kepler_sys, kepler_h, orbit.at(0.0), degrees);
    benchmark::Initialize(&argc, argv);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
}
