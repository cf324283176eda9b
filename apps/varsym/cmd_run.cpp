// apps/varsym/cmd_run.cpp: `varsym run`, integrate a pendulum and stream the trajectory as CSV.
#include <cmath>
#include <iostream>

#include "cli_common.hpp"
#include "commands.hpp"
#include "shared_options.hpp"
#include "varsym/integrate.hpp"
#include "varsym/problems/pendulum.hpp"
#include "varsym/schemes/scheme_kind.hpp"

namespace varsym::cli {

namespace {

struct run_options {
    scheme_options scheme;
    pendulum_options pendulum;
    long long steps_per_period = 50;
    double periods = 1.0;
    double time = 0.0;
    long long steps = 0;
    long long every = 1;
    std::string output;
    bool stats = false;
    newton_options newton;
};

// At most this many steps in one run: about 2 years at 50 ns/step; beyond it something is off.
constexpr double max_steps = 1e15;

void run(const run_options& o, const CLI::App& cmd) {
    const scheme_spec spec = make_spec(o.scheme);
    const pendulum::system sys = make_system(o.pendulum);
    const pendulum::exact_solution exact = make_exact(o.pendulum);

    double h = 0.0;
    double count = 0.0; // number of steps, checked against max_steps before it becomes an integer
    if (cmd.count("--time") > 0) {
        count = static_cast<double>(o.steps);
        h = o.time / count;
    } else {
        const double total = static_cast<double>(o.steps_per_period) * o.periods;
        count = std::round(total);
        if (std::abs(total - count) > 1e-9 * total || count < 1.0)
            throw usage_error("--periods " + std::to_string(o.periods) + " times --steps-per-period " +
                              std::to_string(o.steps_per_period) +
                              " is not a whole number of steps; choose periods so that it is");
        h = exact.period() / static_cast<double>(o.steps_per_period);
    }
    if (count > max_steps) throw usage_error("more than 1e15 steps requested");
    const auto n = static_cast<std::size_t>(count);

    output_file out(o.output);
    out.write("step,t,q,p,energy,q_exact,p_exact\n");
    const auto every = static_cast<std::size_t>(o.every);
    std::string line;
    auto observe = [&](std::size_t j, double t, const phase_state<1>& x) {
        const bool write = every == 0 ? j == n : (j % every == 0 || j == n);
        if (!write) return;
        const auto ref = exact.at(t);
        line = std::to_string(j);
        for (double v : {t, x.q(0), x.p(0), sys.energy(x), ref.q(0), ref.p(0)}) {
            line += ',';
            append_number(line, v);
        }
        line += '\n';
        out.write(line);
    };
    phase_state<1> x{vec<1>{o.pendulum.q0}, vec<1>{o.pendulum.p0}};
    run_summary summary;
    try {
        summary = with_stepper(spec, sys, h, o.newton,
                               [&](auto& stepper) { return integrate(stepper, x, 0.0, n, observe); });
    } catch (const step_failure& e) {
        if (out.is_stdout()) throw numerical_error(e.what());
        out.keep_partial();
        throw numerical_error(std::string(e.what()) + "; the rows before it are in " +
                              out.partial_path());
    }
    out.commit();
    if (o.stats)
        std::cerr << "varsym: " << spec.label() << ", " << summary.steps << " steps of h = " << h
                  << ": Newton iterations per step mean " << summary.mean_newton_iterations()
                  << ", max " << summary.newton_iterations_max << '\n';
}

} // namespace

void add_run_command(CLI::App& app, action& todo) {
    auto o = std::make_shared<run_options>();
    auto* cmd = app.add_subcommand(
        "run", "Integrate the nonlinear pendulum and stream its trajectory as CSV");
    cmd->footer(std::string(pendulum_help) + "\n" +
        "Columns: step,t,q,p,energy,q_exact,p_exact (17 significant digits). The exact solution\n"
        "uses Jacobi elliptic functions (libration and rotation; the separatrix is refused).\n"
        "A file given by --output is written as FILE.part and renamed when the run completes;\n"
        "a run whose Newton iteration fails keeps FILE.part with the rows already computed.\n\n"
        "Examples:\n"
        "  varsym run                                   # Simpson, one period, 50 steps\n"
        "  varsym run --scheme newmark --steps-per-period 10 --periods 5 --output traj.csv\n"
        "  varsym run --time 100 --steps 100000 --every 1000 --q0 3.0\n"
        "  varsym run --scheme gauss --degree 4 --steps-per-period 20\n");
    add_scheme_options(*cmd, o->scheme);
    add_pendulum_options(*cmd, o->pendulum);
    auto* spp = cmd->add_option("--steps-per-period", o->steps_per_period,
                                "Steps per nonlinear period T = 4K(k^2)/omega (one revolution in "
                                "rotation)")
                    ->check(positive_integer)
                    ->capture_default_str();
    auto* periods = cmd->add_option("--periods", o->periods, "Number of periods to integrate")
                        ->check(positive_number)
                        ->capture_default_str();
    auto* time = cmd->add_option("--time", o->time, "Final time T [s] (with --steps; instead of "
                                                    "--periods)")
                     ->check(positive_number);
    auto* steps = cmd->add_option("--steps", o->steps, "Number of steps over --time")
                      ->check(positive_integer);
    time->needs(steps)->excludes(spp)->excludes(periods);
    steps->needs(time);
    cmd->add_option("--every", o->every,
                    "Write every E-th step and always the last; 0 writes only the final row")
        ->check(non_negative_integer)
        ->capture_default_str();
    cmd->add_option("--output,-o", o->output, "CSV file to write (default: standard output)");
    cmd->add_option("--newton-tol", o->newton.tolerance,
                    "Newton stops when its update is below this times the size of the step's increment")
        ->check(positive_number)
        ->capture_default_str();
    cmd->add_option("--newton-max-iter", o->newton.max_iterations,
                    "Newton iterations allowed per step before the run stops with an error")
        ->check(positive_integer)
        ->capture_default_str();
    cmd->add_flag("--stats", o->stats, "Print Newton iteration statistics to standard error");
    cmd->callback([o, cmd, &todo] { todo = [o, cmd] { run(*o, *cmd); }; });
}

} // namespace varsym::cli
