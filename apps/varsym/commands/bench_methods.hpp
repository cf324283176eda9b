// apps/varsym/commands/bench_methods.hpp: the methods `varsym bench` compares, each behind one
// interface: run n steps of size h from the problem's initial state, optionally observing the
// energy.
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
    /// The error of a final state at time t against the exact solution (t in long double: the
    /// time actually integrated, n h, which double would round by up to 1e-13 in a long run).
    std::function<double(const bench_run&, long double)> error;
    /// If > 0, every run covers exactly this time (h = total/n), where the reference is taken.
    double total = 0.0;
};

/// What to run on each problem: varsym schemes (e.g. gauss-4, simpson) and explicit
/// compositions of Störmer–Verlet (yoshida-6, kahan-li-6, kahan-li-8).
struct bench_selection {
    std::vector<std::string> schemes, compositions;
    /// The solver of the family members that do not name one (SCHEME/SOLVER): newton,
    /// simplified or fixed-point, optionally +previous.
    std::string solver = "newton";
};

/// The pendulum from q₀ at rest (ω = 2π, m = 1; named "pendulum" at the paper's q₀ = π/2,
/// "pendulum-q0" otherwise): the selected methods and Boost.Odeint's velocity_verlet,
/// symplectic_rkn_sb3a_mclachlan and symplectic_rkn_sb3a_m4_mclachlan. Error
/// max(|Δq|, |Δp|/(mω)).
bench_problem pendulum_bench(const bench_selection& selection, double q0);
std::string pendulum_name(double q0);

/// Kepler, e = 0.6, a = 1, μ = 1, from pericentre: the same methods. Error max(|Δq|, |Δp|).
bench_problem kepler_bench(const bench_selection& selection);

/// The outer solar system (problems/solar_system.hpp) over `days`: the same methods (the family
/// on its separable fast path, d = 18). Period: Jupiter's, 4332.6 days; error max |Δq| in AU
/// against solar_reference_positions.
bench_problem solar_bench(const bench_selection& selection, double days);

/// The positions after `days` from a long double integration (bench_reference.cpp).
Eigen::VectorXd solar_reference_positions(double days);

/// The composition names --compositions accepts.
const std::vector<std::string>& composition_names();

} // namespace varsym::cli
