// apps/varsym/commands/cmd_converge.cpp: `varsym converge`, the error table of any scheme at
// several step counts with observed orders (the generalisation of the paper's Table 1), and its
// plot.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numeric>
#include <string>
#include <vector>

#include "commands/commands.hpp"
#include "ensemble/ensemble_members.hpp"
#include "models/registry_models.hpp"
#include "options/cli_common.hpp"
#include "options/expression_options.hpp"
#include "options/shared_options.hpp"
#include "output/plot.hpp"
#include "varsym/models/model.hpp"
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
    std::vector<std::string> set; ///< NAME=VALUE: a parameter or q0_I/p0_I (not the pendulum)
    double time = 0.0;            ///< the span of a model without a period (0: the model's)
    expression_spec expression;   ///< --lagrangian etc., for --model lagrangian
    urdf_spec urdf;               ///< --urdf FILE, --torques, for --model urdf
};

/// The model of --model: the registry's, or `lagrangian` made from its options.
std::shared_ptr<const models::model> model_of(const converge_options& o) {
    if (o.model == "urdf") return robot_model_of(o.urdf);
    if (!o.urdf.path.empty())
        throw usage_error("--urdf is for --model urdf, not " + shown(o.model));
    if (!o.urdf.base.empty())
        throw usage_error("--base is for --model urdf, not " + shown(o.model));
    if (o.model == "lagrangian") return expression_model_of(o.expression);
    if (!o.expression.lagrangian.empty())
        throw usage_error("--lagrangian is for --model lagrangian, not " + shown(o.model));
    return unowned(models::get(o.model));
}

/// The method measured: a scheme of the family, or a model's own integrator (the rigid bodies'
/// lgvi of an order).
struct method {
    std::string label; ///< "simpson", "gauss-3", "lgvi-4"
    int order = 0;
    std::string scheme; ///< the CSV's scheme and degree (lgvi: its order as the degree)
    int degree = 0;
};

method method_of(const scheme_spec& spec) {
    return {spec.label(), spec.order(), std::string(scheme_name(spec.kind)), spec.degree};
}

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

