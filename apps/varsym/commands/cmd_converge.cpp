// apps/varsym/commands/cmd_converge.cpp: `varsym converge`, the error table of any scheme at several
// step counts with observed orders (the generalisation of the paper's Table 1), and its plot.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "cli_common.hpp"
#include "commands.hpp"
#include "plot.hpp"
#include "shared_options.hpp"
#include "varsym/problems/paper.hpp"

namespace varsym::cli {

namespace {

struct converge_options {
    std::string model = "pendulum";
    scheme_options scheme;
    pendulum_options pendulum;
    std::vector<int> steps{25, 50, 100, 200};
    int periods = 1;
    std::string format = "text";
    std::string output;
    std::vector<std::string> plot;
    newton_options newton;
};

struct result {
    int steps;
    double err[3]; // momentum, state, energy
};

const char* const quantity_titles[3] = {"momentum", "state", "relative energy"};

double order_between(const result& a, const result& b, int q) {
    return std::log(a.err[q] / b.err[q]) / std::log(static_cast<double>(b.steps) / a.steps);
}

double fitted(const std::vector<result>& rs, int q) {
    std::vector<double> n, e;
    for (const auto& r : rs) {
        if (!(r.err[q] > 0)) return std::nan(""); // exact to round-off: no order to fit
        n.push_back(r.steps);
        e.push_back(r.err[q]);
    }
    return fitted_order(n, e);
}

std::string format_order(double p) {
    char buf[32];
    if (std::isfinite(p))
        std::snprintf(buf, sizeof buf, "%.2f", p);
    else
        std::snprintf(buf, sizeof buf, "n/a");
    return buf;
}

std::string text_table(const converge_options& o, const scheme_spec& spec, double period,
                       const std::vector<result>& rs) {
    char buf[400];
    std::snprintf(buf, sizeof buf,
                  "%s (order %d) on the pendulum (m = %g, omega = %g, q0 = %g, p0 = %g),\n"
                  "%d period(s) of T = %.6g s. Errors in the maximum norm over all steps;\n"
                  "in parentheses the order observed from the previous row.\n\n",
                  spec.label().c_str(), spec.order(), o.pendulum.mass, o.pendulum.omega,
                  o.pendulum.q0, o.pendulum.p0, o.periods, period);
    std::string s = buf;
    std::snprintf(buf, sizeof buf, "%8s   %-20s %-20s %-20s\n", "steps", quantity_titles[0],
                  quantity_titles[1], quantity_titles[2]);
    s += buf;
    for (std::size_t i = 0; i < rs.size(); ++i) {
        std::snprintf(buf, sizeof buf, "%8d", rs[i].steps);
        s += buf;
        for (int q = 0; q < 3; ++q) {
            char local[24] = "";
            if (i > 0)
                std::snprintf(local, sizeof local, "(%s)",
                              format_order(order_between(rs[i - 1], rs[i], q)).c_str());
            std::snprintf(buf, sizeof buf, "   %.3e %-9s", rs[i].err[q], local);
            s += buf;
        }
        s += '\n';
    }
    std::snprintf(buf, sizeof buf, "%8s   %-20s %-20s %-20s\n", "fitted",
                  format_order(fitted(rs, 0)).c_str(), format_order(fitted(rs, 1)).c_str(),
                  format_order(fitted(rs, 2)).c_str());
    return s + buf;
}

std::string csv_table(const scheme_spec& spec, const std::vector<result>& rs) {
    std::string s = "scheme,degree,quantity,steps,error\n";
    char buf[160];
    for (int q = 0; q < 3; ++q)
        for (const auto& r : rs) {
            std::snprintf(buf, sizeof buf, "%s,%d,%s,%d,%.6e\n",
                          std::string(scheme_name(spec.kind)).c_str(), spec.degree,
                          std::string(paper::quantity_name(paper::all_quantities[q])).c_str(),
                          r.steps, r.err[q]);
            s += buf;
        }
    return s;
}

figure convergence_plot(const scheme_spec& spec, const std::vector<result>& rs) {
    // Reference slope N^(−2s), a decade below the first state error so that it stays visible.
    std::string data = "steps,momentum,state,energy,reference\n";
    for (const auto& r : rs) {
        std::string line = std::to_string(r.steps);
        const double ref = 0.1 * rs.front().err[1] *
                           std::pow(static_cast<double>(r.steps) / rs.front().steps, -spec.order());
        for (double v : {r.err[0], r.err[1], r.err[2], ref}) {
            line += ',';
            append_number(line, v);
        }
        data += line + '\n';
    }
    char title[200];
    std::snprintf(title, sizeof title,
                  "set title \"Convergence of %s (order %d) on the pendulum\" font ',15'\n",
                  spec.label().c_str(), spec.order());
    std::string script = script_preamble(900, 650) + R"(set logscale xy
set autoscale xfix
set offsets graph 0.04, graph 0.04, graph 0.04, graph 0.04
set format y '10^{%L}'
set key bottom left box opaque
set xlabel 'steps per period N'
set ylabel 'error (max norm over all steps)'
)";
    script += title;
    script += "set xtics (";
    for (std::size_t i = 0; i < rs.size(); ++i) {
        if (i > 0) script += ", ";
        script += std::to_string(rs[i].steps);
    }
    script += ")\n";
    script += "plot stem.'.csv' using 1:2 with linespoints lw 2 pt 7 title 'momentum', \\\n"
              "     stem.'.csv' using 1:3 with linespoints lw 2 pt 5 title 'state', \\\n"
              "     stem.'.csv' using 1:4 with linespoints lw 2 pt 9 title 'relative energy', \\\n"
              "     stem.'.csv' using 1:5 with lines dt 2 lw 2 lc rgb '#666666' title 'slope −" +
              std::to_string(spec.order()) + "'\n";
    return {{{".csv", data}}, script};
}

void converge(const converge_options& o) {
    const scheme_spec spec = make_spec(o.scheme);
    make_system(o.pendulum); // validates the parameters before any work
    file_roles roles;
    roles.add("--output", o.output);
    if (!o.plot.empty()) {
        check_pictures(o.plot);
        add_figure_files(roles, {".csv"}, o.plot);
    }
    roles.check();
    output_file out(o.output); // before the work: a conflict is refused at once
    const double period = make_exact(o.pendulum).period();
    std::vector<int> steps = o.steps;
    std::sort(steps.begin(), steps.end());
    if (std::adjacent_find(steps.begin(), steps.end()) != steps.end() || steps.size() < 2)
        throw usage_error("--steps needs at least two different step counts, e.g. 25,50,100,200");
    std::vector<result> rs;
    for (int n : steps) {
        const error_norms e = paper::pendulum_errors(spec, n, o.periods, o.pendulum, o.newton);
        rs.push_back({n, {e.momentum, e.state, e.energy}});
    }
    out.write(o.format == "csv" ? csv_table(spec, rs) : text_table(o, spec, period, rs));
    file_roles others;
    others.add("--output", o.output);
    if (!o.plot.empty()) render_figure(convergence_plot(spec, rs), o.plot, others);
    out.commit();
}

} // namespace

