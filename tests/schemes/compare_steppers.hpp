// tests/schemes/compare_steppers.hpp: running two steppers side by side from the same state, a
// resume that needs the stepper's history, and the paper's pendulum case that the scheme tests
// compare them on.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <numbers>

#include "varsym/problems/pendulum.hpp"
#include "varsym/run/state.hpp"

namespace varsym::test {

/// Largest max-norm difference in q and p over n steps of a and b from x0 (both must converge).
template <class A, class B, int D>
double max_difference(A a, B b, phase_state<D> x0, int n) {
    phase_state<D> x = x0, y = x0;
    double worst = 0;
    for (int j = 0; j < n; ++j) {
        EXPECT_TRUE(a.step(x).converged);
        EXPECT_TRUE(b.step(y).converged);
        worst = std::max({worst, (x.q - y.q).template lpNorm<Eigen::Infinity>(),
                          (x.p - y.p).template lpNorm<Eigen::Infinity>()});
    }
    return worst;
}

/// n steps of make() from x0 straight, or `cut` steps, the run_state restored into a new
/// stepper, and the rest: the same bits and Newton statistics with the saved history, and —
/// negative control — not without it. Returns the history saved at `cut`.
template <class Make, int D>
std::vector<double> expect_resume_needs_history(Make make, const phase_state<D>& x0, std::size_t n,
                                                std::size_t cut) {
    auto quiet = [](const auto&) {};
    auto straight = make();
    auto a = run_state<D>::start(x0);
    EXPECT_TRUE(integrate_from(straight, a, n, quiet));
    auto first = make();
    auto b = run_state<D>::start(x0);
    integrate_from(first, b, cut, quiet);
    for (bool with_history : {true, false}) {
        auto c = b;
        if (!with_history) c.history.clear();
        auto second = make();
        restore(second, c);
        integrate_from(second, c, n, quiet);
        const bool same = a.x.q == c.x.q && a.x.p == c.x.p &&
                          a.stats.newton_iterations == c.stats.newton_iterations;
        EXPECT_EQ(same, with_history) << (with_history ? "with" : "without") << " history";
    }
    return b.history;
}

/// The paper's pendulum (m = 1, ω = 2π, q₀ = π/2, p₀ = 0) at N = 50 steps per period.
inline const auto pendulum_sys = pendulum::make_system(1.0, 2 * std::numbers::pi);
inline const double paper_h =
    pendulum::exact_solution(1.0, 2 * std::numbers::pi, std::numbers::pi / 2, 0.0).period() / 50;
inline const phase_state<1> paper_x0{vec<1>{std::numbers::pi / 2}, vec<1>{0.0}};

} // namespace varsym::test
