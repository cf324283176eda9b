// apps/varsym/options/front_end.hpp: the command line of varsym, parsed but not yet run: what main
// runs, and what the fuzz target (fuzz/fuzz_cli.cpp) feeds with arbitrary arguments.
#pragma once

#include <string>
#include <vector>

#include "commands/commands.hpp"
#include "options/config.hpp"

namespace varsym::cli {

/// Prints "varsym: error: MESSAGE" (one line) on standard error and returns code.
int fail(int code, std::string message);
/// The message of the last fail() on this thread ("" if none): what the Python package raises.
const std::string& last_failure();
/// Whether fail() keeps its line off standard error on this thread (the Python package raises
/// it instead).
void set_quiet_failures(bool on);

/// The application with all its subcommands.
class front_end {
  public:
    front_end();
    front_end(const front_end&) = delete;
    front_end& operator=(const front_end&) = delete;

    /// Parses args (argv without the program name): `run --resume FILE` (the checkpoint's
    /// arguments replace args), `run --config FILE` (the file's options are inserted), then the
    /// options of the subcommand. Returns −1 when the subcommand's action is ready to run, else
    /// the exit code after printing help, the version or one error line.
    int parse(std::vector<std::string> args);

    /// Runs the parsed subcommand; every failure becomes one line and its exit code.
    int run();

  private:
    CLI::App app_;
    action todo_;
    run_context run_ctx_;
    config_origins origins_;
};

} // namespace varsym::cli
