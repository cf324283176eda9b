// apps/varsym/commands/cmd_paper.cpp: `varsym paper`, the paper's Table 1 and Figures 1 and 2.
#include <cstdio>
#include <string>
#include <vector>

#include "commands/commands.hpp"
#include "options/cli_common.hpp"
#include "output/plot.hpp"
#include "varsym/integrate.hpp"
#include "varsym/problems/paper.hpp"

namespace varsym::cli {

namespace {

constexpr std::string_view scheme_title(scheme_kind k) {
    return k == scheme_kind::newmark ? "Newmark" : "Symplectic Simpson";
}

// Rows in the paper's order: quantity-major (momentum, state, energy), Newmark before Simpson.
std::vector<paper::table1_row> paper_order(const std::vector<paper::table1_row>& rows) {
    std::vector<paper::table1_row> out;
    for (auto q : paper::all_quantities)
        for (const auto& r : rows)
            if (r.what == q) out.push_back(r);
    return out;
}

std::string table1_text(const std::vector<paper::table1_row>& rows) {
    const paper::pendulum_case c;
    const double period = pendulum::exact_solution(c.mass, c.omega, c.q0, c.p0).period();
    char buf[200];
    std::snprintf(
        buf, sizeof buf,
        "Table 1. Errors in the maximum norm over all time steps of one nonlinear period\n"
        "T = 4K(k^2)/omega = %.6g s (pendulum, m = %g, omega = 2 pi, q0 = pi/2, p0 = 0).\n\n",
        period, c.mass);
    std::string s = buf;
    std::snprintf(buf, sizeof buf, "%-20s %-17s %10s %10s %10s %7s\n", "", "number of meshes", "50",
                  "100", "200", "order");
    s += buf;
    for (const auto& r : rows) {
        const std::string what = r.what == paper::quantity::energy
                                     ? "relative energy"
                                     : std::string(quantity_name(r.what));
        std::snprintf(buf, sizeof buf, "%-20s %-17s %10.2e %10.2e %10.2e %7.1f\n",
                      std::string(scheme_title(r.scheme)).c_str(), what.c_str(), r.errors[0],
                      r.errors[1], r.errors[2], r.order);
        s += buf;
    }
    return s;
}

std::string table1_csv(const std::vector<paper::table1_row>& rows) {
    std::string s = "scheme,quantity,steps,error\n";
    char buf[120];
    for (const auto& r : rows)
        for (std::size_t i = 0; i < r.errors.size(); ++i) {
            std::snprintf(
                buf, sizeof buf, "%s,%s,%d,%.6e\n", std::string(scheme_name(r.scheme)).c_str(),
                std::string(quantity_name(r.what)).c_str(), paper::table1_steps[i], r.errors[i]);
            s += buf;
        }
    return s;
}

// The two figures' gnuplot set-up: two stacked panels sharing t, key on the right.
const std::string paper_preamble =
    script_preamble(1100, 820) + R"(set key outside right top box opaque Left reverse width 1
set autoscale xfix
set xlabel 't [s]'
set lmargin 12
set rmargin 24
)";

std::string csv_row(std::initializer_list<double> values) {
    std::string line;
    for (double v : values) {
        if (!line.empty()) line += ',';
        append_number(line, v);
    }
    return line + '\n';
}

// The exact solution sampled `samples_per_period` times per period over `periods`, as t,q,p CSV.
std::string exact_samples(const pendulum::exact_solution& exact, int periods,
                          int samples_per_period) {
    std::string data = "t,q,p\n";
    for (int i = 0; i <= periods * samples_per_period; ++i) {
        const double t = exact.period() * i / samples_per_period;
        const auto x = exact.at(t);
        data += csv_row({t, x.q(0), x.p(0)});
    }
    return data;
}

constexpr int samples_per_period = 200; // smooth curves for the exact solution

figure figure1(const paper::pendulum_case& c, int periods) {
    const pendulum::exact_solution exact(c.mass, c.omega, c.q0, c.p0);
    const std::string data = exact_samples(exact, periods, samples_per_period);
    std::string script = paper_preamble;
    char title[300];
    std::snprintf(title, sizeof title,
                  "set multiplot layout 2,1 title \"Figure 1. Exact nonlinear pendulum over %d "
                  "periods (ω = 2π, m = 1, q(0) = π/2, p(0) = 0; T = %.5f s)\" font ',15'\n",
                  periods, exact.period());
    script += title;
    script += R"(set ylabel 'state q [rad]'
plot stem.'.csv' using 1:2 with lines lw 2 lc rgb '#1f4e9c' title 'exact q(t)'
set ylabel 'momentum p [kg m^2 s^{-1}]'
plot stem.'.csv' using 1:3 with lines lw 2 lc rgb '#b2182b' title 'exact p(t)'
unset multiplot
)";
    return {{{".csv", data}}, script};
}

