// apps/varsym/cli_common.cpp: validators, number formatting and atomic output files.
#include "cli_common.hpp"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>

#include <fcntl.h>
#include <unistd.h>

namespace varsym::cli {

namespace {

// Parses the whole string as a double; false on trailing text, empty input or overflow.
bool parse_double(const std::string& s, double& v) {
    const char* first = s.data() + (s.starts_with('+') ? 1 : 0);
    const char* last = first + s.size();
    auto [ptr, ec] = std::from_chars(first, last, v);
    return ec == std::errc() && ptr == last;
}

bool parse_integer(const std::string& s, long long& v) {
    const char* first = s.data() + (s.starts_with('+') ? 1 : 0);
    const char* last = first + s.size();
    auto [ptr, ec] = std::from_chars(first, last, v);
    return ec == std::errc() && ptr == last;
}

CLI::Validator number_check(const char* name, bool positive) {
    return CLI::Validator(
        [positive](std::string& s) -> std::string {
            double v = 0;
            if (!parse_double(s, v)) return "'" + s + "' is not a number";
            if (!std::isfinite(v)) return "'" + s + "' is not finite";
            if (positive && !(v > 0)) return "must be > 0, got " + s;
            return {};
        },
        name);
}

CLI::Validator integer_check(const char* name, long long min) {
    return CLI::Validator(
        [min](std::string& s) -> std::string {
            long long v = 0;
            if (!parse_integer(s, v)) return "'" + s + "' is not a whole number";
            if (v < min) return "must be >= " + std::to_string(min) + ", got " + s;
            return {};
        },
        name);
}

} // namespace

const CLI::Validator finite_number = number_check("REAL", false);
const CLI::Validator positive_number = number_check("REAL>0", true);
const CLI::Validator positive_integer = integer_check("INT>0", 1);
const CLI::Validator non_negative_integer = integer_check("INT>=0", 0);

void append_number(std::string& line, double v) {
    char buf[40];
    auto [ptr, ec] = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 17);
    line.append(buf, ptr);
}

output_file::output_file(const std::string& path) {
    if (path.empty() || path == "-") {
        f_ = stdout;
        return;
    }
    path_ = path;
    if (std::filesystem::is_directory(path_))
        throw std::runtime_error("cannot write '" + path + "': it is a directory");
    f_ = std::fopen(partial_path().c_str(), "w");
    if (f_ == nullptr)
        throw std::runtime_error("cannot write '" + path + "': " + std::strerror(errno));
}

output_file::output_file(const std::string& path, std::uint64_t keep) : path_(path) {
    const std::string part = partial_path();
    std::error_code ec;
    const auto size = std::filesystem::file_size(part, ec);
    if (ec)
        throw usage_error("cannot resume: '" + part + "', the rows of the interrupted run, is " +
                          "missing (" + ec.message() + ")");
    if (size < keep)
        throw usage_error("cannot resume: '" + part + "' has " + std::to_string(size) +
                          " bytes, fewer than the " + std::to_string(keep) +
                          " its checkpoint covers; it was changed after the run stopped");
    if (::truncate(part.c_str(), static_cast<off_t>(keep)) != 0)
        throw std::runtime_error("cannot truncate '" + part + "': " + std::strerror(errno));
    f_ = std::fopen(part.c_str(), "a");
    if (f_ == nullptr)
        throw std::runtime_error("cannot write '" + part + "': " + std::strerror(errno));
    bytes_ = keep;
    keep_ = true; // an interrupted resumed run keeps its rows for the next resume
}

void output_file::sync() {
    if (std::fflush(f_) != 0 || (!is_stdout() && ::fsync(::fileno(f_)) != 0))
        throw std::runtime_error("cannot write '" + path_.string() + "': " + std::strerror(errno));
}

output_file::~output_file() {
    if (is_stdout() || committed_) return;
    std::fclose(f_);
    if (!keep_) std::remove(partial_path().c_str());
}

void output_file::write(const std::string& s) {
    bytes_ += s.size();
    if (std::fwrite(s.data(), 1, s.size(), f_) != s.size() || std::fflush(f_) != 0)
        throw std::runtime_error("cannot write '" +
                                 (is_stdout() ? std::string("standard output") : path_.string()) +
                                 "': " + std::strerror(errno));
}

void output_file::commit() {
    if (is_stdout()) {
        std::fflush(f_);
        return;
    }
    const bool ok = std::fflush(f_) == 0 && ::fsync(::fileno(f_)) == 0;
    const int err = errno;
    if (std::fclose(f_) != 0 || !ok) {
        committed_ = true; // the stream is closed: the destructor must not close it again
        std::remove(partial_path().c_str());
        throw std::runtime_error("cannot write '" + path_.string() + "': " + std::strerror(err));
    }
    committed_ = true;
    if (std::rename(partial_path().c_str(), path_.c_str()) != 0) {
        const int e = errno;
        std::remove(partial_path().c_str());
        throw std::runtime_error("cannot write '" + path_.string() + "': " + std::strerror(e));
    }
}

} // namespace varsym::cli
