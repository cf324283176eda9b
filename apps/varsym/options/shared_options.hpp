// apps/varsym/options/shared_options.hpp: options that several subcommands share: the pendulum's
// parameters and the choice of scheme and degree.
#pragma once

#include <string>

#include "options/cli_common.hpp"
#include "varsym/problems/paper.hpp"
#include "varsym/problems/pendulum.hpp"
#include "varsym/schemes/scheme_kind.hpp"

namespace varsym::cli {

/// The pendulum's parameters, defaulting to the paper's case.
using pendulum_options = paper::pendulum_case;

/// --mass, --omega, --q0, --p0 with their units and defaults (the paper's case).
void add_pendulum_options(CLI::App& cmd, pendulum_options& o);
/// The system and its exact solution; bad values (separatrix, …) become usage_error.
pendulum::system make_system(const pendulum_options& o);
pendulum::exact_solution make_exact(const pendulum_options& o);

struct scheme_options {
    std::string scheme = "simpson";
    int degree = 0; ///< 0: the scheme's natural degree
};

/// --scheme simpson|newmark|lobatto|gauss and --degree s.
void add_scheme_options(CLI::App& cmd, scheme_options& o);
scheme_spec make_spec(const scheme_options& o);

/// The pendulum's footer for --help: model, units, conventions.
extern const char* const pendulum_help;

} // namespace varsym::cli
