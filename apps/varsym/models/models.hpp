// apps/varsym/models/models.hpp: the built-in models of `varsym run --model NAME`: their options,
// descriptions for `varsym models`, and how each runs.
#pragma once

#include <cmath>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "options/cli_common.hpp"
#include "output/checkpoint.hpp"
#include "varsym/contact/geometry.hpp"
#include "varsym/models/model.hpp"
#include "varsym/multibody/tree.hpp"
#include "varsym/schemes/scheme_kind.hpp"

namespace varsym::optimal {
struct trajectory;
}

namespace varsym::cli {

class file_roles;

/// The frames of `varsym run --animate`: the coordinates (the first `width` state values, or
/// simulation::q where `coordinates` is set) at the first state at or after each multiple of
/// `every` seconds of simulated time from the start (models::animation_rows' rule), and the
/// last state.
struct frame_recorder {
    double every = 0.0;
    int width = 0;
    bool coordinates = false; ///< record q (a built-in model's figure takes its coordinates)
    /// Per frame, the contact forces of the step that ended there (a robot in contact): six
    /// numbers each, the point [m] and the force [N] (the impulse over h), in the world frame.
    std::vector<std::vector<double>> forces;
    std::vector<double> t, q;
    double next = 0.0; ///< the time of the next frame due
    [[nodiscard]] bool due(double time) const { return t.empty() || time >= next - 1e-9 * every; }
    void add(double time, std::span<const double> state) {
        if (every > 0.0)
            next =
                (t.empty() ? time : t.front()) +
                (std::floor((time - (t.empty() ? time : t.front())) / every + 1e-6) + 1.0) * every;
        t.push_back(time);
        q.insert(q.end(), state.begin(), state.begin() + width);
    }
};

/// What `varsym run` resolved from its model-independent options.
struct run_setup {
    scheme_spec spec;
    newton_options newton;
    bool by_time = false;           ///< --time and --steps given (else steps per period)
    long long steps_per_period = 0; ///< 0: the model's default
    double periods = 1.0;
    double time = 0.0;
    long long steps = 0;
    long long every = 1;
    std::string output;
    bool stats = false;
    bool quiet = false;             ///< no progress line
    std::vector<double> q0, p0, v0; ///< initial state; empty: the model's default
    bool periods_given = false;
    std::string checkpoint;          ///< --checkpoint FILE, or the file of --resume
    long long checkpoint_every = 0;  ///< checkpoint every this many steps (0: by time only)
    double checkpoint_seconds = 0.0; ///< and every this many seconds of wall time (0: never)
    double max_energy_error = -1.0;  ///< stop (exit 4) past it; < 0: the default, 0: never
    std::vector<std::string> args;   ///< the run's arguments, kept in its checkpoints
    std::shared_ptr<const cli::checkpoint> resume; ///< the checkpoint a resumed run continues
    std::vector<checkpoint::input_file> inputs;    ///< the model's files, kept in checkpoints
    bool scheme_given = false; ///< --scheme or --degree was set (the rigid bodies refuse them)
    std::string animate;       ///< --animate FILE: the robot's motion as an HTML page
    double animate_fps = 60.0; ///< --animate-fps
    std::vector<std::string> mesh_path;     ///< --mesh-path
    std::shared_ptr<frame_recorder> frames; ///< set by the model that draws the animation
    /// The model's own integrator where it is not `spec` (the rigid bodies: "lgvi-4"; from
    /// models::problem::integrator).
    std::string method;
    int method_order = 0;      ///< its order
    double method_limit = 0.0; ///< the largest h·ω its steps are defined at (advice only)

