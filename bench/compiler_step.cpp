// bench/compiler_step.cpp: the hot loop users run, Simpson's step on the paper's pendulum
// (ω = 2π, q₀ = π/2, 50 steps a period), against Boost.Odeint's symplectic_rkn_sb3a_mclachlan
// at equal steps, in one process. Built by bench/compilers.sh with each compiler at the flags of
// a Release build; prints "simpson_ns odeint_ns" per step, the best of 7 blocks of 10⁶ steps.
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <numbers>

#include <boost/numeric/odeint.hpp>

#include "varsym/problems/pendulum.hpp"
#include "varsym/schemes/simpson.hpp"

namespace {

constexpr double omega = 2.0 * std::numbers::pi;
constexpr long steps = 1'000'000;

template <class F>
double best_ns_per_step(F&& block) {
    double best = 1e300;
    for (int k = 0; k < 7; ++k) {
        const auto t0 = std::chrono::steady_clock::now();
        block();
        const std::chrono::duration<double, std::nano> dt = std::chrono::steady_clock::now() - t0;
        best = std::min(best, dt.count() / steps);
    }
    return best;
}

using state = std::array<double, 1>;
struct coordinate {
    void operator()(const state& p, state& dqdt) const { dqdt[0] = p[0]; }
};
struct momentum {
    void operator()(const state& q, state& dpdt) const {
        dpdt[0] = -omega * omega * std::sin(q[0]);
    }
};

} // namespace

int main() {
    using namespace varsym;
    const auto sys = pendulum::make_system(1.0, omega);
    const double h = pendulum::exact_solution(1.0, omega, std::numbers::pi / 2, 0.0).period() / 50;
    double sink = 0.0;
    const double simpson_ns = best_ns_per_step([&] {
        simpson::stepper s(sys, h);
        phase_state<1> x{vec<1>{std::numbers::pi / 2}, vec<1>{0.0}};
        for (long j = 0; j < steps; ++j)
            (void)s.step(x);
        sink += x.q(0);
    });
    const double odeint_ns = best_ns_per_step([&] {
        boost::numeric::odeint::symplectic_rkn_sb3a_mclachlan<state> s;
        state q{std::numbers::pi / 2}, p{0.0};
        double t = 0.0;
        for (long j = 0; j < steps; ++j, t += h)
            s.do_step(std::make_pair(coordinate(), momentum()),
                      std::make_pair(std::ref(q), std::ref(p)), t, h);
        sink += q[0];
    });
    std::printf("%.2f %.2f\n", simpson_ns, odeint_ns);
    std::fprintf(stderr, "(final q sum %.17g)\n", sink); // keeps both loops
}
