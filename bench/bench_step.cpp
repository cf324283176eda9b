// bench/bench_step.cpp: time of one step on the paper's pendulum (ω = 2π, q₀ = π/2, p₀ = 0,
// N = 50 steps per period): varsym's fast and paper-reference steppers, the Lobatto and Gauss
// family for s = 1 … 6, and Boost.Odeint's symplectic steppers of order 2 and 4 on the same
// problem, in one process.
#include <benchmark/benchmark.h>

#include <array>
#include <numbers>

// The umbrella header does not include the m4 stepper, and Boost 1.74's m4 header is not
// self-contained (it needs the umbrella's symplectic_nystroem_stepper_base first).
#include <boost/numeric/odeint.hpp>
#include <boost/numeric/odeint/stepper/symplectic_rkn_sb3a_m4_mclachlan.hpp>

#include "varsym/problems/pendulum.hpp"
#include "varsym/reference/paper_schemes.hpp"
#include "varsym/schemes/galerkin.hpp"
#include "varsym/schemes/newmark.hpp"
#include "varsym/schemes/simpson.hpp"

namespace {

using namespace varsym;
constexpr double omega = 2.0 * std::numbers::pi;
const double period = pendulum::exact_solution(1.0, omega, std::numbers::pi / 2, 0.0).period();
const double h = period / 50;

template <class Stepper>
void run_steps(benchmark::State& state, Stepper stepper) {
    phase_state<1> x{vec<1>{std::numbers::pi / 2}, vec<1>{0.0}};
    long iterations = 0;
    for (auto _ : state) {
        iterations += stepper.step(x).iterations;
        benchmark::DoNotOptimize(x);
    }
    state.counters["newton_its"] =
        benchmark::Counter(static_cast<double>(iterations), benchmark::Counter::kAvgIterations);
}

using pendulum_system = pendulum::system;

const pendulum_system sys = pendulum::make_system(1.0, omega);
void simpson_step(benchmark::State& s) {
    run_steps(s, simpson::stepper(sys, h));
}
void newmark_step(benchmark::State& s) {
    run_steps(s, newmark::stepper(sys, h));
}
void simpson_paper_step(benchmark::State& s) {
    run_steps(s, paper_reference::simpson_stepper(sys, h));
}
void newmark_paper_step(benchmark::State& s) {
    run_steps(s, paper_reference::newmark_stepper(sys, h));
}

// The family, degree s = state.range(0), at the same h.
void lobatto_step(benchmark::State& s) {
    run_steps(
        s, galerkin::stepper(sys, h, galerkin::rule_kind::lobatto, static_cast<int>(s.range(0))));
}
void gauss_step(benchmark::State& s) {
    run_steps(s,
              galerkin::stepper(sys, h, galerkin::rule_kind::gauss, static_cast<int>(s.range(0))));
}

// Boost.Odeint: q'' = −ω² sin q as (coordinate, momentum) with m = 1.
using odeint_state = std::array<double, 1>;
struct odeint_coordinate {
    void operator()(const odeint_state& p, odeint_state& dqdt) const { dqdt[0] = p[0]; }
};
struct odeint_momentum {
    void operator()(const odeint_state& q, odeint_state& dpdt) const {
        dpdt[0] = -omega * omega * std::sin(q[0]);
    }
};

template <class Stepper>
void odeint_steps(benchmark::State& state) {
    Stepper stepper;
    odeint_state q{std::numbers::pi / 2}, p{0.0};
    double t = 0;
    for (auto _ : state) {
        stepper.do_step(std::make_pair(odeint_coordinate(), odeint_momentum()),
                        std::make_pair(std::ref(q), std::ref(p)), t, h);
        t += h;
        benchmark::DoNotOptimize(q);
        benchmark::DoNotOptimize(p);
    }
}

namespace odeint = boost::numeric::odeint;
void odeint_sb3a_mclachlan_step(benchmark::State& s) {
    odeint_steps<odeint::symplectic_rkn_sb3a_mclachlan<odeint_state>>(s);
}
void odeint_sb3a_m4_mclachlan_step(benchmark::State& s) {
    odeint_steps<odeint::symplectic_rkn_sb3a_m4_mclachlan<odeint_state>>(s);
}

// velocity_verlet's system is the acceleration a(q, v), with state pairs (q, v).
void odeint_velocity_verlet_step(benchmark::State& state) {
    odeint::velocity_verlet<odeint_state> stepper;
    odeint_state q{std::numbers::pi / 2}, v{0.0};
    auto accel = [](const odeint_state& x, const odeint_state&, odeint_state& a, double) {
        a[0] = -omega * omega * std::sin(x[0]);
    };
    double t = 0;
    for (auto _ : state) {
        stepper.do_step(accel, std::make_pair(std::ref(q), std::ref(v)), t, h);
        t += h;
        benchmark::DoNotOptimize(q);
        benchmark::DoNotOptimize(v);
    }
}

} // namespace

BENCHMARK(simpson_step);
BENCHMARK(newmark_step);
BENCHMARK(simpson_paper_step);
BENCHMARK(newmark_paper_step);
BENCHMARK(lobatto_step)->DenseRange(1, 6);
BENCHMARK(gauss_step)->DenseRange(1, 6);
BENCHMARK(odeint_sb3a_mclachlan_step);
BENCHMARK(odeint_sb3a_m4_mclachlan_step);
BENCHMARK(odeint_velocity_verlet_step);
