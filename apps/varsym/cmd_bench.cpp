// apps/varsym/cmd_bench.cpp: `varsym bench`, varsym's schemes and Boost.Odeint's symplectic
// steppers on the same problems in one process: error, energy error, time per step, Newton
// iterations, ratios to odeint's stepper of the same order, and the work–precision diagram.
#include <algorithm>
#include <cstdio>
#include <memory>

#include "bench_methods.hpp"
#include "cli_common.hpp"
#include "commands.hpp"
#include "plot.hpp"

namespace varsym::cli {

namespace {

struct bench_options {
    std::vector<std::string> problems{"pendulum", "kepler"};
    std::vector<std::string> schemes{"newmark",   "simpson",   "lobatto-3", "lobatto-4",
                                     "lobatto-5", "lobatto-6", "gauss-2",   "gauss-3",
                                     "gauss-4",   "gauss-5",   "gauss-6"};
    std::vector<int> steps{25, 50, 100, 200, 400, 800};
    std::vector<int> kepler_steps{100, 200, 400, 800, 1600, 3200};
    double periods = 1000;
    double orbits = 100;
    int repetitions = 5;
    std::string format = "text";
    std::string output;
    std::vector<std::string> plot;
};

struct row {
    std::string problem, method, peer;
    int order = 0, steps = 0;
    double error = 0, energy_error = 0, ns = 0, us_period = 0, newton = 0;
    double ns_ratio = 0, error_ratio = 0;
};

/// odeint's stepper of the same order (velocity_verlet for 2, sb3a_mclachlan for 4); for
/// higher orders odeint has none, so its best 4th-order method.
std::string peer_of(const bench_method& m) {
    if (m.odeint) return "";
    return m.order == 2 ? "odeint-velocity_verlet" : "odeint-sb3a_mclachlan";
}

std::vector<row> measure(const bench_problem& b, const std::vector<int>& steps, double periods,
                         int reps) {
    std::vector<row> rows;
    for (const bench_method& m : b.methods)
        for (int n_per : steps) {
            const double h = b.period / n_per;
            const auto n = static_cast<std::size_t>(std::llround(n_per * periods));
            row r{b.name, m.name, peer_of(m), m.order, n_per};
            // One observed run (energy error, Newton statistics; it is also the warm-up), then
            // `reps` timed runs without observer: the median time per step.
            const bench_run observed = m.run(n, h, true);
            r.error = b.error(observed, static_cast<double>(n) * h);
            r.energy_error = observed.energy_error;
            r.newton = observed.newton_mean;
            std::vector<double> ns;
            for (int i = 0; i < reps; ++i)
                ns.push_back(1e9 * m.run(n, h, false).seconds / static_cast<double>(n));
            std::sort(ns.begin(), ns.end());
            r.ns = ns[ns.size() / 2];
            r.us_period = 1e-3 * r.ns * n_per;
            rows.push_back(r);
        }
    for (row& r : rows) {
        const auto peer = std::find_if(rows.begin(), rows.end(), [&](const row& o) {
            return o.problem == r.problem && o.method == r.peer && o.steps == r.steps;
        });
        if (peer == rows.end()) continue;
        r.ns_ratio = r.ns / peer->ns;
        r.error_ratio = r.error / peer->error;
    }
    return rows;
}

std::string csv(const std::vector<row>& rows) {
    std::string s = "problem,method,order,steps_per_period,error,max_rel_energy_error,ns_per_step,"
                    "us_per_period,newton_per_step,peer,ns_ratio,error_ratio\n";
    char buf[400];
    for (const row& r : rows) {
        std::snprintf(buf, sizeof buf, "%s,%s,%d,%d,%.4e,%.4e,%.1f,%.3f,%.2f,%s,%.3f,%.3e\n",
                      r.problem.c_str(), r.method.c_str(), r.order, r.steps, r.error,
                      r.energy_error, r.ns, r.us_period, r.newton, r.peer.c_str(), r.ns_ratio,
                      r.error_ratio);
        s += buf;
    }
    return s;
}

std::string text(const std::vector<row>& rows, const bench_options& o) {
    char buf[400];
    std::snprintf(
        buf, sizeof buf,
        "Pendulum: q0 = pi/2, omega = 2 pi, %g nonlinear periods; Kepler: e = 0.6, a = 1, %g "
        "orbits.\n"
        "error: final max(|dq|, |dp|/omega) (Kepler: max(|dq|, |dp|)); dE: max relative energy\n"
        "error; ns/step: median of %d timed runs after a warm-up; ratios to the peer (odeint's\n"
        "stepper of the same order, or its best 4th-order one, sb3a_mclachlan).\n",
        o.periods, o.orbits, o.repetitions);
    std::string s = buf;
    std::string problem;
    for (const row& r : rows) {
        if (r.problem != problem) {
            problem = r.problem;
            std::snprintf(buf, sizeof buf, "\n%-9s %-25s %5s %5s %10s %10s %9s %10s %6s %9s %10s\n",
                          "problem", "method", "order", "N", "error", "dE", "ns/step", "us/period",
                          "Newton", "ns ratio", "err ratio");
            s += buf;
        }
        char ns_ratio[32] = "", error_ratio[32] = "";
        if (!r.peer.empty()) {
            std::snprintf(ns_ratio, sizeof ns_ratio, "%.3f", r.ns_ratio);
            std::snprintf(error_ratio, sizeof error_ratio, "%.2e", r.error_ratio);
        }
        std::snprintf(buf, sizeof buf,
                      "%-9s %-25s %5d %5d %10.3e %10.3e %9.1f %10.2f %6.2f %9s %10s\n",
                      r.problem.c_str(), r.method.c_str(), r.order, r.steps, r.error,
                      r.energy_error, r.ns, r.us_period, r.newton, ns_ratio, error_ratio);
        s += buf;
    }
    return s;
}

/// Work–precision diagram: final error against µs per period, log–log, one curve per method,
/// one panel per problem.
figure work_precision(const std::vector<row>& rows, const std::vector<std::string>& problems) {
    figure fig;
    const int panels = static_cast<int>(problems.size());
    std::string script = script_preamble(640 * panels, 620) + "set datafile separator ','\n" +
                         "set logscale xy\nset format y '10^{%L}'\nset format x '10^{%L}'\n"
                         "set key outside bottom center horizontal maxrows 5 font ',9' noenhanced\n"
                         "set xlabel 'CPU time per period [us]'\nset ylabel 'final error'\n"
                         "set multiplot layout 1," +
                         std::to_string(panels) + "\n";
    for (const std::string& p : problems) {
        std::string data, names;
        std::string method;
        int blocks = 0;
        for (const row& r : rows) {
            if (r.problem != p) continue;
            if (r.method != method) {
                if (!method.empty()) data += "\n\n";
                method = r.method;
                names += (names.empty() ? "" : " ") + method;
                ++blocks;
            }
            std::string line;
            append_number(line, r.us_period);
            line += ',';
            append_number(line, r.error);
            data += line + '\n';
        }
        fig.data.push_back({"-" + p + ".csv", data});
        script += "set title '" + p + "' font ',14'\nnames = '" + names + "'\n" +
                  "plot for [i=0:" + std::to_string(blocks - 1) + "] stem.'-" + p +
                  ".csv' index i using 1:2 with linespoints lw 2 pt ((i % 7) + 1) "
                  "title (word(names, i + 1))\n";
    }
    fig.script = script + "unset multiplot\n";
    return fig;
}

void bench(const bench_options& o) {
    file_roles roles;
    roles.add("--output", o.output);
    if (!o.plot.empty()) {
        check_pictures(o.plot);
        std::vector<std::string> suffixes;
        for (const std::string& p : o.problems)
            suffixes.push_back("-" + p + ".csv");
        add_figure_files(roles, suffixes, o.plot);
    }
    roles.check();
    for (const double runs : {o.periods, o.orbits})
        for (const int n : o.steps)
            if (std::llround(n * runs) < 1 || n * runs > 1e10)
                throw usage_error("--periods/--orbits times steps per period must give between 1 "
                                  "and 1e10 steps a run");
    output_file out(o.output); // before the work: a conflict is refused at once
    std::vector<row> rows;
    std::vector<std::string> problems;
    for (const std::string& p : o.problems) {
        const bool pendulum = p == "pendulum";
        const bench_problem b = pendulum ? pendulum_bench(o.schemes) : kepler_bench(o.schemes);
        const auto r = measure(b, pendulum ? o.steps : o.kepler_steps,
                               pendulum ? o.periods : o.orbits, o.repetitions);
        rows.insert(rows.end(), r.begin(), r.end());
        problems.push_back(p);
    }
    out.write(o.format == "csv" ? csv(rows) : text(rows, o));
    file_roles others;
    others.add("--output", o.output);
    if (!o.plot.empty()) render_figure(work_precision(rows, problems), o.plot, others);
    out.commit();
}

} // namespace

void add_bench_command(CLI::App& app, action& todo) {
    auto o = std::make_shared<bench_options>();
    auto* cmd = app.add_subcommand(
        "bench",
        "Work-precision benchmark: varsym's schemes against Boost.Odeint's symplectic steppers");
    cmd->footer(
        "\nOne process runs every method on the same problems and step counts: the pendulum\n"
        "(q0 = pi/2, omega = 2 pi, m = 1) over --periods nonlinear periods and the Kepler orbit\n"
        "(e = 0.6) over --orbits orbits. For each method and N it reports the final error\n"
        "against the exact solution, the max relative energy error, ns per step (median of\n"
        "--repetitions timed runs after one observed run that also warms up), mean Newton\n"
        "iterations per step, and ratios of ns/step and error to odeint's stepper of the same\n"
        "order. Times are for this machine at this moment: compare ratios, not absolute times.\n"
        "Odeint's steppers: velocity_verlet (order 2), symplectic_rkn_sb3a_mclachlan and\n"
        "symplectic_rkn_sb3a_m4_mclachlan (order 4). On Kepler the Lobatto and Gauss members\n"
        "run on the general engine with hand derivatives.\n\n"
        "Examples:\n"
        "  varsym bench                                  # everything (a few minutes)\n"
        "  varsym bench --problems pendulum --plot wp.png --format csv -o wp-table.csv\n"
        "  varsym bench --schemes simpson,gauss-4 --steps 50,100 --periods 100 --repetitions 3\n");
    cmd->add_option("--problems", o->problems, "pendulum and/or kepler")
        ->check(CLI::IsMember({"pendulum", "kepler"}))
        ->delimiter(',')
        ->capture_default_str();
    cmd->add_option("--schemes", o->schemes, "varsym schemes: newmark, simpson, lobatto-s, gauss-s")
        ->delimiter(',')
        ->capture_default_str();
    cmd->add_option("--steps", o->steps, "Pendulum: steps per period N")
        ->transform(positive_integer)
        ->delimiter(',')
        ->capture_default_str();
    cmd->add_option("--kepler-steps", o->kepler_steps, "Kepler: steps per orbit")
        ->transform(positive_integer)
        ->delimiter(',')
        ->capture_default_str();
    cmd->add_option("--periods", o->periods, "Pendulum periods per run")
        ->transform(positive_number)
        ->capture_default_str();
    cmd->add_option("--orbits", o->orbits, "Kepler orbits per run")
        ->transform(positive_number)
        ->capture_default_str();
    cmd->add_option("--repetitions", o->repetitions,
                    "Timed runs per method and N (the median is reported)")
        ->transform(positive_integer)
        ->capture_default_str();
    cmd->add_option("--format", o->format, "text or csv")
        ->check(CLI::IsMember({"text", "csv"}))
        ->capture_default_str();
    cmd->add_option("--output,-o", o->output,
                    "File to write the table to (default: standard output)");
    cmd->add_option(
        "--plot", o->plot,
        "Work-precision diagram, .png or .svg (data and gnuplot script kept beside it)");
    cmd->callback([o, &todo] { todo = [o] { bench(*o); }; });
}

} // namespace varsym::cli
