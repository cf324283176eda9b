// apps/varsym/cmd_models.cpp: `varsym models`, the built-in models with their parameters and
// conserved quantities.
#include <iostream>

#include "commands.hpp"
#include "models.hpp"

namespace varsym::cli {

void add_models_command(CLI::App& app, action& todo) {
    auto* cmd = app.add_subcommand("models", "List the built-in models, their parameters and what "
                                             "they conserve");
    cmd->footer("\nEach model runs with 'varsym run --model NAME [its parameters]'.");
    cmd->callback([&todo] {
        todo = [] {
            for (const model& m : make_models())
                std::cout << m.name << ": " << m.summary << '\n' << m.description << "\n\n";
            std::cout << "All models: --scheme simpson|newmark|lobatto|gauss (--degree s) "
                         "(rigid bodies: --order 2|4|6),\n--steps-per-period/--periods or "
                         "--time/--steps, --every, --output; see 'varsym run --help'.\n";
        };
    });
}

} // namespace varsym::cli
