// apps/varsym/commands/commands.hpp: the subcommands of the varsym tool, one source file each.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "options/cli_common.hpp"
#include "output/checkpoint.hpp"

namespace varsym::cli {

/// What main tells `varsym run` beyond its options: the arguments to keep in checkpoints and,
/// for `varsym run --resume FILE`, the checkpoint (whose arguments main parsed instead).
struct run_context {
    std::vector<std::string> args;
    std::shared_ptr<const checkpoint> resume;
    std::string resume_path;
};

/// `varsym run`: integrate a model, stream CSV (cmd_run.cpp).
void add_run_command(CLI::App& app, action& todo, run_context& ctx);

/// `varsym bench`: varsym against Boost.Odeint, work-precision (cmd_bench.cpp).
void add_bench_command(CLI::App& app, action& todo);

/// `varsym models`: the built-in models (cmd_models.cpp).
void add_models_command(CLI::App& app, action& todo);

/// `varsym converge`: error table and observed orders of any scheme (cmd_converge.cpp).
void add_converge_command(CLI::App& app, action& todo);

/// `varsym stability`: each scheme's linear stability limit (stability.cpp).
void add_stability_command(CLI::App& app, action& todo);

/// `varsym ensemble`: one model from many initial states or parameters (cmd_ensemble.cpp).
void add_ensemble_command(CLI::App& app, action& todo);
/// `varsym section`: Poincaré sections of orbits (cmd_section.cpp).
void add_section_command(CLI::App& app, action& todo);
/// `varsym optimize`: optimal control of a model with inputs (cmd_optimize.cpp).
void add_optimize_command(CLI::App& app, action& todo);
/// `varsym animate`: a robot's motion from a CSV file as a 3-D animation page (cmd_animate.cpp).
void add_animate_command(CLI::App& app, action& todo);
/// `varsym paper table1|figure1|figure2`: reproduce the paper (cmd_paper.cpp).
void add_paper_command(CLI::App& app, action& todo);

} // namespace varsym::cli
