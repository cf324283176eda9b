// varsym/problems/paper.hpp: the experiments of Dubois & Rojas-Quintero (2023), shared by the
// `varsym paper` command, the tests and the examples.
#pragma once

#include <array>
#include <numbers>
#include <string_view>
#include <vector>

#include "varsym/diagnostics/convergence.hpp"
#include "varsym/diagnostics/error_norms.hpp"
#include "varsym/problems/pendulum.hpp"
#include "varsym/schemes/scheme_kind.hpp"

namespace varsym::paper {

/// The paper's pendulum (§2, Figure 1): m = 1, ω = 2π, q(0) = π/2, p(0) = 0.
struct pendulum_case {
    double mass = 1.0;
    double omega = 2.0 * std::numbers::pi;
    double q0 = 0.5 * std::numbers::pi;
    double p0 = 0.0;
};

/// Table 1: N = 50, 100, 200 steps over one nonlinear period T = 4K(k²)/ω.
inline constexpr std::array<int, 3> table1_steps{50, 100, 200};

enum class quantity { momentum, state, energy };
inline constexpr std::array all_quantities{quantity::momentum, quantity::state, quantity::energy};

constexpr std::string_view quantity_name(quantity q) {
    return q == quantity::momentum ? "momentum" : q == quantity::state ? "state" : "energy";
}

struct table1_row {
    scheme_kind scheme;
    quantity what;
    std::array<double, 3> errors; ///< at table1_steps
    double order;                 ///< fitted over the three step counts
};

/// Runs N steps per period of scheme k over `periods` nonlinear periods of the pendulum case c.
/// A template (Case is always pendulum_case) only so that including this header compiles nothing:
/// as an inline function it would compile every family member for the pendulum in each
/// translation unit that includes <varsym/varsym.hpp>, about 2 minutes at -O3.
template <class Case = pendulum_case>
error_norms pendulum_errors(const scheme_spec& k, int steps_per_period, int periods = 1,
                            const Case& c = {}, const newton_options& opt = {}) {
    const pendulum::exact_solution exact(c.mass, c.omega, c.q0, c.p0);
    const auto sys = pendulum::make_system(c.mass, c.omega);
    const double h = exact.period() / steps_per_period;
    const phase_state<1> x0{vec<1>{c.q0}, vec<1>{c.p0}};
    const auto n = static_cast<std::size_t>(steps_per_period) * static_cast<std::size_t>(periods);
    return with_stepper(k, sys, h, opt, [&](auto& stepper) {
        return measure_errors(stepper, x0, n, [&](double t) { return exact.at(t); });
    });
}

/// The paper's Table 1: rows (scheme × quantity), errors at N = 50, 100, 200 and fitted order.
template <class Case = pendulum_case>
std::vector<table1_row> table1(const Case& c = {}) {
    std::vector<table1_row> rows;
    for (auto k : paper_schemes) {
        std::array<error_norms, 3> e;
        for (std::size_t i = 0; i < table1_steps.size(); ++i)
            e[i] = pendulum_errors(k, table1_steps[i], 1, c);
        for (auto q : all_quantities) {
            table1_row r{k, q, {}, 0.0};
            for (std::size_t i = 0; i < 3; ++i)
                r.errors[i] = q == quantity::momentum ? e[i].momentum
                              : q == quantity::state  ? e[i].state
                                                      : e[i].energy;
            const std::array<double, 3> n{double(table1_steps[0]), double(table1_steps[1]),
                                          double(table1_steps[2])};
            r.order = fitted_order(n, r.errors);
            rows.push_back(r);
        }
    }
    return rows;
}

} // namespace varsym::paper
