// apps/varsym/commands/cmd_optimize_exec.cpp: `varsym optimize` in the varsym program: it runs
// the program varsym-optimize beside it (same arguments, by exec: signals, exit code and output
// are that program's own). The optimizer lives in its own program because IPOPT's sequential
// MUMPS defines MPI_Init, MPI_Comm_rank and MPI_Finalize as stubs: in one process with Open MPI
// one of the two gets the other's symbols, and either `mpirun varsym ensemble` or IPOPT breaks.
// The real command is cmd_optimize.cpp, linked into varsym-optimize.
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <unistd.h>

#include "commands/commands.hpp"

namespace varsym::cli {

void add_optimize_command(CLI::App& app, action& todo) {
    auto* cmd = app.add_subcommand(
        "optimize", "Optimal control of a model with inputs (discrete mechanics, IPOPT)");
    cmd->prefix_command(); // every argument, --help included, goes to varsym-optimize
    cmd->set_help_flag();
    cmd->callback([cmd, &todo] {
        todo = [args = cmd->remaining()] {
            std::error_code ec;
            const auto self = std::filesystem::read_symlink("/proc/self/exe", ec);
            const auto helper =
                (ec ? std::filesystem::path(".") : self.parent_path()) / "varsym-optimize";
            std::vector<std::string> words{helper.string(), "optimize"};
            words.insert(words.end(), args.begin(), args.end());
            std::vector<char*> argv;
            for (auto& w : words)
                argv.push_back(w.data());
            argv.push_back(nullptr);
            ::execv(helper.c_str(), argv.data());
            throw std::runtime_error("cannot run " + helper.string() + ": " + std::strerror(errno) +
                                     " (varsym optimize needs the program varsym-optimize "
                                     "beside varsym: build it with 'make tool')");
        };
    });
}

} // namespace varsym::cli
