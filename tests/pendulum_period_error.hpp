// tests/pendulum_period_error.hpp: the error of a stepper over one period of the paper's pendulum
// (m = 1, ω = 2π, q₀ = π/2, p₀ = 0): max |q_j − q(t_j)| over its steps, against the exact
// solution in long double at t_j = j h (so the reference adds nothing at the 1e-15 level).
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

#include "varsym/integrate.hpp"
#include "varsym/problems/pendulum.hpp"

namespace varsym::test {

/// The exact solution in long double, whose period sets h = T / n.
inline const pendulum::basic_exact_solution<long double>& paper_pendulum_exact() {
    static const pendulum::basic_exact_solution<long double> exact(
        1, 2 * std::numbers::pi_v<long double>, std::numbers::pi_v<long double> / 2, 0);
    return exact;
}

/// n steps of `stepper` (whose step must be T / n) from the paper's initial state.
template <class Stepper>
double period_error(Stepper& stepper, int n) {
    using LD = long double;
    const auto& exact = paper_pendulum_exact();
    const double h = stepper.step_size();
    phase_state<1> x{vec<1>{std::numbers::pi / 2}, vec<1>{0.0}};
    LD worst = 0;
    integrate(stepper, x, 0.0, static_cast<std::size_t>(n),
              [&](std::size_t j, double, const phase_state<1>& y) {
                  const auto e = exact.state(static_cast<LD>(j) * static_cast<LD>(h));
                  worst = std::max(worst, std::abs(static_cast<LD>(y.q(0)) - e.q));
              });
    return static_cast<double>(worst);
}

} // namespace varsym::test
