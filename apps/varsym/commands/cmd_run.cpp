// apps/varsym/commands/cmd_run.cpp: `varsym run`, integrate a built-in model and stream its
// trajectory as CSV. The model-independent options live here; each model adds its own (models.hpp).
#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include <fcntl.h>
#include <unistd.h>

#include "commands/commands.hpp"
#include "models/models.hpp"
#include "models/registry_models.hpp"
#include "options/cli_common.hpp"
#include "options/shared_options.hpp"
#include "output/files.hpp"
#include "varsym/solvers/solver_name.hpp"

namespace varsym::cli {

namespace {

struct run_options {
    std::string model = "pendulum";
    scheme_options scheme;
    run_setup setup;
    std::string config;
    std::string resume;     ///< only to refuse --resume from a config file: main handles it
    std::string q0, p0, v0; ///< comma-separated lists (number_list)
    std::shared_ptr<parameter_options> parameters = std::make_shared<parameter_options>();
    std::vector<cli::model> models = make_models(parameters); ///< with this command line's
};

/// The files a run touches, checked against each other before anything is written: the output
/// and its partial file, the checkpoint and its temporary file (or OUTPUT.ckpt, where a failed
/// or interrupted run without --checkpoint saves its state), and the files it reads (the config
/// file, the robot's URDF).
void check_files(const run_setup& s, const std::string& config, const std::string& urdf) {
    const bool to_file = !s.output.empty() && s.output != "-";
    const file_kind out_kind = to_file ? kind_of(s.output) : file_kind::special;
    if (out_kind == file_kind::directory)
        throw usage_error("cannot write '" + s.output + "': it is a directory");
    const bool atomic = to_file && out_kind != file_kind::special;
    file_roles roles;
    roles.add_output("--output", s.output);
    if (atomic) roles.add("the output's partial file", s.output + ".part");
    const std::string ck = !s.checkpoint.empty() ? s.checkpoint : atomic ? s.output + ".ckpt" : "";
    const std::string ck_role = s.checkpoint.empty() ? "the failure checkpoint" : "--checkpoint";
    if (!ck.empty()) {
        roles.add(ck_role, ck);
        roles.add(ck_role + "'s temporary file", ck + ".tmp");
    }
    if (!config.empty()) roles.add("--config", config);
    roles.add("--urdf", urdf);
    if (!s.animate.empty()) add_animation_roles(roles, "--animate", s.animate);
    roles.check();
    if (s.checkpoint.empty() || s.resume) return;
    // A new run with --checkpoint CK.
    if (!atomic)
        throw usage_error("--checkpoint needs --output naming a regular file: a resumed run "
                          "appends its rows to that file");
    if (std::filesystem::exists(s.checkpoint) || std::filesystem::is_symlink(s.checkpoint))
        throw usage_error("checkpoint '" + s.checkpoint +
                          "' exists: continue its run with 'varsym run --resume " + s.checkpoint +
                          "', or remove it to start a new run");
    const std::string tmp = s.checkpoint + ".tmp";
    if (std::filesystem::exists(tmp) || std::filesystem::is_symlink(tmp))
        throw usage_error("'" + tmp + "' exists; varsym writes checkpoint '" + s.checkpoint +
                          "' through that name: move it away");
    // Can CK.tmp be created? (created exclusively, so removing it removes only our file)
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0)
        throw std::runtime_error("cannot write checkpoint '" + s.checkpoint + "': '" + tmp +
                                 "': " + std::strerror(errno));
    ::close(fd);
    ::unlink(tmp.c_str());
}

/// `varsym run --resume FILE`: the run's options came from the checkpoint; its output and
/// checkpoint are the files it named and FILE. Returns false if the run had already completed.
bool prepare_resume(run_setup& s, const run_context& ctx, const std::string& urdf) {
    s.resume = ctx.resume;
    s.output = ctx.resume->output;
    s.checkpoint = ctx.resume_path;
    namespace fs = std::filesystem;
    if (ctx.resume->step == ctx.resume->steps && !fs::exists(s.output + ".part") &&
        fs::exists(s.output)) {
        std::cerr << "varsym: the run of checkpoint '" << ctx.resume_path << "' is complete ("
                  << ctx.resume->steps << " steps); its rows are in " << s.output << '\n';
        return false;
    }
    check_files(s, "", urdf);
    return true;
}

/// The model's own options may not be combined with another model.
void check_model_options(const std::vector<model>& models, const model& chosen,
                         const CLI::App& cmd) {
    for (const model& other : models) {
        if (other.name == chosen.name) continue;
        for (const std::string& opt : other.options) {
            const bool own = std::find(chosen.options.begin(), chosen.options.end(), opt) !=
                             chosen.options.end();
            if (!own && cmd.count(opt) > 0)
                throw usage_error(opt + " is a parameter of --model " + other.name +
                                  ", not of --model " + chosen.name + " (see 'varsym models')");
        }
    }
}

void run(run_options& o, const CLI::App& cmd, const run_context& ctx) {
    if (cmd.count("--lagrangian") > 0 && cmd.count("--model") == 0) o.model = "lagrangian";
    if (cmd.count("--urdf") > 0 && cmd.count("--model") == 0) o.model = "urdf";
    const auto it = std::find_if(o.models.begin(), o.models.end(),
                                 [&](const model& m) { return m.name == o.model; });
    check_model_options(o.models, *it, cmd);
    if (it->name != "urdf") {
        if (cmd.count("--mesh-path") > 0)
            throw usage_error("--mesh-path finds a URDF robot's meshes (--urdf FILE); --model " +
                              it->name + " has none");
        const models::model* drawn = models::find(it->name);
        if (cmd.count("--animate") > 0 && (drawn == nullptr || !drawn->drawing))
            throw usage_error("--animate: --model " + it->name + " has no 3-D figure; " +
                              drawn_models());
    }
    if (!o.setup.animate.empty() && (!o.setup.checkpoint.empty() || ctx.resume))
        throw usage_error("--animate keeps its frames in memory, which a resumed run would "
                          "not have: drop --checkpoint, or animate the finished CSV with "
                          "'varsym animate'");
    o.setup.spec = make_spec(o.scheme);
    o.setup.scheme_given = cmd.count("--scheme") + cmd.count("--degree") > 0;
    o.setup.by_time = cmd.count("--time") > 0;
    o.setup.periods_given = cmd.count("--periods") > 0;
    o.setup.args = ctx.args;
    o.setup.q0 = parse_number_list(o.q0);
    o.setup.p0 = parse_number_list(o.p0);
    o.setup.v0 = parse_number_list(o.v0);
    const std::string urdf =
        cmd.count("--urdf") > 0 ? cmd.get_option("--urdf")->as<std::string>() : "";
    if (ctx.resume) {
        if (!prepare_resume(o.setup, ctx, urdf)) return;
    } else {
        if (!o.resume.empty())
            throw usage_error(
                "--resume must be given on the command line, as 'varsym run --resume FILE'");
        check_files(o.setup, o.config, urdf);
    }
    // Neither --checkpoint-every nor --checkpoint-seconds (a new or a resumed run): every 60 s.
    if (!o.setup.checkpoint.empty() && o.setup.checkpoint_every == 0 &&
        o.setup.checkpoint_seconds == 0.0)
        o.setup.checkpoint_seconds = 60.0;
    it->run(o.setup);
}

std::string model_names(const std::vector<model>& models) {
    std::string names;
    for (const model& m : models)
        names += (names.empty() ? "" : ", ") + m.name;
    return names;
}

} // namespace

