// apps/varsym/commands/cmd_bench.cpp: `varsym bench`, varsym's schemes and Boost.Odeint's
// symplectic steppers on the same problems in one process: error, energy error, time per step,
// Newton iterations, ratios to odeint's stepper of the same order, and the work–precision diagram.
#include <algorithm>
#include <cstdio>
#include <limits>
#include <memory>
#include <numbers>

#include "commands/bench_methods.hpp"
#include "commands/commands.hpp"
#include "options/cli_common.hpp"
#include "output/plot.hpp"

namespace varsym::cli {

namespace {

struct bench_options {
    std::vector<std::string> problems{"pendulum", "kepler", "solar"};
    std::vector<std::string> schemes{"newmark",   "simpson",   "lobatto-3", "lobatto-4",
                                     "lobatto-5", "lobatto-6", "gauss-2",   "gauss-3",
                                     "gauss-4",   "gauss-5",   "gauss-6"};
    std::vector<std::string> compositions{"yoshida-6", "yoshida-6-kdk", "kahan-li-8",
                                          "kahan-li-8-kdk"};
    std::string solver = "fixed-point";
    std::vector<double> q0{std::numbers::pi / 2, 2.5};
    std::vector<int> steps{25, 50, 100, 200, 400, 800};
    std::vector<int> kepler_steps{100, 200, 400, 800, 1600, 3200};
    std::vector<int> solar_steps{20, 40, 80, 160, 320, 640};
    double days = 200000;
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
            // A problem with a reference at one time (b.total) runs exactly to it.
            const auto n = static_cast<std::size_t>(
                std::llround(n_per * (b.total > 0 ? b.total / b.period : periods)));
            const double h = b.total > 0 ? b.total / static_cast<double>(n) : b.period / n_per;
            row r{b.name, m.name, peer_of(m), m.order, n_per};
            // One observed run (energy error, Newton statistics; it is also the warm-up), then
            // `reps` timed runs without observer: the median time per step.
            const bench_run observed = m.run(n, h, true);
            r.error = b.error(observed, static_cast<long double>(n) * h);
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

/// For each problem and method, the least µs per period among the runs whose error is at most
/// each of 1e-6, 1e-8, 1e-10, 1e-12 ("-" where no run reached it).
std::string cheapest(const std::vector<row>& rows) {
    constexpr double targets[] = {1e-6, 1e-8, 1e-10, 1e-12};
    char buf[200];
    std::string s = "\nCheapest us per period at an error of at most:\n";
    std::snprintf(buf, sizeof buf, "%-14s %-25s %10s %10s %10s %10s\n", "problem", "method", "1e-6",
                  "1e-8", "1e-10", "1e-12");
    s += buf;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        if (i > 0 && rows[i].problem == rows[i - 1].problem && rows[i].method == rows[i - 1].method)
            continue;
        std::snprintf(buf, sizeof buf, "%-14s %-25s", rows[i].problem.c_str(),
                      rows[i].method.c_str());
        s += buf;
        for (double target : targets) {
            double best = std::numeric_limits<double>::infinity();
            for (const row& r : rows)
                if (r.problem == rows[i].problem && r.method == rows[i].method && r.error <= target)
                    best = std::min(best, r.us_period);
            if (std::isinf(best))
                std::snprintf(buf, sizeof buf, " %10s", "-");
            else
                std::snprintf(buf, sizeof buf, " %10.2f", best);
            s += buf;
        }
        s += '\n';
    }
    return s;
}

std::string text(const std::vector<row>& rows, const bench_options& o) {
    char buf[800];
    std::snprintf(
        buf, sizeof buf,
        "Pendulum: omega = 2 pi, from q0 at rest (pendulum: q0 = pi/2; pendulum-X: q0 = X), %g\n"
        "nonlinear periods; Kepler: e = 0.6, a = 1, %g orbits; solar: outer solar system, %g "
        "days,\n"
        "N steps per Jupiter period (4332.6 days), error max |dq| in AU.\n"
        "error: final max(|dq|, |dp|/omega) (Kepler: max(|dq|, |dp|)); dE: max relative energy\n"
        "error; ns/step: median of %d timed runs after a warm-up; ratios to the peer (odeint's\n"
        "stepper of the same order, or its best 4th-order one, sb3a_mclachlan).\n",
        o.periods, o.orbits, o.days, o.repetitions);
    std::string s = buf;
    std::string problem;
    for (const row& r : rows) {
        if (r.problem != problem) {
            problem = r.problem;
            std::snprintf(buf, sizeof buf,
                          "\n%-14s %-25s %5s %5s %10s %10s %9s %10s %6s %9s %10s\n", "problem",
                          "method", "order", "N", "error", "dE", "ns/step", "us/period", "Newton",
                          "ns ratio", "err ratio");
            s += buf;
        }
        char ns_ratio[32] = "", error_ratio[32] = "";
        if (!r.peer.empty()) {
            std::snprintf(ns_ratio, sizeof ns_ratio, "%.3f", r.ns_ratio);
            std::snprintf(error_ratio, sizeof error_ratio, "%.2e", r.error_ratio);
        }
        std::snprintf(buf, sizeof buf,
                      "%-14s %-25s %5d %5d %10.3e %10.3e %9.1f %10.2f %6.2f %9s %10s\n",
                      r.problem.c_str(), r.method.c_str(), r.order, r.steps, r.error,
                      r.energy_error, r.ns, r.us_period, r.newton, ns_ratio, error_ratio);
        s += buf;
    }
    return s + cheapest(rows);
}

/// Distinct line colours of the work–precision diagram (Tableau's 10 and 20b, and four more):
/// with the 13 markers of gnuplot's point types, every curve of a panel has its own colour up
/// to 24 methods and its own colour–marker pair up to 312 (24 and 13 are coprime).
constexpr const char* curve_colors =
    "#1f77b4 #d62728 #2ca02c #ff7f0e #9467bd #8c564b #e377c2 #7f7f7f #bcbd22 #17becf #000000 "
    "#393b79 #637939 #8c6d31 #843c39 #7b4173 #5254a3 #8ca252 #bd9e39 #ad494a #a55194 #e6550d "
    "#31a354 #756bb1";
constexpr int curve_color_count = 24;

/// Work–precision diagram: final error against µs per period, log–log, one curve per method
/// (each its own colour and marker), one panel per problem.
figure work_precision(const std::vector<row>& rows, const std::vector<std::string>& problems) {
    figure fig;
    const int panels = static_cast<int>(problems.size());
    // Up to two panels a row.
    const int columns = std::min(panels, 2), lines = (panels + 1) / 2;
    std::string script = script_preamble(640 * columns, 620 * lines) +
                         "set datafile separator ','\n" +
                         "set logscale xy\nset format y '10^{%L}'\nset format x '10^{%L}'\n"
                         "set key outside bottom center horizontal maxrows 5 font ',9' noenhanced\n"
                         "set xlabel 'CPU time per period [us]'\nset ylabel 'final error'\n"
                         "colors = '" +
                         curve_colors + "'\n" + "set multiplot layout " + std::to_string(lines) +
                         "," + std::to_string(columns) + "\n";
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
                  ".csv' index i using 1:2 with linespoints lw 2 lc rgb word(colors, (i % " +
                  std::to_string(curve_color_count) +
                  ") + 1) pt ((i % 13) + 1) ps 1.2 "
                  "title (word(names, i + 1))\n";
    }
    fig.script = script + "unset multiplot\n";
    return fig;
}

void bench(const bench_options& o) {
    file_roles roles;
    roles.add_output("--output", o.output);
    if (!o.plot.empty()) {
        check_pictures(o.plot);
        std::vector<std::string> suffixes;
        for (const std::string& p : o.problems)
            if (p == "pendulum")
                for (double q0 : o.q0)
                    suffixes.push_back("-" + pendulum_name(q0) + ".csv");
            else
                suffixes.push_back("-" + p + ".csv");
        add_figure_files(roles, suffixes, o.plot);
    }
    roles.check();
    for (const double q0 : o.q0)
        if (!(q0 > 0.0 && q0 < std::numbers::pi))
            throw usage_error("--q0 must be between 0 and pi rad (exclusive), got " +
                              std::to_string(q0));
    for (const double runs : {o.periods, o.orbits})
        for (const int n : o.steps)
            if (std::llround(n * runs) < 1 || n * runs > 1e10)
                throw usage_error("--periods/--orbits times steps per period must give between 1 "
                                  "and 1e10 steps a run");
    if (!(o.days >= 1.0 && o.days <= 1e7))
        throw usage_error("--days must be between 1 and 1e7 (the long double reference takes "
                          "about 3.5 us a day)");
    output_file out(o.output); // before the work: a conflict is refused at once
    std::vector<row> rows;
    std::vector<std::string> problems;
    bench_selection selection{o.schemes, {}, o.solver};
    for (const std::string& c : o.compositions)
        if (c != "none") selection.compositions.push_back(c);
    auto run = [&](const bench_problem& b, const std::vector<int>& steps, double runs) {
        const auto r = measure(b, steps, runs, o.repetitions);
        rows.insert(rows.end(), r.begin(), r.end());
        problems.push_back(b.name);
    };
    for (const std::string& p : o.problems) {
        if (p == "pendulum")
            for (double q0 : o.q0)
                run(pendulum_bench(selection, q0), o.steps, o.periods);
        else if (p == "kepler")
            run(kepler_bench(selection), o.kepler_steps, o.orbits);
        else
            run(solar_bench(selection, o.days), o.solar_steps, 0.0);
    }
    out.write(o.format == "csv" ? csv(rows) : text(rows, o));
    file_roles others;
    others.add_output("--output", o.output);
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
        "(omega = 2 pi, m = 1) from each --q0 at rest over --periods nonlinear periods, and the\n"
        "Kepler orbit (e = 0.6) over --orbits orbits, and the outer solar system (Hairer, Lubich\n"
        "& Wanner, sec. I.2.4: d = 18, AU and days) over --days days against a long double\n"
        "reference, N counting steps per Jupiter period. For each method and N it reports the "
        "final\n"
        "error against the exact solution at the time integrated (N h, in long double), the\n"
        "max relative energy error, ns per step (median of\n"
        "--repetitions timed runs after one observed run that also warms up), mean Newton\n"
        "iterations per step, and ratios of ns/step and error to odeint's stepper of the same\n"
        "order. Times are for this machine at this moment: compare ratios, not absolute times.\n"
        "Odeint's steppers: velocity_verlet (order 2), symplectic_rkn_sb3a_mclachlan and\n"
        "symplectic_rkn_sb3a_m4_mclachlan (order 4); explicit compositions of Stormer-Verlet:\n"
        "Yoshida's order 6 (9 stages) and Kahan & Li's orders 6 (9) and 8 (17 stages), each of\n"
        "drift-kick-drift steps (as Hairer's gni_comp; the more accurate) or, with -kdk,\n"
        "kick-drift-kick steps. The\n"
        "family's members solve their steps by --solver, or by the solver named after '/'\n"
        "(e.g. --schemes gauss-4/newton,gauss-4 compares Newton with the default).\n"
        "The text table ends with the cheapest us per period at errors 1e-6 to 1e-12.\n\n"
        "Examples:\n"
        "  varsym bench                                  # everything (about 3 minutes)\n"
        "  varsym bench --problems pendulum --plot wp.png --format csv -o wp-table.csv\n"
        "  varsym bench --schemes simpson,gauss-4 --steps 50,100 --periods 100 --repetitions 3\n");
    cmd->add_option("--problems", o->problems, "pendulum, kepler and/or solar")
        ->check(CLI::IsMember({"pendulum", "kepler", "solar"}))
        ->delimiter(',')
        ->capture_default_str();
    cmd->add_option(
           "--schemes", o->schemes,
           "varsym schemes: newmark, simpson, lobatto-s, gauss-s[/SOLVER[+previous|+forces]]")
        ->delimiter(',')
        ->capture_default_str();
    cmd->add_option("--solver", o->solver,
                    "How lobatto-s (s >= 3) and gauss-s (s >= 2) solve their steps unless named "
                    "in --schemes: newton, simplified or fixed-point, +previous or +forces to "
                    "start from the previous step's polynomial or forces (simpson and newmark "
                    "always use Newton on d x d)")
        ->capture_default_str();
    cmd->add_option("--compositions", o->compositions,
                    "Explicit compositions of Stormer-Verlet run beside them: yoshida-6, "
                    "kahan-li-6, kahan-li-8 (drift-kick-drift), the same with -kdk "
                    "(kick-drift-kick), or none")
        ->check([](const std::string& v) {
            const auto& names = composition_names();
            return v == "none" || std::find(names.begin(), names.end(), v) != names.end()
                       ? std::string()
                       : "unknown composition '" + v +
                             "' (yoshida-6, kahan-li-6, kahan-li-8, each also -kdk; none)";
        })
        ->delimiter(',')
        ->capture_default_str();
    cmd->add_option("--q0", o->q0, "Pendulum: initial angles [rad], from rest, each a problem")
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
    cmd->add_option("--solar-steps", o->solar_steps,
                    "Outer solar system: steps per Jupiter period (4332.6 days)")
        ->transform(positive_integer)
        ->delimiter(',')
        ->capture_default_str();
    cmd->add_option("--days", o->days, "Outer solar system: days per run")
        ->transform(positive_number)
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
