// fuzz/fuzz_cli.cpp: libFuzzer target over varsym's input parsers: the command line of every
// subcommand (CLI11 options and their validators), `run --config FILE` (TOML through toml++,
// expanded into arguments) and `run --resume FILE` (the checkpoint reader). It parses only:
// running a subcommand would integrate and write files. Any crash, sanitizer report or
// exception escaping front_end::parse (which main would not catch) is a finding.
//
// Input: one mode byte, then
//   mode % 3 == 0: arguments separated by '\n';
//   mode % 3 == 1: arguments, a '\0', then a TOML file passed as `run ... --config FILE`;
//   mode % 3 == 2: a checkpoint file passed as `run --resume FILE`.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <unistd.h>
#include <vector>

#include "front_end.hpp"

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

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
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
    cli.parse(args);
    return 0;
}
