// apps/varsym/main.cpp: the varsym command-line tool: parses the command line, runs the chosen
// subcommand, and turns every failure into one line on standard error and an exit code
// (front_end.cpp).
#include <string>
#include <vector>

#include "front_end.hpp"

int main(int argc, char** argv) {
    varsym::cli::front_end cli;
    const int status = cli.parse(std::vector<std::string>(argv + 1, argv + argc));
    return status >= 0 ? status : cli.run();
}
