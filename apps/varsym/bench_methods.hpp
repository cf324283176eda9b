// apps/varsym/bench_methods.hpp: the methods `varsym bench` compares, each behind one interface:
// run n steps of size h from the problem's initial state, optionally observing the energy.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "varsym/types.hpp"

namespace varsym::cli {

/// What one run of a method produced.
struct bench_run {
    Eigen::VectorXd q, p;      ///< the final state
    double energy_error = 0.0; ///< max |H_j − H_0|/|H_0| over the steps (observed runs only)
    double newton_mean = 0.0;  ///< mean Newton iterations per step (0 for explicit methods)
    double seconds = 0.0;      ///< time spent stepping (not constructing, not observing)
};

struct bench_method {
    std::string name;
    int order = 0;
    bool odeint = false;
    /// run(n, h, observe): n steps of size h; with observe, also the energy error.
    std::function<bench_run(std::size_t, double, bool)> run;
};

/// A problem of the benchmark: its methods, period and exact final state.
struct bench_problem {
    std::string name;
    double period = 0.0;
    std::vector<bench_method> methods;
    /// The error of a final state at time t against the exact solution.
    std::function<double(const bench_run&, double)> error;
};

/// The pendulum (q₀ = π/2, ω = 2π, m = 1): every varsym scheme in `specs` and Boost.Odeint's
/// velocity_verlet, symplectic_rkn_sb3a_mclachlan and symplectic_rkn_sb3a_m4_mclachlan. Error
/// max(|Δq|, |Δp|/(mω)).
bench_problem pendulum_bench(const std::vector<std::string>& specs);

/// Kepler, e = 0.6, a = 1, μ = 1, from pericentre: the same methods. Error max(|Δq|, |Δp|).
bench_problem kepler_bench(const std::vector<std::string>& specs);

} // namespace varsym::cli
