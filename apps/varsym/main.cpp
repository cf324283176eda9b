// apps/varsym/main.cpp: the varsym command-line tool: parses the command line, runs the chosen
// subcommand, and turns every failure into one line on standard error and an exit code
// (front_end.cpp).
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "options/front_end.hpp"
#include "output/signals.hpp"

int main(int argc, char** argv) {
    using namespace varsym::cli;
    install_signal_handlers();
    int status = exit_failure;
    try {
        front_end cli;
        status = cli.parse(std::vector<std::string>(argv + 1, argv + argc));
        if (status < 0) status = cli.run();
    } catch (const std::exception& e) { // the front end catches all; this is the last guard
        return fail(exit_failure, e.what());
    }
    // Help, tables and CSV on standard output: a failed write (a full disk, a closed pipe
    // without SIGPIPE) is a failure, not a success.
    std::cout.flush();
    if (!std::cout || std::fflush(stdout) != 0 || std::ferror(stdout) != 0) {
        const int err = errno;
        if (status == exit_ok)
            return fail(exit_failure,
                        std::string("cannot write standard output: ") + std::strerror(err));
    }
    return status;
}
