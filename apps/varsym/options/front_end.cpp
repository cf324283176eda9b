// apps/varsym/options/front_end.cpp: the varsym application: its subcommands, how a command line is
// parsed (resume, config files, CLI11), and how every failure becomes one line and an exit code.
#include "options/front_end.hpp"

#include <exception>
#include <filesystem>
#include <iostream>
#include <memory>
#include <new>

#include "output/checkpoint.hpp"
#include "varsym/integrate.hpp"

namespace varsym::cli {

namespace {
thread_local std::string last_message; // NOLINT: what fail() said last, for an embedder
thread_local bool quiet = false;       // NOLINT
} // namespace

int fail(int code, std::string message) {
    for (char& c : message)
        if (c == '\n') c = ' ';
    constexpr std::size_t limit = 2000; // one line, even when it quotes a huge value
    if (message.size() > limit) message = message.substr(0, limit) + "... (message cut)";
    if (!quiet) std::cerr << "varsym: error: " << message << '\n';
    last_message = std::move(message);
    return code;
}

const std::string& last_failure() {
    return last_message;
}
void set_quiet_failures(bool on) {
    quiet = on;
}

namespace {

/// If args are `run --resume FILE` (or --resume=FILE), reads the checkpoint into ctx and replaces
/// args by the arguments of its run. Any other option beside --resume is refused.
bool resume_arguments(std::vector<std::string>& args, run_context& ctx) {
    if (args.empty() || args[0] != "run") return false;
    std::string file;
    bool found = false;
    for (std::size_t i = 1; i < args.size(); ++i) {
        if (args[i] == "--resume" && i + 1 < args.size())
            file = args[i + 1], found = true;
        else if (args[i].rfind("--resume=", 0) == 0)
            file = args[i].substr(9), found = true;
    }
    if (!found) return false;
    const bool alone = args.size() == 3 || (args.size() == 2 && args[1].rfind("--resume=", 0) == 0);
    if (!alone)
        throw usage_error("--resume FILE takes no other option: the run continues with the options "
                          "stored in its checkpoint");
    auto ck = std::make_shared<checkpoint>(read_checkpoint(file));
    args = {"run"};
    args.insert(args.end(), ck->args.begin(), ck->args.end());
    ctx.args = ck->args;
    ctx.resume = std::move(ck);
    ctx.resume_path = file;
    return true;
}

/// The arguments of `varsym run` a checkpoint keeps: after "run", without --config FILE (whose
/// options expand_config already inserted), so a resume does not depend on the config file, and
/// with --urdf FILE made absolute, so a resume from another directory reads the same robot.
std::vector<std::string> run_arguments(const std::vector<std::string>& args) {
    std::vector<std::string> out;
    if (args.empty() || args[0] != "run") return out;
    const auto absolute = [](const std::string& path) {
        return path.empty() ? path : std::filesystem::absolute(path).lexically_normal().string();
    };
    for (std::size_t i = 1; i < args.size(); ++i) {
        if (args[i] == "--config") {
            ++i;
            continue;
        }
        if (args[i].rfind("--config=", 0) == 0) continue;
        if (args[i] == "--urdf" && i + 1 < args.size()) {
            out.push_back(args[i]);
            out.push_back(absolute(args[++i]));
            continue;
        }
        if (args[i].rfind("--urdf=", 0) == 0) {
            out.push_back("--urdf=" + absolute(args[i].substr(7)));
            continue;
        }
        out.push_back(args[i]);
    }
    return out;
}

} // namespace

front_end::front_end()
    : app_{"varsym: variational symplectic integrators for Lagrangian mechanics.\n"
           "Newmark (2nd order) and nonlinear Simpson (4th order) schemes of Dubois & "
           "Rojas-Quintero (2023),\nand the Lobatto and Gauss variational family of any "
           "order 2s, solved by Newton at each step.",
           "varsym"} {
    app_.set_version_flag("--version", std::string("varsym ") + varsym_version);
    app_.require_subcommand(1);
    app_.footer(
        "\nExit codes: 0 success, 1 I/O or run-time failure, 2 bad command line or input "
        "value\nor a file conflict, 3 a step's Newton iteration did not converge (use a smaller "
        "step),\n4 the energy error passed --max-energy-error, 130/143 stopped by "
        "SIGINT/SIGTERM.\n"
        "Run 'varsym COMMAND --help' for the options of a command.");
    add_run_command(app_, todo_, run_ctx_);
    add_models_command(app_, todo_);
    add_bench_command(app_, todo_);
    add_converge_command(app_, todo_);
    add_ensemble_command(app_, todo_);
    add_section_command(app_, todo_);
    add_paper_command(app_, todo_);
    add_stability_command(app_, todo_);
    add_optimize_command(app_, todo_);
    add_animate_command(app_, todo_);
}

int front_end::parse(std::vector<std::string> args) {
    // Name an unknown (sub)command plainly; CLI11 would only say that one is required.
    const CLI::App* level = &app_;
    for (std::size_t i = 0; i < args.size() && !args[i].empty() && args[i][0] != '-' &&
                            !level->get_subcommands({}).empty();
         ++i) {
        const CLI::App* next = nullptr;
        std::string names;
        for (const auto* sub : level->get_subcommands({})) {
            if (sub->check_name(args[i])) next = sub;
            names += (names.empty() ? "" : ", ") + sub->get_name();
        }
        if (next == nullptr)
            return fail(exit_usage, "unknown command '" + args[i] + "'; expected one of " + names +
                                        " (see 'varsym --help')");
        level = next;
    }
    try {
        if (!resume_arguments(args, run_ctx_)) {
            args = expand_config(args, app_, origins_);
            run_ctx_.args = run_arguments(args);
        }
    } catch (const usage_error& e) {
        return fail(exit_usage, e.what());
    } catch (const std::bad_alloc&) {
        return fail(exit_failure, "out of memory while reading the command line's files");
    } catch (const std::exception& e) {
        return fail(exit_failure, e.what());
    }
    std::string program = "varsym";
    std::vector<char*> argv{program.data()};
    for (std::string& a : args)
        argv.push_back(a.data());
    try {
        app_.parse(static_cast<int>(argv.size()), argv.data());
    } catch (const CLI::CallForHelp& e) {
        return app_.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app_.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app_.exit(e);
    } catch (const CLI::ParseError& e) {
        return fail(exit_usage, locate(e.what(), origins_) + " (see 'varsym --help')");
    }
    return -1;
}

int front_end::run() {
    try {
        if (todo_) todo_();
        return exit_ok;
    } catch (const usage_error& e) {
        return fail(exit_usage, locate(e.what(), origins_));
    } catch (const numerical_error& e) {
        return fail(exit_numerical, e.what());
    } catch (const step_failure& e) {
        return fail(exit_numerical, e.what());
    } catch (const energy_error& e) {
        return fail(exit_energy, e.what());
    } catch (const interrupted& e) {
        if (!quiet) std::cerr << "varsym: " << e.what() << '\n';
        last_message = e.what();
        return 128 + e.signal;
    } catch (const std::bad_alloc&) {
        return fail(exit_failure, "out of memory");
    } catch (const std::invalid_argument& e) {
        // The library's and the models layer's word for data they refuse (a degree of 9, a
        // size that does not fit in memory): bad input wherever a command lets it through.
        return fail(exit_usage, e.what());
    } catch (const std::exception& e) {
        return fail(exit_failure, e.what());
    }
}

} // namespace varsym::cli
