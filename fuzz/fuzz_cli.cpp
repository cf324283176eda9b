// fuzz/fuzz_cli.cpp: libFuzzer target over varsym's input parsers: the command line of every
// subcommand (CLI11 options and their validators), `run --config FILE` (TOML through toml++,
// expanded into arguments) and `run --resume FILE` (the checkpoint reader). Where the input names
// no path (no '/' anywhere) it also runs `varsym run`, `models`, `ensemble` and `section`, in a
// private scratch directory, with runs limited to 2000 steps (max_run_steps; an ensemble's
// members times steps): checkpoints, journals, outputs, the energy
// watch and the failure paths are exercised too. Each input gets a fresh front end (its own
// option values and model parameters). Any crash, sanitizer report, or exception escaping
// front_end::parse or front_end::run is a finding.
//
// Input: one mode byte, then
//   mode % 3 == 0: arguments separated by '\n';
//   mode % 3 == 1: arguments, a '\0', then a TOML file passed as `run ... --config FILE`;
//   mode % 3 == 2: a checkpoint file passed as `run --resume FILE`.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <unistd.h>
#include <vector>

#include <filesystem>
#include <stdexcept>

#include "models/models.hpp"
#include "options/front_end.hpp"

namespace {

std::vector<std::string> split_lines(const std::string& s) {
    std::vector<std::string> out;
    std::size_t start = 0;
    while (start <= s.size()) {
        const std::size_t end = s.find('\n', start);
        out.push_back(s.substr(start, end == std::string::npos ? std::string::npos : end - start));
        if (end == std::string::npos) break;
        start = end + 1;
    }
    return out;
}

/// A scratch file of this process, rewritten for each input.
const std::string& scratch_file(const std::string& contents) {
    static const std::string path = [] {
        char name[] = "/tmp/varsym-fuzz-XXXXXX";
        const int fd = ::mkstemp(name);
        if (fd >= 0) ::close(fd);
        return std::string(name);
    }();
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (f != nullptr) {
        std::fwrite(contents.data(), 1, contents.size(), f);
        std::fclose(f);
    }
    return path;
}

/// Runs the action in a scratch directory, emptied first, and comes back: libFuzzer writes its
/// corpus and crash files relative to the directory it started in.
void run_in_scratch_directory(varsym::cli::front_end& cli) {
    static const std::string home = std::filesystem::current_path().string();
    static const std::string dir = [] {
        char name[] = "/tmp/varsym-fuzz-dir-XXXXXX";
        if (::mkdtemp(name) == nullptr) throw std::runtime_error("mkdtemp failed");
        return std::string(name);
    }();
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator(dir, ec))
        std::filesystem::remove_all(e.path(), ec);
    if (::chdir(dir.c_str()) != 0) throw std::runtime_error("chdir failed");
    cli.run();
    if (::chdir(home.c_str()) != 0) throw std::runtime_error("chdir back failed");
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    varsym::cli::max_run_steps = 2000;
    const int mode = data[0] % 3;
    const std::string rest(reinterpret_cast<const char*>(data) + 1, size - 1);
    std::vector<std::string> args;
    if (mode == 0) {
        args = split_lines(rest);
    } else if (mode == 1) {
        const std::size_t cut = rest.find('\0');
        args = split_lines(rest.substr(0, cut));
        const std::string file = scratch_file(cut == std::string::npos ? "" : rest.substr(cut + 1));
        args.insert(args.begin(), {"run", "--config", file});
    } else {
        args = {"run", "--resume", scratch_file(rest)};
    }
    varsym::cli::front_end cli;
    if (cli.parse(args) != -1) return 0;
    const bool names_a_path = mode == 2 || rest.find('/') != std::string::npos;
    // ensemble and section are bounded by max_run_steps too (members × steps).
    const bool cheap = !args.empty() &&
                       (args[0] == "run" || args[0] == "models" || args[0] == "ensemble" ||
                        args[0] == "section") &&
                       rest.find("chain") == std::string::npos;
    if (names_a_path || !cheap) return 0;
    run_in_scratch_directory(cli);
    return 0;
}