void add_converge_command(CLI::App& app, action& todo) {
    auto o = std::make_shared<converge_options>();
    auto* cmd = app.add_subcommand(
        "converge", "Error table of a scheme at several step counts, with observed orders");
    cmd->footer(
        std::string(pendulum_help) +
        "\nErrors, as in the paper's Table 1: max over all steps of |p_j - p(t_j)|, "
        "|q_j - q(t_j)|\nand |H_j - H_0|/H_0 against the exact solution. The fitted "
        "order is the least-squares\nslope over all step counts; round-off (about 1e-15 "
        "in q) stops it for the highest orders.\n\n"
        "Examples:\n"
        "  varsym converge --scheme simpson                         # Table 1's Simpson rows\n"
        "  varsym converge --scheme gauss --degree 3 --steps 16,32,64,128 --plot conv.png\n"
        "  varsym converge --scheme lobatto --degree 2 --format csv\n");
    cmd->add_option("--model", o->model,
                    "Model: pendulum (the other models run with 'varsym run --model')")
        ->check(CLI::IsMember({"pendulum"}))
        ->capture_default_str();
    add_scheme_options(*cmd, o->scheme);
    add_pendulum_options(*cmd, o->pendulum);
    cmd->add_option("--steps", o->steps, "Steps per period, comma-separated")
        ->delimiter(',')
        ->transform(positive_integer)
        ->capture_default_str();
    cmd->add_option("--periods", o->periods, "Number of periods integrated")
        ->transform(positive_integer)
        ->capture_default_str();
    cmd->add_option("--format", o->format, "text or csv (scheme,degree,quantity,steps,error)")
        ->check(CLI::IsMember({"text", "csv"}))
        ->capture_default_str();
    cmd->add_option("--output,-o", o->output,
                    "File to write the table to (default: standard output)");
    cmd->add_option(
        "--plot", o->plot,
        "Log-log convergence plot, .png or .svg (data and gnuplot script kept beside it); "
        "repeat for both formats");
    cmd->callback([o, &todo] { todo = [o] { converge(*o); }; });
}

} // namespace varsym::cli
