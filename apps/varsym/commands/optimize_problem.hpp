// apps/varsym/commands/optimize_problem.hpp: the options of `varsym optimize` and the optimal
// control problem they describe (varsym/optimal/problem.hpp).
#pragma once

#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "models/registry_models.hpp"
#include "options/shared_options.hpp"
#include "output/files.hpp"
#include "varsym/models/robot.hpp"
#include "varsym/multibody/tree.hpp"
#include "varsym/optimize/model.hpp"

namespace varsym::cli {

struct optimize_options {
    std::string model;
    double time = 0.0;
    int steps = 50;
    scheme_options scheme;
    std::string from, to, from_velocity, to_velocity;
    std::string free_end, terminal_weight; ///< "q1,v2"; one weight per freed entry
    double max_control = std::numeric_limits<double>::infinity();
    double max_velocity = std::numeric_limits<double>::infinity();
    std::string cost = "effort", hessian = "automatic";
    int max_iterations = 3000, refine = 0, threads = 0;
    std::string output, controls, config, ipopt_options;
    std::vector<std::string> plot;
    std::string animate;                ///< --animate FILE: the robot's motion as an HTML page
    double animate_fps = 60.0;          ///< --animate-fps
    std::vector<std::string> mesh_path; ///< --mesh-path
    bool quiet = false;
    std::shared_ptr<parameter_options> parameters = std::make_shared<parameter_options>();
    std::string urdf; ///< --urdf FILE: the model `urdf`
    std::string lagrangian, coordinates = "q", expression_parameters, inputs,
                            constraints;    ///< `lagrangian`
    std::vector<std::string> typed_options; ///< those of the four above given (--inputs, ...)
    bool no_limits = false;                 ///< --no-limits: a robot's URDF limits left out
    /// --reach LINK with --reach-position X,Y,Z, --reach-rpy R,P,Y and --reach-weight W: a URDF
    /// link's target pose at T (models::frame_target) instead of --to.
    std::string reach, reach_position, reach_rpy;
    double reach_weight = 0.0;
};

/// Adds --max-velocity, --reach, --reach-position, --reach-rpy and --reach-weight to cmd.
void add_velocity_and_reach_options(CLI::App& cmd, optimize_options& o);
/// With --reach: one line saying how far the link ends from its target (the miss in m, and in
/// rad with --reach-rpy); else empty.
std::string reach_report(const optimize_options& o, const optimal::model_outcome& out);

/// --ipopt-options FILE, read before any file is made: an unreadable file or an option IPOPT
/// does not have is a usage_error naming FILE:LINE, and its output_file is a role (file_roles).
/// (IPOPT prints on standard error only.)
void check_ipopt_options(const std::string& file, file_roles& roles);

/// The model of --model, --urdf or --lagrangian (with --inputs), and its parameter values into
/// `values`; usage_error for a model without inputs, an unreadable URDF, a bad expression or an
/// input that is not a coordinate.
std::shared_ptr<const models::model> optimize_model(const optimize_options& o,
                                                    std::vector<double>& values);
/// Hides from cmd's --help the parameters only a simulation uses (models::model::
/// simulation_only: --push, --torque, a controller's --kp) where no model with inputs optimises
/// with them; optimize refuses them with a word when given.
void hide_simulation_only(CLI::App& cmd);

/// The request the options describe for model m at its parameters' values and lists (the
/// problem, the limits, the reach target, refinement and the solver's options but its
/// callbacks); usage_error naming the option on bad input. The robot of --reach is read here,
/// once, so a URDF changed or removed during the solve cannot turn a solved problem into an
/// error.
optimal::model_request request_of(const optimize_options& o, const models::model& m,
                                  std::span<const double> values, const models::lists& lists);

} // namespace varsym::cli
