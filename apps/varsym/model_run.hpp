// apps/varsym/model_run.hpp: the driver every model's run shares: steps a stepper, streams the
// CSV rows (state, energy, conserved quantities, exact values), and turns a failed step into
// exit code 3 keeping the rows already written.
#pragma once

#include <iostream>
#include <string>

#include "models.hpp"
#include "varsym/integrate.hpp"

namespace varsym::cli {

/// Streams `step,t,<state columns><extra header>` rows for plan.steps steps from x, written every
/// s.every steps and at the end. `with_stepper(f)` calls f(stepper); `extras(t, x, line)` appends
/// the model's columns (each preceded by a comma) to a row.
template <int D, class WithStepper, class Extras>
void stream_trajectory(const run_setup& s, const run_plan& plan, phase_state<D> x,
                       const std::string& extra_header, WithStepper&& with_stepper, Extras&& extras) {
    output_file out(s.output);
    const int d = static_cast<int>(x.q.size());
    out.write("step,t," + state_columns(d) + extra_header + "\n");
    const auto every = static_cast<std::size_t>(s.every);
    const std::size_t n = plan.steps;
    std::string line;
    auto observe = [&](std::size_t j, double t, const phase_state<D>& y) {
        const bool write = every == 0 ? j == n : (j % every == 0 || j == n);
        if (!write) return;
        line = std::to_string(j);
        line += ',';
        append_number(line, t);
        for (Eigen::Index i = 0; i < d; ++i) {
            line += ',';
            append_number(line, y.q(i));
        }
        for (Eigen::Index i = 0; i < d; ++i) {
            line += ',';
            append_number(line, y.p(i));
        }
        extras(t, y, line);
        line += '\n';
        out.write(line);
    };
    run_summary summary;
    try {
        summary = with_stepper([&](auto& stepper) { return integrate(stepper, x, 0.0, n, observe); });
    } catch (const step_failure& e) {
        if (out.is_stdout()) throw numerical_error(e.what());
        out.keep_partial();
        throw numerical_error(std::string(e.what()) + "; the rows before it are in " +
                              out.partial_path());
    }
    out.commit();
    if (s.stats)
        std::cerr << "varsym: " << s.spec.label() << ", " << summary.steps << " steps of h = " << plan.h
                  << ": Newton iterations per step mean " << summary.mean_newton_iterations()
                  << ", max " << summary.newton_iterations_max << '\n';
}

/// Appends ",v" for each value.
inline void append_values(std::string& line, std::initializer_list<double> values) {
    for (double v : values) {
        line += ',';
        append_number(line, v);
    }
}

} // namespace varsym::cli