void add_run_command(CLI::App& app, action& todo, run_context& ctx) {
    auto o = std::make_shared<run_options>();
    auto* cmd = app.add_subcommand(
        "run",
        "Integrate a model (default: the paper's pendulum) and stream its trajectory as CSV");
    std::vector<std::string> names;
    for (const model& m : o->models)
        names.push_back(m.name);
    cmd->footer(
        std::string(pendulum_help) + "\n" +
        "Models (parameters and conserved quantities: 'varsym models'): " + model_names(o->models) +
        ".\n"
        "Columns (pendulum: step,t,q,p,energy,q_exact,p_exact): step,t, then q,p for d = 1 or\n"
        "q_1..q_d,p_1..p_d, then energy, the model's conserved quantities by name\n"
        "(angular_momentum, p_phi, p_psi), then the exact solution where the model has one\n"
        "(q_exact,p_exact or q_1_exact,...); 17 significant digits.\n"
        "A file given by --output is written as FILE.part and renamed when the run completes;\n"
        "a run whose Newton iteration fails keeps FILE.part with the rows already computed.\n"
        "Long runs: --checkpoint CK writes the complete state (q, p, compensated-summation\n"
        "carries, step, options) to CK atomically; after a crash or kill, 'varsym run --resume "
        "CK'\n"
        "truncates FILE.part to the rows CK covers and continues: the result is byte-identical\n"
        "to a run that never stopped. A failed step leaves CK (or FILE.ckpt) at the last good\n"
        "state and exits 3 with a safer step size.\n"
        "--config FILE reads options from a TOML file: each key is a long option of this\n"
        "command without '--' (model = \"kepler\", eccentricity = 0.3, q0 = [1.0, 0.0], stats =\n"
        "true); options on the command line take precedence over the file.\n\n"
        "Examples:\n"
        "  varsym run                                   # Simpson, pendulum, one period, 50 steps\n"
        "  varsym run --scheme newmark --steps-per-period 10 --periods 5 --output traj.csv\n"
        "  varsym run --time 100 --steps 100000 --every 1000 --q0 3.0\n"
        "  varsym run --model kepler --eccentricity 0.9 --periods 10 --steps-per-period 400\n"
        "  varsym run --model heavy-top --scheme gauss --degree 3 --periods 5\n"
        "  varsym run --model double-pendulum --time 20 --steps 20000 --every 100 -o arm.csv\n"
        "  varsym run --lagrangian \"0.5*th_dot**2 + 9.81*cos(th)\" --coordinates th --q0 1\n"
        "  varsym run --urdf ur5.urdf --scheme gauss --degree 2 --time 2 --steps 2000\n"
        "  varsym run --config kepler.toml\n"
        "  varsym run --time 1e5 --steps 100000000 --every 10000 -o long.csv --checkpoint "
        "long.ckpt\n"
        "  varsym run --resume long.ckpt\n");
    cmd->add_option("--model", o->model, "The system to integrate: " + model_names(o->models))
        ->check(CLI::IsMember(names))
        ->capture_default_str();
    add_scheme_options(*cmd, o->scheme);
    run_setup& s = o->setup;
    auto* spp =
        cmd->add_option("--steps-per-period", s.steps_per_period,
                        "Steps per period of the model (pendulum: nonlinear period; kepler: "
                        "orbit; default: the model's, see 'varsym models')")
            ->transform(positive_integer);
    auto* periods = cmd->add_option("--periods", s.periods, "Number of periods to integrate")
                        ->transform(positive_number)
                        ->capture_default_str();
    auto* time = cmd->add_option("--time", s.time,
                                 "Final time T [s] (with --steps; instead of "
                                 "--periods)")
                     ->transform(positive_number);
    auto* steps = cmd->add_option("--steps", s.steps, "Number of steps over --time")
                      ->transform(positive_integer);
    time->needs(steps)->excludes(spp)->excludes(periods);
    steps->needs(time);
    cmd->add_option("--every", s.every,
                    "Write every E-th step and always the last; 0 writes only the final row")
        ->transform(non_negative_integer)
        ->capture_default_str();
    cmd->add_option("--output,-o", s.output, "CSV file to write (default: standard output)");
    cmd->add_option("--q0", o->q0,
                    "Initial configuration q(0), d values separated by commas "
                    "(default: the model's)")
        ->check(number_list)
        ->type_name(list_type_name);
    auto* p0 = cmd->add_option("--p0", o->p0, "Initial momenta p(0) = dL/dqdot, d values")
                   ->check(number_list)
                   ->type_name(list_type_name);
    cmd->add_option("--v0", o->v0, "Initial velocities dq/dt(0), d values (instead of --p0)")
        ->check(number_list)
        ->type_name(list_type_name)
        ->excludes(p0);
    cmd->add_option(
           "--newton-tol", s.newton.tolerance,
           "Newton stops when its update is below this times the size of the step's increment")
        ->transform(positive_number)
        ->capture_default_str();
    cmd->add_option("--newton-max-iter", s.newton.max_iterations,
                    "Newton iterations allowed per step before the run stops with an error")
        ->transform(positive_integer)
        ->capture_default_str();
    cmd->add_option_function<std::string>(
           "--iteration",
           [&s](const std::string& v) { s.newton.iteration = named(iteration_names, v).value(); },
           "How a step is solved by lobatto-s (s >= 3) and gauss-s (s >= 2) on the separable "
           "models, and by every scheme on the general engine's (double-pendulum, heavy-top, "
           "--urdf robots, expressions): newton (exact Jacobian each iteration; the default on "
           "the general engine's models with exact derivatives, except on robots of about 10 "
           "joints and more with a fixed or planar base (gauss-2, Simpson; fewer at higher "
           "degrees, about 36 with gauss-1), where the default takes newton or "
           "articulated step by step, whichever a model of their costs and the updates counted "
           "say is cheaper), "
           "simplified (one Jacobian kept across steps; first derivatives only in its sweeps; "
           "the default of double-pendulum and heavy-top, whose derivatives are automatic), "
           "fixed-point (the Jacobian's mass term alone; the default of the separable models, "
           "measured fastest there) or articulated (robots from --urdf with a fixed or planar "
           "base: the mass term at the step's midpoint, solved in O(n) by the articulated-body "
           "algorithm; faster than newton on long chains, docs/robots.md). All stop at the "
           "same round-off floor; the last three hand a step to newton where they diverge")
        ->check(CLI::IsMember({"newton", "simplified", "fixed-point", "articulated"}));
    cmd->add_option_function<std::string>(
           "--predictor",
           [&s](const std::string& v) { s.newton.predictor = named(predictor_names, v).value(); },
           "Where a step's iteration starts: taylor (from q and p; default), previous (the "
           "previous step's polynomial continued) or forces (the previous step's forces "
           "continued: fewest iterations, 10-30 % faster, round-off growing as sqrt(t) instead "
           "of repeating). The last two are kept in checkpoints; separable models only")
        ->check(CLI::IsMember({"taylor", "previous", "forces"}));
    cmd->add_option("--max-energy-error", s.max_energy_error,
                    "Stop the run (exit 4, keeping its rows) when the relative energy error "
                    "|E-E0|/|E0| passes this bound; 0: never. Default: 100 (h omega)^order at "
                    "the start, between 0.01 and 0.5")
        ->transform(non_negative_number);
    auto* animate = cmd->add_option(
        "--animate", s.animate,
        "urdf, arm, double-pendulum, heavy-top, top, pendulum-3d, rigid-body, "
        "spherical-pendulum: also write the motion as a 3-D animation, one self-contained HTML "
        "page that any browser opens offline (docs/robots.md)");
    cmd->add_option("--animate-fps", s.animate_fps,
                    "Frames per second of simulated time that --animate keeps (linear "
                    "interpolation between them); 0 keeps every step")
        ->transform(non_negative_number)
        ->capture_default_str()
        ->needs(animate);
    cmd->add_option("--mesh-path", s.mesh_path,
                    "Directories where --animate looks for the URDF's meshes first: "
                    "package://PKG/PATH is DIR/PKG/PATH or DIR/PATH (then beside the URDF and "
                    "in its parent directories)")
        ->needs(animate);
    cmd->add_flag("--stats", s.stats, "Print Newton iteration statistics to standard error");
    cmd->add_flag("--quiet,-q", s.quiet,
                  "No progress line (shown on standard error when it is a terminal, never on "
                  "standard output)");
    cmd->add_option("--config", o->config, "TOML file of options (see below)");
    for (const model& m : o->models)
        m.add_options(*cmd);
    o->parameters->add(*cmd); // the registry models' parameters, after the mechanisms' options
    auto* ckpt = cmd->add_option("--checkpoint", s.checkpoint,
                                 "Write the run's complete state to FILE (atomically) every "
                                 "--checkpoint-every steps or --checkpoint-seconds (default 60 s), "
                                 "at the end, and at a failed step; needs --output");
    cmd->add_option("--checkpoint-every", s.checkpoint_every, "Checkpoint every S steps")
        ->transform(positive_integer)
        ->needs(ckpt);
    cmd->add_option("--checkpoint-seconds", s.checkpoint_seconds,
                    "Checkpoint every T seconds of wall-clock time")
        ->transform(positive_number)
        ->needs(ckpt);
    cmd->add_option("--resume", o->resume,
                    "Continue the run of checkpoint FILE to its end: 'varsym run --resume FILE' "
                    "alone, the options are those of the checkpointed run");
    cmd->callback([o, cmd, &todo, &ctx] { todo = [o, cmd, &ctx] { run(*o, *cmd, ctx); }; });
}

} // namespace varsym::cli
