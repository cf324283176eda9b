// apps/varsym/commands/cmd_optimize.cpp: `varsym optimize`: the optimal control of a model with
// control inputs by discrete mechanics (varsym/optimize/transcription.hpp), solved by IPOPT
// (varsym::optimal). Writes the nodes' states and costates, and the controls; prints a progress
// line per iteration; Ctrl-C stops the solver and keeps the last iterate.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <memory>
#include <span>

#include "commands/commands.hpp"
#include "commands/optimize_problem.hpp"
#include "models/registry_models.hpp"
#include "options/shared_options.hpp"
#include "output/files.hpp"
#include "output/plot.hpp"
#include "output/signals.hpp"
#include "varsym/optimize/model.hpp"

namespace varsym::cli {

namespace {

std::string node_rows(const optimal::trajectory& path) {
    const auto d = path.q.rows();
    std::string out = "t";
    for (const char* name : {"q", "v", "p", "lambda"})
        for (Eigen::Index i = 1; i <= d; ++i) {
            // Appended piece by piece: GCC 12 sees a false -Wstringop-overflow in the
            // concatenation "," + std::string(name) + … at -O2.
            out += ',';
            out += name;
            out += std::to_string(i);
        }
    out += '\n';
    for (Eigen::Index n = 0; n < path.node_times.size(); ++n) {
        append_number(out, path.node_times(n));
        for (const auto* m : {&path.q, &path.v, &path.p, &path.costate})
            for (Eigen::Index i = 0; i < d; ++i) {
                out += ',';
                append_number(out, (*m)(i, n));
            }
        out += '\n';
    }
    return out;
}

std::string control_rows(const optimal::trajectory& path) {
    std::string out = "t";
    for (Eigen::Index i = 1; i <= path.u.rows(); ++i)
        out += ",u" + std::to_string(i);
    out += '\n';
    for (Eigen::Index c = 0; c < path.control_times.size(); ++c) {
        append_number(out, path.control_times(c));
        for (Eigen::Index i = 0; i < path.u.rows(); ++i) {
            out += ',';
            append_number(out, path.u(i, c));
        }
        out += '\n';
    }
    return out;
}

/// The poses of `m` at nine nodes evenly spread over the motion, each shifted right so that
/// its first point sits at k times the widest pose's width: "x,y" rows, a blank row between.
std::string pose_rows(const models::model& m, std::span<const double> values,
                      const models::lists& lists, const optimal::trajectory& path) {
    std::vector<std::vector<double>> poses;
    const auto n = path.q.cols() - 1;
    for (int k = 0; k <= 8; ++k) {
        const Eigen::VectorXd q = path.q.col(n * k / 8);
        poses.push_back(m.pose(values, lists, std::span<const double>(q.data(), q.size())));
    }
    double width = 0.0;
    for (const auto& p : poses)
        for (std::size_t i = 0; i < p.size(); i += 2)
            width = std::max(width, std::abs(p[i] - p[0]));
    std::string out = "x,y\n";
    for (std::size_t k = 0; k < poses.size(); ++k) {
        for (std::size_t i = 0; i < poses[k].size(); i += 2) {
            append_number(out, poses[k][i] - poses[k][0] + 2.4 * width * static_cast<double>(k));
            out += ',';
            append_number(out, poses[k][i + 1]);
            out += '\n';
        }
        out += '\n';
    }
    return out;
}

/// The figure of `--plot`: the coordinates over time, the controls at the quadrature points,
/// and a strip of poses where the model draws itself.
figure optimize_plot(const models::model& m, std::span<const double> values,
                     const models::lists& lists, const optimal::trajectory& path) {
    figure fig;
    fig.data = {{".nodes.csv", node_rows(path)}, {".controls.csv", control_rows(path)}};
    const bool poses = static_cast<bool>(m.pose);
    if (poses) fig.data.emplace_back(".poses.csv", pose_rows(m, values, lists, path));
    const auto d = path.q.rows(), inputs = path.u.rows();
    std::string s = script_preamble(900, poses ? 820 : 600);
    s += "set multiplot layout " + std::string(poses ? "3" : "2") + ",1 title '" + m.name +
         ": optimal motion (" + path.scheme.label() +
         ", N = " + std::to_string(path.node_times.size() - 1) +
         ")'\nset key outside right\n"
         "set xlabel 't [s]'\nset ylabel 'q'\nplot ";
    for (Eigen::Index i = 0; i < d; ++i)
        s += std::string(i ? ", " : "") + "stem.'.nodes.csv' using 1:" + std::to_string(i + 2) +
             " skip 1 with lines lw 2 title 'q" + std::to_string(i + 1) + "'";
    s += "\nset ylabel 'u'\nplot ";
    for (Eigen::Index i = 0; i < inputs; ++i)
        s += std::string(i ? ", " : "") + "stem.'.controls.csv' using 1:" + std::to_string(i + 2) +
             " skip 1 with linespoints pt 7 ps 0.4 lw 1.5 title 'u" + std::to_string(i + 1) + "'";
    if (poses)
        s += "\nunset xlabel\nset ylabel 'poses, t = 0 … T'\nunset key\nunset xtics\n"
             "set size ratio -1\nset offsets 0.3, 0.3, 0.3, 0.3\nplot stem.'.poses.csv' using 1:2 "
             "skip 1 with linespoints lw 2 "
             "pt 7 ps 0.6 lc rgb '#1f5fa8'";
    s += "\nunset multiplot\n";
    fig.script = s;
    return fig;
}

void optimize(const optimize_options& o) {
    if (o.model.empty())
        throw usage_error("optimize needs --model NAME, --urdf FILE or --lagrangian EXPR");
    std::vector<double> values;
    const auto model = optimize_model(o, values);
    const models::model& m = *model;
    // Another model's parameter, or one only a simulation uses (the parameter that holds the
    // input constant, which the optimiser computes; a controller's gains) would be silently
    // dropped: refused, as `run` refuses them.
    for (const std::string& name : o.parameters->given_names()) {
        const bool own = std::any_of(m.parameters.begin(), m.parameters.end(),
                                     [&](const auto& p) { return p.option_name() == name; }) ||
                         std::any_of(m.lists.begin(), m.lists.end(),
                                     [&](const auto& l) { return l.option_name() == name; });
        if (!own)
            throw usage_error("--" + name + " is not a parameter of " + m.name +
                              " (see 'varsym models')");
        for (std::string only : m.simulation_only)
            if (std::replace(only.begin(), only.end(), '_', '-'); only == name)
                throw usage_error(
                    "--" + name + " is a simulation's parameter of " + m.name +
                    (name == "contact" || name == "friction" || name == "ground-height" ||
                             name == "ground-slope" || name == "boxes"
                         ? ": optimal control has no contact (its transcription keeps to "
                           "motions in free space)"
                         : "; optimize computes the inputs (bound them with --max-control)"));
    }
    const models::lists lists = o.parameters->lists(m);
    optimal::model_request request = request_of(o, m, values, lists);
    // Options that do not combine (the service refuses them too, without the options' names).
    const optimal::control_problem& p = request.problem;
    if (request.solver.hessian == optimal::hessian_kind::exact && p.cost.invariant != 0.0)
        throw usage_error("--hessian exact: the invariant cost has no exact Hessian (it would "
                          "need L's fourth derivatives); use automatic or limited-memory");
    file_roles roles;
    if (!o.config.empty()) roles.add("--config", o.config);
    roles.add("--urdf", o.urdf);
    roles.add("--ipopt-options", o.ipopt_options);
    roles.add_output("--output", o.output);
    if (!o.controls.empty()) roles.add("--controls", o.controls);
    if (!o.animate.empty()) {
        if (m.name != "urdf" && !m.drawing)
            throw usage_error("--animate: " + m.name + " has no 3-D figure; " + drawn_models(true));
        if (m.name != "urdf" && !o.mesh_path.empty())
            throw usage_error("--mesh-path finds a URDF robot's meshes (--urdf FILE); " + m.name +
                              " has none");
        add_animation_roles(roles, "--animate", o.animate);
        animation_check(o.animate);
    }
    check_ipopt_options(o.ipopt_options, roles);
    file_roles others = roles;
    if (!o.plot.empty()) {
        check_pictures(o.plot);
        add_figure_files(roles, {".nodes.csv", ".controls.csv", ".poses.csv"}, o.plot);
    }
    roles.check();
    install_signal_handlers();
    request.solver.progress = [&](const optimal::iteration& it) {
        if (!o.quiet)
            std::fprintf(stderr,
                         "varsym optimize: iteration %4d  cost %.10g  infeasibility %.2e%s\n",
                         it.number, it.cost, it.primal_infeasibility,
                         it.restoration ? "  (restoration)" : "");
        return pending_signal() == 0;
    };
    request.solver.stop = [] { return pending_signal() != 0; }; // also in IPOPT's derivative test
    if (!o.quiet)
        request.level = [](int n) { std::fprintf(stderr, "varsym optimize: N = %d\n", n); };
    // The files are made once the problem is known to be solvable (no file left on bad input).
    std::unique_ptr<output_file> states, inputs_file;
    int sig = 0;          // a signal that stopped the solve
    request.ready = [&] { // the problem is sound: the files, and signals deferred to the solver
        states = std::make_unique<output_file>(o.output);
        if (!o.controls.empty()) inputs_file = std::make_unique<output_file>(o.controls);
        set_signal_polling(true, "IPOPT's current iteration finishes");
    };
    request.solved = [&] {
        sig = pending_signal();
        set_signal_polling(false);
    };
    optimal::model_outcome out;
    try {
        out = optimal::optimize(m, values, lists, std::move(request));
    } catch (const std::invalid_argument& e) {
        throw usage_error(e.what());
    }
    const optimal::trajectory& path = out.path;
    states->write(node_rows(path));
    states->commit();
    if (inputs_file) {
        inputs_file->write(control_rows(path));
        inputs_file->commit();
    }
    if (!o.plot.empty()) render_figure(optimize_plot(m, values, lists, path), o.plot, others);
    if (!o.animate.empty())
        write_optimal_animation(path, m, values, lists, m.name == "urdf" ? o.urdf : "", o.animate,
                                o.animate_fps, o.mesh_path, o.quiet);
    const optimal::nlp_result& r = out.result;
    std::fprintf(stderr,
                 "varsym optimize: %s (%s) after %d iterations in %.3g s: cost %.12g, "
                 "T %.12g, max |g| %.1e, closure (general engine replay) %.1e\n",
                 optimal::status_name(r.verdict), r.message.c_str(), r.iterations, out.seconds,
                 path.cost, path.node_times(path.node_times.size() - 1), out.residual(),
                 out.check.closure.error);
    std::fputs(reach_report(o, out).c_str(), stderr);
    if (out.check.velocity_excess > 1e-6)
        std::fprintf(stderr,
                     "varsym optimize: the node velocities exceed the velocity limits by up to "
                     "%.2g %% (the limits hold on the steps' polynomials): take more --steps\n",
                     100.0 * out.check.velocity_excess);
    if (out.check.controls_at_bound > 0)
        std::fprintf(stderr,
                     "varsym optimize: bound active: |u| = %s at %d of %lld control values\n",
                     std::isfinite(o.max_control) ? "--max-control" : "its URDF effort",
                     out.check.controls_at_bound, static_cast<long long>(path.u.size()));
    if (sig != 0)
        throw interrupted(sig, "varsym optimize: stopped by signal; the files hold the last "
                               "iterate");
    switch (out.verdict) {
    case optimal::verdict::solved:
        return;
    case optimal::verdict::not_solved:
    case optimal::verdict::interrupted:
        throw numerical_error("varsym optimize: " + out.message +
                              "; the files hold the last iterate");
    case optimal::verdict::not_trusted:
    case optimal::verdict::time_bound:
        throw numerical_error("varsym optimize: " + out.message);
    }
}

} // namespace

void add_optimize_command(CLI::App& app, action& todo) {
    auto o = std::make_shared<optimize_options>();
    auto* cmd = app.add_subcommand(
        "optimize", "Optimal control of a model with inputs (discrete mechanics, IPOPT)");
    cmd->footer(
        "Finds the controls u(t) that take the model from (--from, --from-velocity) at t = 0 to\n"
        "(--to, --to-velocity) at t = --time at the least cost (--cost: by default the effort,\n"
        "the integral of u^2/2), by\n"
        "discrete mechanics and optimal control: the scheme's discrete Lagrange-d'Alembert\n"
        "equations are the constraints of a sparse nonlinear program solved by IPOPT (exact\n"
        "first and second derivatives). Models with inputs: acrobot (elbow torque), arm (joint\n"
        "torques), cart-pole (push on the cart), pendulum (torque at the pivot), a URDF robot\n"
        "(--urdf: its actuated joints' torques within the URDF's limits) and a typed Lagrangian\n"
        "(--lagrangian with --inputs). Writes the nodes (t, q, v, p and the costates lambda of\n"
        "the momenta) to --output, and u at each step's quadrature points to --controls. The\n"
        "optimum found is local: another --scheme or --steps can reach another one.\n"
        "--free-end frees final coordinates; --terminal-weight pulls them towards --to.\n"
        "A robot's link can be sent to a target pose instead: --reach LINK --reach-position.\n"
        "Exit codes: 0 solved; 2 bad input; 3 not solved (infeasible, iteration limit: the\n"
        "files hold the last iterate) or not trusted (the simulator's replay of the controls\n"
        "misses the optimal motion: steps too coarse); 130/143 stopped by SIGINT/SIGTERM (last\n"
        "iterate kept).\n"
        "See docs/optimal_control.md.");
    cmd->add_option("--model", o->model,
                    "A model with control inputs: acrobot, arm, cart-pole, pendulum; urdf (implied "
                    "by --urdf) or lagrangian (implied by --lagrangian)");
    cmd->add_option("--urdf", o->urdf,
                    "A robot's URDF file: the inputs are the torques (forces) of its actuated "
                    "joints (URDF effort > 0), bounded by their efforts; the joints' position "
                    "and velocity limits bound q and q' (--no-limits drops them)");
    cmd->add_flag("--no-limits", o->no_limits,
                  "urdf: leave the URDF's joint position, velocity and effort limits out "
                  "(--max-control, --max-velocity still apply)");
    cmd->add_option("--lagrangian", o->lagrangian,
                    "A Lagrangian L typed as an expression (Python syntax) over --coordinates, "
                    "their velocities NAME_dot, t and --parameters; its inputs: --inputs");
    cmd->add_option("--coordinates", o->coordinates,
                    "lagrangian: the coordinates' names, comma-separated")
        ->capture_default_str();
    cmd->add_option("--parameters", o->expression_parameters,
                    "lagrangian: parameters of the expression, NAME=VALUE,...");
    cmd->add_option("--inputs", o->inputs,
                    "lagrangian: the coordinates the inputs act on, one input each (a generalized "
                    "force in the units of dL/dq there), e.g. th1,th2");
    cmd->add_option(
        "--constraints", o->constraints,
        "lagrangian: holonomic constraints g(q) = 0, comma-separated, e.g. x**2+y**2-1");
    cmd->add_option("--time", o->time, "Horizon T [s]")->required()->transform(positive_number);
    cmd->add_option("--steps", o->steps, "Steps N of h = T/N")
        ->transform(positive_integer)
        ->capture_default_str();
    add_scheme_options(*cmd, o->scheme);
    add_velocity_and_reach_options(*cmd, *o);
    cmd->add_option("--from", o->from, "Start position q(0), one value per coordinate")
        ->required()
        ->transform(number_list)
        ->type_name(list_type_name);
    cmd->add_option("--to", o->to, "Final position q(T) (with --reach: its first guess)")
        ->transform(number_list)
        ->type_name(list_type_name);
    cmd->add_option("--from-velocity", o->from_velocity, "Start velocity (default: rest)")
        ->transform(number_list)
        ->type_name(list_type_name);
    cmd->add_option("--to-velocity", o->to_velocity, "Final velocity (default: rest)")
        ->transform(number_list)
        ->type_name(list_type_name);
    cmd->add_option("--free-end", o->free_end,
                    "Final coordinates left free instead of fixed: q1, q2, ... (positions) and v1, "
                    "v2, ... (velocities), e.g. q1,v1; their --to / --to-velocity values are then "
                    "the terminal cost's targets");
    cmd->add_option("--terminal-weight", o->terminal_weight,
                    "Terminal cost weights, one per --free-end entry in its order: w (x(T) - "
                    "target)^2/2 each (default 0: free and unweighted)")
        ->transform(number_list)
        ->type_name(list_type_name);
    cmd->add_option("--max-control", o->max_control,
                    "Bound |u| <= U on every input (default: none)")
        ->transform(positive_number);
    cmd->add_option(
           "--cost", o->cost,
           "The running cost, terms with optional weights: effort (u^2/2), invariant "
           "(tau^T M^-1 tau/2, tau the inputs' generalized force), power (sum |tau_i "
           "q'_i|, smoothed), time (the horizon itself: minimum time, --time its first "
           "guess; needs --max-control or a robot's URDF efforts), e.g. power,effort=0.01 or "
           "time,effort=0.001")
        ->capture_default_str();
    cmd->add_option("--hessian", o->hessian,
                    "automatic (exact where there is one; with --cost time, limited memory again "
                    "where the exact one fails), exact (L's third derivatives) or limited-memory")
        ->check(CLI::IsMember({"automatic", "exact", "limited-memory"}))
        ->capture_default_str();
    cmd->add_option("--max-iterations", o->max_iterations, "IPOPT's iteration limit")
        ->transform(positive_integer)
        ->capture_default_str();
    cmd->add_option("--threads", o->threads,
                    "Threads for a URDF robot's step derivatives, at most 4096 (default 0: one "
                    "per CPU this process may use, fewer on small problems; 1: none; one with "
                    "--cost time; the same answer)")
        ->transform(non_negative_integer)
        ->check(CLI::Range(0, 4096));
    cmd->add_option("--refine", o->refine,
                    "Mesh refinement: solve with N/2^K steps first, then double N up to --steps, "
                    "each level started from the previous solution")
        ->check(CLI::Range(0, 10))
        ->capture_default_str();
    cmd->add_option("--output,-o", o->output, "CSV of the nodes (default: standard output)");
    cmd->add_option("--controls", o->controls, "CSV of the controls at the quadrature points");
    cmd->add_option("--plot", o->plot,
                    "Picture of the motion, .png or .svg: the coordinates, the controls and a "
                    "strip of poses (data and gnuplot script kept beside it); repeat for both "
                    "formats");
    auto* animate = cmd->add_option(
        "--animate", o->animate,
        "urdf, arm: also write the optimal motion as a 3-D animation, one self-contained "
        "HTML page that any browser opens offline (docs/robots.md)");
    cmd->add_option("--animate-fps", o->animate_fps,
                    "Frames per second of --animate, on the steps' polynomials (0: the nodes)")
        ->transform(non_negative_number)
        ->capture_default_str()
        ->needs(animate);
    cmd->add_option("--mesh-path", o->mesh_path,
                    "Directories where --animate looks for the URDF's meshes first: "
                    "package://PKG/PATH is DIR/PKG/PATH or DIR/PATH")
        ->needs(animate);
    cmd->add_flag("--quiet", o->quiet, "No progress line per iteration");
    cmd->add_option("--ipopt-options", o->ipopt_options,
                    "IPOPT options file (IPOPT's ipopt.opt format: 'name value' lines), read "
                    "after and over varsym's options. IPOPT reads no other (./ipopt.opt is "
                    "ignored). Whatever it loosens, the answer must still pass varsym's own "
                    "check (the equations, bounds and boundary values, and the replay) to exit 0");
    cmd->add_option("--config", o->config,
                    "TOML file of options: each key a long option without '--' (model = "
                    "\"acrobot\", to = [3.14159, 0], refine = 2); the command line wins");
    // Only the parameters of the models with inputs: the others' would be refused anyway.
    o->parameters->add(*cmd, [](const models::model& m) { return m.has_inputs(); });
    hide_simulation_only(*cmd);
    cmd->callback([o, cmd, &todo] {
        if (cmd->count("--model") == 0) {
            if (!o->urdf.empty()) o->model = "urdf";
            if (!o->lagrangian.empty()) o->model = "lagrangian";
        }
        o->typed_options.clear();
        for (const char* name : {"--coordinates", "--parameters", "--inputs", "--constraints"})
            if (cmd->count(name) > 0) o->typed_options.emplace_back(name);
        todo = [o] { optimize(*o); };
    });
}

} // namespace varsym::cli