figure figure2(const paper::pendulum_case& c, int periods, int steps_per_period) {
    const pendulum::exact_solution exact(c.mass, c.omega, c.q0, c.p0);
    const auto sys = pendulum::make_system(c.mass, c.omega);
    const double h = exact.period() / steps_per_period;
    const auto n = static_cast<std::size_t>(periods) * static_cast<std::size_t>(steps_per_period);
    std::vector<phase_state<1>> traj[2];
    for (int s = 0; s < 2; ++s) {
        phase_state<1> x{vec<1>{c.q0}, vec<1>{c.p0}};
        with_stepper(paper_schemes[s], sys, h, {}, [&](auto& stepper) {
            integrate(stepper, x, 0.0, n,
                      [&](std::size_t, double, const phase_state<1>& y) { traj[s].push_back(y); });
        });
    }
    std::string data = "step,t,q_newmark,p_newmark,q_simpson,p_simpson,q_exact,p_exact\n";
    for (std::size_t j = 0; j <= n; ++j) {
        const double t = static_cast<double>(j) * h;
        const auto e = exact.at(t);
        data += std::to_string(j) + ',' +
                csv_row({t, traj[0][j].q(0), traj[0][j].p(0), traj[1][j].q(0), traj[1][j].p(0),
                         e.q(0), e.p(0)});
    }
    const std::string fine = exact_samples(exact, periods, samples_per_period);
    std::string script = paper_preamble;
    char title[300];
    std::snprintf(title, sizeof title,
                  "set multiplot layout 2,1 title \"Figure 2. Newmark and Simpson schemes, %d "
                  "steps per period, %d periods (ω = 2π, q(0) = π/2, p(0) = 0)\" font ',15'\n",
                  steps_per_period, periods);
    script += title;
    script += R"(set ylabel 'state q [rad]'
plot stem.'-exact.csv' using 1:2 with lines lw 1.5 lc rgb '#444444' title 'exact', \
     stem.'.csv' using 2:3 with linespoints lw 1.5 pt 7 ps 0.9 lc rgb '#e66101' title 'Newmark', \
     stem.'.csv' using 2:5 with linespoints lw 1.5 pt 5 ps 0.9 lc rgb '#1f4e9c' title 'Simpson'
set ylabel 'momentum p [kg m^2 s^{-1}]'
plot stem.'-exact.csv' using 1:3 with lines lw 1.5 lc rgb '#444444' title 'exact', \
     stem.'.csv' using 2:4 with linespoints lw 1.5 pt 7 ps 0.9 lc rgb '#e66101' title 'Newmark', \
     stem.'.csv' using 2:6 with linespoints lw 1.5 pt 5 ps 0.9 lc rgb '#1f4e9c' title 'Simpson'
unset multiplot
)";
    return {{{".csv", data}, {"-exact.csv", fine}}, script};
}

} // namespace

void add_paper_command(CLI::App& app, action& todo) {
    auto* paper_cmd = app.add_subcommand(
        "paper", "Reproduce Dubois & Rojas-Quintero (2023): Table 1, Figures 1 and 2");
    paper_cmd->require_subcommand(1);

    auto* t1 = paper_cmd->add_subcommand(
        "table1",
        "Errors of Newmark and Simpson at N = 50, 100, 200 steps per period, with orders");
    auto format = std::make_shared<std::string>("text");
    auto t1_out = std::make_shared<std::string>();
    t1->add_option("--format", *format,
                   "text (laid out as in the paper) or csv "
                   "(scheme,quantity,steps,error)")
        ->check(CLI::IsMember({"text", "csv"}))
        ->capture_default_str();
    t1->add_option("--output,-o", *t1_out, "File to write (default: standard output)");
    t1->callback([=, &todo] {
        todo = [=] {
            output_file out(*t1_out);
            const auto rows = paper_order(paper::table1());
            out.write(*format == "csv" ? table1_csv(rows) : table1_text(rows));
            out.commit();
        };
    });

    struct figure_options {
        std::vector<std::string> outputs;
        int periods = 5;
        int steps = 10;
    };
    auto add_figure = [&](const char* name, const char* help, bool has_steps) {
        auto o = std::make_shared<figure_options>();
        auto* f = paper_cmd->add_subcommand(name, help);
        f->footer("\nBeside the picture: STEM.csv (data) and STEM.gp (gnuplot script); run "
                  "'gnuplot STEM.gp'\nin that folder to redraw after restyling.");
        f->add_option(
             "--output,-o", o->outputs,
             "Picture to draw, .png or .svg; repeat for both formats (same folder and name)")
            ->required();
        f->add_option("--periods", o->periods, "Number of periods shown (at most 1000)")
            ->transform(positive_integer)
            ->check(CLI::Range(1, 1000))
            ->capture_default_str();
        if (has_steps)
            f->add_option("--steps-per-period", o->steps,
                          "Steps per period of both schemes (at most 10000)")
                ->transform(positive_integer)
                ->check(CLI::Range(1, 10000))
                ->capture_default_str();
        f->callback([=, &todo] {
            todo = [=] {
                check_pictures(o->outputs);
                if (has_steps && o->periods * o->steps > 100000)
                    throw usage_error("--periods times --steps-per-period is at most 100000 (a "
                                      "picture cannot show more points)");
                const paper::pendulum_case c;
                render_figure(has_steps ? figure2(c, o->periods, o->steps) : figure1(c, o->periods),
                              o->outputs);
            };
        });
    };
    add_figure("figure1", "Exact solution over five periods: q(t) and p(t)", false);
    add_figure("figure2", "Newmark, Simpson and exact solution, 10 steps per period, five periods",
               true);
}

} // namespace varsym::cli
