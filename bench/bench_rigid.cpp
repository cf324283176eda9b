// bench/bench_rigid.cpp: the heavy top on SO(3) (Lie group integrator, orders 2, 4, 6) against
// the same top in Euler angles on the general engine (automatic derivatives; Newmark, Simpson,
// gauss-3), per step and at equal accuracy: for each method the fewest steps per nutation period
// that bring the error after 10 periods within 1e-6 (found before timing), then the time of
// those 10 periods. Two errors (the second argument): 0, θ against its closed form; 1, the
// whole attitude (the angle of R_refᵀR [rad]) against a fine reference on which the two
// formulations agree to 1e-11. Counters: steps_per_period, error, time_per_period.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>

#include "varsym/integrate.hpp"
#include "varsym/lie/lgvi.hpp"
#include "varsym/lie/symmetric_top.hpp"
#include "varsym/schemes/variational.hpp"

using namespace varsym;

namespace {

constexpr double target = 1e-6;
constexpr int periods = 10;

// The `top` and `heavy-top` models' default top and start.
const lie::rigid_body top(lie::vec3(1.0, 1.0, 0.5).asDiagonal().toDenseMatrix(), lie::vec3(0, 0, 1),
                          1.0);
lie::body_state start() {
    lie::body_state x;
    x.R = so3::from_euler(1.0, 0.0, 0.0);
    x.pi = top.inertia() * so3::body_rate(1.0, 0.0, 0.0, 0.5, 8.0);
    return x;
}
const heavy_top::nutation nutation = lie::nutation_of(top, start());
const double period = nutation.period();

/// The errors after `periods` periods: θ against the closed form, R against `reference`.
struct errors {
    double theta, attitude;
};
double angle(const lie::mat3& a, const lie::mat3& b) {
    const auto q = so3::quaternion(a.transpose() * b);
    return 2.0 * std::atan2(std::sqrt(q[1] * q[1] + q[2] * q[2] + q[3] * q[3]), q[0]);
}
lie::mat3 lgvi_end(int order, int n) {
    lie::lgvi s(top, period / n, order);
    lie::body_state x = start();
    for (int k = 0; k < n * periods; ++k)
        if (!s.step(x).converged) return lie::mat3::Constant(NAN);
    return x.R;
}
lie::mat3 euler_end(const scheme_spec& spec, int n) {
    const auto sys = heavy_top::make_system(lie::euler_lagrangian(top));
    general::stepper s(sys, period / n, spec);
    phase_state<3> x = lie::euler_state(start());
    for (int k = 0; k < n * periods; ++k)
        if (!s.step(x).converged) return lie::mat3::Constant(NAN);
    return so3::from_euler(x.q(0), x.q(1), x.q(2));
}
/// The reference attitude: the order-6 group integrator at 2000 steps per period, checked
/// against gauss-3 in Euler angles at 2000 steps per period.
const lie::mat3 reference = [] {
    const lie::mat3 a = lgvi_end(6, 2000), b = euler_end(scheme_spec(scheme_kind::gauss, 3), 2000);
    if (!(angle(a, b) < 1e-11)) throw std::runtime_error("the two references disagree");
    return a;
}();
errors errors_of(const lie::mat3& r) {
    const double theta = std::acos(std::clamp(r(2, 2), -1.0, 1.0));
    const double e = std::abs(theta - nutation.theta(periods * period));
    const double a = angle(reference, r);
    return {std::isfinite(e) ? e : INFINITY, std::isfinite(a) ? a : INFINITY};
}

/// The fewest steps per period whose error is within target: doubling, then bisection.
int steps_for(const std::function<double(int)>& error) {
    int hi = 8;
    while (!(error(hi) <= target))
        hi *= 2;
    int lo = hi / 2;
    while (hi - lo > 1) {
        const int mid = (lo + hi) / 2;
        (error(mid) <= target ? hi : lo) = mid;
    }
    return hi;
}

void report(benchmark::State& state, int n, double err) {
    state.counters["steps_per_period"] = n;
    state.counters["error"] = err;
    state.counters["time_per_period"] = benchmark::Counter(
        periods, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

/// Times `end(n)` at the fewest n meeting the target on metric `which` (0 θ, 1 attitude).
void equal_accuracy(benchmark::State& state, const std::function<lie::mat3(int)>& end) {
    const bool attitude = state.range(1) == 1;
    auto error = [&](int m) {
        const errors e = errors_of(end(m));
        return attitude ? e.attitude : e.theta;
    };
    const int n = steps_for(error);
    lie::mat3 r;
    for (auto _ : state)
        benchmark::DoNotOptimize(r = end(n));
    report(state, n, error(n));
}

void top_lgvi_equal_accuracy(benchmark::State& state) {
    const int order = static_cast<int>(state.range(0));
    state.SetLabel(state.range(1) == 1 ? "attitude" : "theta");
    equal_accuracy(state, [order](int m) { return lgvi_end(order, m); });
}

void top_euler_equal_accuracy(benchmark::State& state) {
    const scheme_spec spec = state.range(0) == 0   ? scheme_spec(scheme_kind::newmark)
                             : state.range(0) == 1 ? scheme_spec(scheme_kind::simpson)
                                                   : scheme_spec(scheme_kind::gauss, 3);
    state.SetLabel(spec.label() + (state.range(1) == 1 ? ", attitude" : ", theta"));
    equal_accuracy(state, [spec](int m) { return euler_end(spec, m); });
}

/// One step at h = T/100 (the `top` model's default).
void top_lgvi_step(benchmark::State& state) {
    lie::lgvi s(top, period / 100, static_cast<int>(state.range(0)));
    lie::body_state x = start();
    for (auto _ : state) {
        if (!s.step(x).converged) state.SkipWithError("Newton failed");
        benchmark::DoNotOptimize(x.R.data());
    }
    state.SetItemsProcessed(state.iterations());
}
void top_euler_simpson_step(benchmark::State& state) {
    const auto sys = heavy_top::make_system(lie::euler_lagrangian(top));
    general::stepper s(sys, period / 100, scheme_kind::simpson);
    phase_state<3> x = lie::euler_state(start());
    for (auto _ : state) {
        if (!s.step(x).converged) state.SkipWithError("Newton failed");
        benchmark::DoNotOptimize(x.q.data());
    }
    state.SetItemsProcessed(state.iterations());
}

} // namespace

BENCHMARK(top_lgvi_step)->Arg(2)->Arg(4)->Arg(6);
BENCHMARK(top_euler_simpson_step);
BENCHMARK(top_lgvi_equal_accuracy)->ArgsProduct({{2, 4, 6}, {0, 1}})->Unit(benchmark::kMicrosecond);
BENCHMARK(top_euler_equal_accuracy)
    ->ArgsProduct({{0, 1, 2}, {0, 1}})
    ->Unit(benchmark::kMicrosecond);