std::string text_table(const converge_options& o, const method& spec, double period,
                       const std::vector<result>& rs, const std::string& against) {
    char buf[600];
    if (o.model == "pendulum")
        std::snprintf(buf, sizeof buf,
                      "%s (order %d) on the pendulum (m = %g, omega = %g, q0 = %g, p0 = %g),\n"
                      "%d period(s) of T = %.6g s. Errors in the maximum norm over all steps;\n"
                      "in parentheses the order observed from the previous row.\n\n",
                      spec.label.c_str(), spec.order, o.pendulum.mass, o.pendulum.omega,
                      o.pendulum.q0, o.pendulum.p0, o.periods, period);
    else
        std::snprintf(buf, sizeof buf,
                      "%s (order %d) on %s over t = 0..%.6g, against %s.\nErrors in the maximum "
                      "norm over all steps; in parentheses the order observed\nfrom the previous "
                      "row. Energy: E - W under forces; absolute where E0 = 0.\n\n",
                      spec.label.c_str(), spec.order, o.model.c_str(), period, against.c_str());
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

std::string csv_table(const method& spec, const std::vector<result>& rs) {
    std::string s = "scheme,degree,quantity,steps,error\n";
    char buf[160];
    for (int q = 0; q < 3; ++q)
        for (const auto& r : rs) {
            std::snprintf(buf, sizeof buf, "%s,%d,%s,%d,%.6e\n", spec.scheme.c_str(), spec.degree,
                          std::string(paper::quantity_name(paper::all_quantities[q])).c_str(),
                          r.steps, r.err[q]);
            s += buf;
        }
    return s;
}

figure convergence_plot(const method& spec, const std::vector<result>& rs,
                        const std::string& model) {
    // Log axes show positive errors only: a quantity with no positive error (a motion the
    // scheme reproduces exactly, a system at rest) is left out, and with none left there is
    // nothing to draw.
    std::array<bool, 3> drawn{};
    for (int q = 0; q < 3; ++q)
        drawn[static_cast<std::size_t>(q)] =
            std::any_of(rs.begin(), rs.end(), [&](const result& r) { return r.err[q] > 0.0; });
    if (std::none_of(drawn.begin(), drawn.end(), [](bool b) { return b; }))
        throw std::runtime_error("cannot draw --plot: every error is 0 (the scheme reproduces "
                                 "this motion exactly), nothing to show on log axes; the table "
                                 "was written");
    // Reference slope N^(−2s), a decade below the first state error so that it stays visible.
    std::string data = "steps,momentum,state,energy,reference\n";
    for (const auto& r : rs) {
        std::string line = std::to_string(r.steps);
        const double first = rs.front().err[drawn[1] ? 1 : drawn[0] ? 0 : 2];
        const double ref =
            0.1 * first * std::pow(static_cast<double>(r.steps) / rs.front().steps, -spec.order);
        for (double v : {r.err[0], r.err[1], r.err[2], ref}) {
            line += ',';
            append_number(line, v);
        }
        data += line + '\n';
    }
    char title[200];
    std::snprintf(title, sizeof title,
                  "set title \"Convergence of %s (order %d) on the %s\" font ',15'\n",
                  spec.label.c_str(), spec.order, model.c_str());
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
    script += "plot ";
    const char* series[] = {"using 1:2 with linespoints lw 2 pt 7 title 'momentum'",
                            "using 1:3 with linespoints lw 2 pt 5 title 'state'",
                            "using 1:4 with linespoints lw 2 pt 9 title 'relative energy'"};
    for (std::size_t q = 0; q < 3; ++q)
        if (drawn[q]) script += std::string("stem.'.csv' ") + series[q] + ", \\\n     ";
    script += "stem.'.csv' using 1:5 with lines dt 2 lw 2 lc rgb '#666666' title 'slope −" +
              std::to_string(spec.order) + "'\n";
    return {{{".csv", data}}, script};
}

/// The states (q, p) and watched energies of a simulation at each of its n steps, and at its
/// start, with the model's exact q and p where it has them (the columns NAME_exact).
struct recorded_run {
    std::vector<double> state, exact, energy;
    bool has_exact = false;
};
recorded_run record_run(models::simulation& sim, std::size_t n) {
    recorded_run r;
    const auto& cols = sim.columns();
    std::vector<std::size_t> exact;
    for (const char* k : {"q", "p"})
        for (int i = 0; i <= sim.dim(); ++i) {
            const std::string name = i == 0 ? std::string(k) + "_exact"
                                            : std::string(k) + "_" + std::to_string(i) + "_exact";
            const auto it = std::find(cols.begin(), cols.end(), name);
            if (it != cols.end()) exact.push_back(static_cast<std::size_t>(it - cols.begin()));
        }
    r.has_exact = exact.size() == static_cast<std::size_t>(2 * sim.dim());
    std::vector<double> values(cols.size());
    auto keep = [&] {
        r.state.insert(r.state.end(), sim.q().begin(), sim.q().end());
        r.state.insert(r.state.end(), sim.p().begin(), sim.p().end());
        r.energy.push_back(sim.watched_energy());
        if (!r.has_exact) return false;
        sim.values(values);
        for (std::size_t k : exact)
            r.exact.push_back(values[k]);
        return false;
    };
    keep();
    sim.advance(n, keep);
    return r;
}

/// The errors of scheme `spec` on a model of the models layer at each step count over `span`:
/// against its exact solution where it has one, else against gauss-8 (order 16) at twice the
/// step counts' least common multiple. A model with its own integrator (the rigid bodies) is
/// measured with that, of the order its parameters choose, against its highest order at those
/// steps; `measured` says which method ran. Sets `against` to say which reference.
std::vector<result> model_errors(const converge_options& o, const models::model& m,
                                 const scheme_spec& spec, const std::vector<int>& steps,
                                 double& span, std::string& against, method& measured) {
    std::vector<double> values = m.defaults();
    ensemble_model keys; // the keys an ensemble member of m takes: q0_I, p0_I, the parameters
    keys.name = m.name;
    keys.dim = m.dim;
    keys.fixed_start = !m.fixed_start.empty();
    for (const auto& p : m.parameters)
        keys.parameters.emplace_back(p.name, p.value);
    std::vector<std::pair<std::size_t, double>> q0, p0; // --set q0_I=…, p0_I=…
    for (const auto& a : o.set) {
        const std::size_t eq = a.find('=');
        double v = 0.0;
        if (eq == std::string::npos || !CLI::detail::lexical_cast(a.substr(eq + 1), v) ||
            !std::isfinite(v))
            throw usage_error("--set needs NAME=VALUE with a finite value, got " + shown(a) +
                              " (NAME: a parameter of " + m.name + ", q0_I or p0_I)");
        const auto [kind, i] = target_of(a.substr(0, eq), keys);
        if (kind == 2)
            values[i] = v;
        else
            (kind == 0 ? q0 : p0).emplace_back(i, v);
    }
    models::problem pr, best; // best: the own integrator's highest order, the reference
    try {
        if (q0.empty() && p0.empty()) {
            pr = m.prepare(values);
        } else { // the model's start, the keys given replaced (as in an ensemble's members)
            models::start st{m.q0, m.p0, {}};
            try {
                pr = m.prepare(values);
                st = {pr.q0, pr.p0, {}};
            } catch (const std::invalid_argument&) {
                // The default start is refused (a typed mechanism at q = 0, off its
                // constraints): the keys given replace the model's listed start instead.
                if (st.q0.size() != static_cast<std::size_t>(m.dim)) throw;
            }
            for (const auto& [i, v] : q0)
                st.q0[i] = v;
            for (const auto& [i, v] : p0)
                st.p0[i] = v;
            pr = m.prepare(values, st);
        }
        if (!m.integrator_note.empty()) {
            const auto i = static_cast<std::size_t>(m.parameter_index(m.integrator_parameter));
            std::vector<double> top = values;
            top[i] = m.parameters[i].upper;
            best = m.prepare(top);
        }
    } catch (const std::invalid_argument& e) {
        throw usage_error(e.what());
    }
    const std::string& own = pr.integrator.label; // "lgvi-4": the CSV's scheme is "lgvi"
    measured = own.empty() ? method_of(spec)
                           : method{own, pr.integrator.order, own.substr(0, own.find('-')),
                                    pr.integrator.order};
    const bool periodic = pr.period > 0.0 && m.steps_per_period > 0;
    span = periodic ? pr.period * o.periods : o.time > 0.0 ? o.time : m.time;
    long long lcm = 1;
    for (int n : steps) {
        lcm = std::lcm(lcm, static_cast<long long>(n));
        if (lcm > 1'000'000) throw usage_error("--steps: their least common multiple passes 1e6");
    }
    const long long per = periodic ? o.periods : 1;
    auto run = [&](const models::problem& p, const scheme_spec& sp, long long n) {
        const auto sim = p.simulate({sp, o.newton, span / static_cast<double>(n)});
        return record_run(*sim, static_cast<std::size_t>(n));
    };
    recorded_run reference;
    const long long fine = 2 * lcm * per;
    const int d = static_cast<int>(pr.q0.size()); // the parameters may set it (chain: n)
    std::vector<result> rs;
    for (int n : steps) {
        const recorded_run r = run(pr, spec, n * per);
        if (!r.has_exact && reference.state.empty())
            reference = best.simulate ? run(best, spec, fine)
                                      : run(pr, scheme_spec(scheme_kind::gauss, 8), fine);
        const long long stride = fine / (n * per);
        result e{n, {0.0, 0.0, 0.0}};
        const double e0 = r.energy.front(), scale = std::abs(e0) > 1e-12 ? std::abs(e0) : 1.0;
        for (std::size_t j = 0; j < r.energy.size(); ++j) {
            const double* x = r.state.data() + j * 2 * d;
            const double* ref =
                r.has_exact
                    ? r.exact.data() + j * 2 * d
                    : reference.state.data() +
                          static_cast<std::size_t>(static_cast<long long>(j) * stride) * 2 * d;
            for (int i = 0; i < d; ++i) {
                e.err[1] = std::max(e.err[1], std::abs(x[i] - ref[i]));
                e.err[0] = std::max(e.err[0], std::abs(x[d + i] - ref[d + i]));
            }
            e.err[2] = std::max(e.err[2], std::abs(r.energy[j] - e0) / scale);
        }
        rs.push_back(e);
        against = r.has_exact ? "the exact solution"
                              : (best.simulate ? best.integrator.label : "gauss-8") + " at " +
                                    std::to_string(fine) + " steps";
    }
    return rs;
}

void converge(const converge_options& o, const CLI::App& cmd) {
    const scheme_spec spec = make_spec(o.scheme);
    method measured = method_of(spec);
    const bool pendulum = o.model == "pendulum";
    std::shared_ptr<const models::model> model; // the other models'
    if (pendulum) {
        make_system(o.pendulum); // validates the parameters before any work
        if (!o.set.empty())
            throw usage_error("--set is for the other models; the pendulum's "
                              "parameters are --mass, --omega, --q0, --p0");
        if (!o.expression.lagrangian.empty())
            throw usage_error("--lagrangian is for --model lagrangian, not " + shown(o.model));
        if (!o.urdf.path.empty() || !o.urdf.torques.empty() || cmd.count("--base") > 0)
            throw usage_error(std::string(!o.urdf.path.empty()      ? "--urdf"
                                          : !o.urdf.torques.empty() ? "--torques"
                                                                    : "--base") +
                              " is for --model urdf, not " + shown(o.model));
    } else {
        for (const char* opt : {"--mass", "--omega", "--q0", "--p0"})
            if (cmd.count(opt) > 0)
                throw usage_error(std::string(opt) + " is the pendulum's; give " + o.model +
                                  "'s parameters and start with --set NAME=VALUE (NAME: a "
                                  "parameter, q0_I or p0_I)");
        model = model_of(o); // lagrangian: L parsed and differentiated once
        refuse_scheme(*model, cmd.count("--scheme") + cmd.count("--degree") > 0, "--set order=K");
    }
    file_roles roles;
    roles.add_output("--output", o.output);
    roles.add("--urdf", o.urdf.path);
    if (!o.plot.empty()) {
        check_pictures(o.plot);
        add_figure_files(roles, {".csv"}, o.plot);
    }
    roles.check();
    output_file out(o.output); // before the work: a conflict is refused at once
    std::vector<int> steps = o.steps;
    std::sort(steps.begin(), steps.end());
    if (std::adjacent_find(steps.begin(), steps.end()) != steps.end() || steps.size() < 2)
        throw usage_error("--steps needs at least two different step counts, e.g. 25,50,100,200");
    std::vector<result> rs;
    double period = 0.0;
    std::string against;
    if (pendulum) {
        period = make_exact(o.pendulum).period();
        for (int n : steps) {
            const error_norms e = paper::pendulum_errors(spec, n, o.periods, o.pendulum, o.newton);
            rs.push_back({n, {e.momentum, e.state, e.energy}});
        }
    } else {
        rs = model_errors(o, *model, spec, steps, period, against, measured);
    }
    out.write(o.format == "csv" ? csv_table(measured, rs)
                                : text_table(o, measured, period, rs, against));
    out.commit(); // the table is kept whatever becomes of the figure
    file_roles others;
    others.add_output("--output", o.output);
    if (!o.plot.empty()) render_figure(convergence_plot(measured, rs, o.model), o.plot, others);
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
        "  varsym converge --scheme lobatto --degree 2 --format csv\n"
        "  varsym converge --model kepler --set eccentricity=0.9 --scheme gauss --degree 2\n"
        "  varsym converge --model acrobot --set torque=1 --time 2 --steps 50,100,200,400\n"
        "  varsym converge --model lagrangian --lagrangian \"0.5*x_dot**2 - 0.25*x**4\" "
        "--coordinates x \\\n    --set q0_1=1 --time 10 --scheme gauss --degree 2\n"
        "  varsym converge --urdf ur5.urdf --set q0_2=-1 --time 1 --scheme gauss --degree 2\n");
    std::vector<std::string> names;
    for (const auto& m : models::registry())
        names.push_back(m.name);
    names.emplace_back("lagrangian");
    names.emplace_back("urdf");
    std::string list;
    for (const auto& n : names)
        list += (list.empty() ? "" : ", ") + n;
    cmd->add_option("--model", o->model,
                    "Model: " + list +
                        " (the models layer's; lagrangian: your L, from --lagrangian and its "
                        "options; urdf: your robot, from --urdf FILE; errors against the exact "
                        "solution where the "
                        "model has one, else against gauss-8 at twice the steps' common "
                        "multiple; the rigid bodies run their Lie group integrator, its order "
                        "by --set order=2|4|6, against order 6; their q: Euler angles, p: Pi)")
        ->check(CLI::IsMember(names))
        ->capture_default_str();
    cmd->add_option("--set", o->set,
                    "NAME=VALUE: a parameter of a model other than the pendulum, or its start "
                    "q0_I, p0_I (the others from the model's start, as in an ensemble's "
                    "members; repeat; 'varsym models')");
    add_expression_options(*cmd, o->expression);
    add_urdf_option(*cmd, o->urdf);
    cmd->add_option("--time", o->time,
                    "Span of a model without a period (default: the model's run length)")
        ->transform(positive_number);
    add_scheme_options(*cmd, o->scheme);
    add_pendulum_options(*cmd, o->pendulum);
    cmd->add_option("--steps", o->steps,
                    "Steps per period (over --time for a model without a period), "
                    "comma-separated")
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
    cmd->callback([o, cmd, &todo] {
        todo = [o, cmd] {
            // --lagrangian and --urdf imply their models.
            if (cmd->count("--model") == 0 && cmd->count("--lagrangian") > 0)
                o->model = "lagrangian";
            if (cmd->count("--model") == 0 && cmd->count("--urdf") > 0) o->model = "urdf";
            converge(*o, *cmd);
        };
    });
}

} // namespace varsym::cli
