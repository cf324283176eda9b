// bench/soak.cpp: the long-run soak of `make soak` (not part of `make test`): 10⁸ Simpson steps
// of the paper's pendulum at N = 50 and N = 2000 steps per period, each with and without
// compensated summation of the increments. Reports the largest relative energy error in each tenth
// of the run (bounded and flat means no drift), the time, and the peak resident memory.
#include <sys/resource.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>

#include "varsym/integrate.hpp"
#include "varsym/problems/pendulum.hpp"
#include "varsym/schemes/simpson.hpp"

using namespace varsym;

namespace {

template <class Stepper>
std::array<double, 10> soak(Stepper stepper, const pendulum::system& sys, std::size_t n,
                            double& seconds) {
    phase_state<1> x{vec<1>{std::numbers::pi / 2}, vec<1>{0.0}};
    const double e0 = sys.energy(x);
    std::array<double, 10> worst{};
    const std::size_t tenth = std::max<std::size_t>(n / 10, 1);
    const auto start = std::chrono::steady_clock::now();
    integrate(stepper, x, 0.0, n, [&](std::size_t j, double, const phase_state<1>& y) {
        const std::size_t w = std::min<std::size_t>(j == 0 ? 0 : (j - 1) / tenth, 9);
        worst[w] = std::max(worst[w], std::abs(sys.energy(y) - e0) / e0);
    });
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return worst;
}

void report(const char* name, const std::array<double, 10>& worst, double seconds) {
    std::printf("%-24s", name);
    for (double w : worst)
        std::printf(" %.3e", w);
    std::printf("   last/first %.3f   %.1f s\n", worst[9] / worst[0], seconds);
}

} // namespace

int main(int argc, char** argv) {
    const std::size_t n = argc > 1 ? std::strtoull(argv[1], nullptr, 10) : 100'000'000ULL;
    const auto sys = pendulum::make_system(1.0, 2 * std::numbers::pi);
    const double period =
        pendulum::exact_solution(1.0, 2 * std::numbers::pi, std::numbers::pi / 2, 0.0).period();
    bool ok = true;
    // N = 50: the paper's step, truncation error ~1e-6 dominates; N = 2000: truncation error
    // ~3e-13, so round-off in the accumulated q and p is what the energy error shows.
    for (int steps_per_period : {50, 2000}) {
        const double h = period / steps_per_period;
        std::printf("%zu Simpson steps of the paper's pendulum, N = %d (%.3g periods).\n"
                    "Max relative energy error in each tenth of the run:\n",
                    n, steps_per_period, static_cast<double>(n) / steps_per_period);
        double s1 = 0, s2 = 0;
        const auto compensated = soak(simpson::stepper(sys, h), sys, n, s1);
        report("compensated summation", compensated, s1);
        const auto plain =
            soak(simpson::stepper<pendulum::system, plain_update<1>>(sys, h), sys, n, s2);
        report("plain summation", plain, s2);
        // Bounded, no drift: the last tenth's largest error within 10 % of the first tenth's
        // (the maxima rise a little as the sampled phases fill the period).
        if (steps_per_period == 50) ok = compensated[9] <= 1.1 * compensated[0];
    }
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    std::printf("peak resident memory: %.1f MB\n", static_cast<double>(usage.ru_maxrss) / 1024.0);
    std::printf(ok ? "OK: energy error bounded, no drift at N = 50\n"
                   : "DRIFT: energy error grows at N = 50\n");
    return ok ? 0 : 1;
}