    /// The integrator as messages and checkpoints name it, and its order.
    [[nodiscard]] std::string label() const { return method.empty() ? spec.label() : method; }
    [[nodiscard]] int order() const { return method.empty() ? spec.order() : method_order; }
};

/// A built-in model. Its parameters are options of `varsym run` that only it accepts.
struct model {
    std::string name;
    std::string summary;     ///< one line
    std::string description; ///< Lagrangian, units, parameters' meaning, conserved quantities
    std::vector<std::string> options; ///< its own options, e.g. "--eccentricity"
    std::function<void(CLI::App&)> add_options;
    std::function<void(const run_setup&)> run;
};

/// All models, in the order `varsym models` lists them: the models layer's registry first
/// (registry_models.hpp; their parameters read from `po`, one per parsed command line), then the
/// tool's own, each with its own parameters bound to the options a command line sets.
std::vector<model> make_models(std::shared_ptr<class parameter_options> po = nullptr);

/// `lagrangian`: the user's L given by --lagrangian (model_expression.cpp); --project read
/// from `po`.
model make_expression_model(std::shared_ptr<class parameter_options> po = nullptr);

/// `urdf`: a robot from the URDF file of --urdf (model_robot.cpp); its parameters read from `po`.
model make_robot_model(std::shared_ptr<class parameter_options> po = nullptr);
/// --urdf FILE and --torques EXPR,... as given.
struct urdf_spec {
    std::string path, torques;
    std::string base; ///< --base: fixed, free or planar (empty: not given, fixed)
};
/// The model of the URDF file and typed torques (usage_error naming --urdf or --torques). With
/// `file`, also the URDF's absolute path and the digest of the bytes read (what a checkpoint or
/// an ensemble journal records).
std::shared_ptr<const models::model> robot_model_of(const urdf_spec& u,
                                                    checkpoint::input_file* file = nullptr);
/// The robot of --urdf and --base alone (usage_error naming --urdf), and its model.
std::shared_ptr<const multibody::tree> robot_tree_of(const urdf_spec& u,
                                                     checkpoint::input_file* file = nullptr);
std::shared_ptr<const models::model> robot_model_of(const urdf_spec& u,
                                                    std::shared_ptr<const multibody::tree> tree);
/// Refuses --animate where three.js is missing (usage_error saying how to install it).
void animation_check(const std::string& path);
/// Refuses `option`'s page name where it is "-" or a directory, and adds the page and its
/// PAGE.tmp to `roles` (cmd_animate.cpp).
void add_animation_roles(file_roles& roles, const std::string& option, const std::string& page);
/// "--animate draws a URDF robot (--urdf FILE) and the models heavy-top, ...": for refusals;
/// `with_inputs`: only those an optimisation applies to.
std::string drawn_models(bool with_inputs = false);
/// Model m's coordinates' names, d of them ("th", "phi", ...; q_1..q_d where its `coordinates`
/// text does not list d names).
std::vector<std::string> coordinate_names(const models::model& m, int d);
/// Writes the motion (t, q) of built-in model m (its `drawing` at values and lists) to the
/// animation page `path`, and says so on standard error.
void write_figure_animation(const models::model& m, std::span<const double> values,
                            const models::lists& lists, std::span<const double> t,
                            const Eigen::MatrixXd& q, const std::string& path, double fps,
                            bool quiet, const std::string& title);
/// A run with --animate: `run` with s's frames recorded (`width` values, simulation::q where
/// `coordinates` is set), then `write` of the page from them, also where the run failed or
/// was stopped (the page ends there and says so; the run's own error is rethrown).
void run_animated(const run_setup& s, int width, bool coordinates,
                  const std::function<void(const run_setup&)>& run,
                  const std::function<void(const frame_recorder&, const Eigen::MatrixXd&)>& write);
/// Writes robot `tree`'s motion (t, q: rows × coordinates) to the animation page `path`,
/// meshes found from `urdf` and `mesh_path`, and says so on standard error (cmd_animate.cpp).
void write_animation(std::shared_ptr<const multibody::tree> tree, std::span<const double> t,
                     const Eigen::MatrixXd& q, const std::string& urdf, const std::string& path,
                     double fps, const std::vector<std::string>& mesh_path, bool quiet,
                     std::vector<contact::obstacle> world = {},
                     std::vector<std::vector<double>> forces = {});
/// `optimize --animate`: the optimal motion on its steps' polynomials at `fps` frames per
/// second (0: its nodes) as the animation page `page`: of the robot of `urdf`, or where that is
/// empty of model m's figure at values and lists (cmd_animate.cpp).
void write_optimal_animation(const optimal::trajectory& path, const models::model& m,
                             std::span<const double> values, const models::lists& lists,
                             const std::string& urdf, const std::string& page, double fps,
                             const std::vector<std::string>& mesh_path, bool quiet);
/// Headless Chromium's path (usage_error saying how to install it where it is missing), and a
/// PNG of animation page `page` with the robot at the last of `times`, faint at the others
/// (output/snapshot.cpp).
std::string find_chromium();
void take_snapshot(const std::string& page, const std::string& png,
                   const std::vector<double>& times);
/// Refuses to resume the run of `ck` with the input `now` unless ck recorded that very file with
/// the same digest (usage_error saying which and what to do).
void check_resumed_input(const checkpoint& ck, const checkpoint::input_file& now);
/// Adds --urdf FILE and --torques to cmd.
void add_urdf_option(CLI::App& cmd, urdf_spec& u);

/// The most steps one run may take (1e15; the fuzz target lowers it to run actions cheaply).
extern double max_run_steps;

/// How many steps of which size: from --steps-per-period/--periods when the model has a period
/// (period > 0), else from --time/--steps (or the model's defaults). Refuses inconsistent input.
struct run_plan {
    std::size_t steps = 0;
    double h = 0.0;
    double period = 0.0; ///< the model's period, 0 if it has none
};
run_plan plan_steps(const run_setup& s, const std::string& model, double period,
                    long long default_steps_per_period, double default_time,
                    long long default_steps);

/// The initial vector of `option` (--q0, --p0, --v0): the given values, which must be d of them
/// (`names` says what they are in the message), or `fallback` when none were given.
vec<dynamic> initial_vector(const std::vector<double>& given, const char* option, int d,
                            const std::string& names, const vec<dynamic>& fallback);

/// The linear stability limit of a scheme: the largest z such that the step map of the harmonic
/// oscillator with h·ω < z is stable (infinity if it is stable at every h·ω); computed by
/// running the scheme's stepper on the models layer's oscillator (commands/cmd_stability.cpp).
double linear_stability_limit(const scheme_spec& spec);

/// Where h·ω is unstable for `spec`, scanned up to stability_scan_end (cmd_stability.cpp).
inline constexpr double stability_scan_end = 50.0;

} // namespace varsym::cli
