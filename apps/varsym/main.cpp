// apps/varsym/main.cpp: the varsym command-line tool: parses the command line, runs the chosen
// subcommand, and turns every failure into one line on standard error and an exit code.
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "cli_common.hpp"
#include "commands.hpp"
#include "config.hpp"
#include "varsym/integrate.hpp"

namespace {

int fail(int code, std::string message) {
    for (char& c : message)
        if (c == '\n') c = ' ';
    std::cerr << "varsym: error: " << message << '\n';
    return code;
}

} // namespace

int main(int argc, char** argv) {
    using namespace varsym::cli;
    CLI::App app{"varsym: variational symplectic integrators for Lagrangian mechanics.\n"
                 "Newmark (2nd order) and nonlinear Simpson (4th order) schemes of Dubois & "
                 "Rojas-Quintero (2023),\nand the Lobatto and Gauss variational family of any "
                 "order 2s, solved by Newton at each step.",
                 "varsym"};
    app.set_version_flag("--version", "varsym 0.1.0");
    app.require_subcommand(1);
    app.footer("\nExit codes: 0 success, 1 I/O or run-time failure, 2 bad command line or input "
               "value,\n3 a step's Newton iteration did not converge (use a smaller step).\n"
               "Run 'varsym COMMAND --help' for the options of a command.");
    action todo;
    add_run_command(app, todo);
    add_models_command(app, todo);
    add_bench_command(app, todo);
    add_converge_command(app, todo);
    add_paper_command(app, todo);

    // Name an unknown (sub)command plainly; CLI11 would only say that one is required.
    const CLI::App* level = &app;
    for (int i = 1; i < argc && argv[i][0] != '-' && !level->get_subcommands({}).empty(); ++i) {
        const CLI::App* next = nullptr;
        std::string names;
        for (const auto* sub : level->get_subcommands({})) {
            if (sub->check_name(argv[i])) next = sub;
            names += (names.empty() ? "" : ", ") + sub->get_name();
        }
        if (next == nullptr)
            return fail(exit_usage, std::string("unknown command '") + argv[i] + "'; expected one of " +
                                        names + " (see 'varsym --help')");
        level = next;
    }
    // `run --config FILE`: the file's options become arguments (the command line wins).
    config_origins origins;
    std::vector<std::string> args(argv + 1, argv + argc);
    try {
        args = expand_config(args, *app.get_subcommand("run"), origins);
    } catch (const usage_error& e) {
        return fail(exit_usage, e.what());
    }
    std::vector<char*> expanded{argv[0]};
    for (std::string& a : args) expanded.push_back(a.data());
    try {
        app.parse(static_cast<int>(expanded.size()), expanded.data());
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        return fail(exit_usage, locate(e.what(), origins) + " (see 'varsym --help')");
    }
    try {
        if (todo) todo();
        return exit_ok;
    } catch (const usage_error& e) {
        return fail(exit_usage, locate(e.what(), origins));
    } catch (const numerical_error& e) {
        return fail(exit_numerical, e.what());
    } catch (const varsym::step_failure& e) {
        return fail(exit_numerical, e.what());
    } catch (const std::exception& e) {
        return fail(exit_failure, e.what());
    }
}
