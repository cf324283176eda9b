// apps/varsym/cli_common.hpp: what every varsym subcommand shares: validators, errors with exit
// codes, CSV number formatting, and output files that never look complete when they are not.
#pragma once

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>

#include <CLI/CLI.hpp>

namespace varsym::cli {

/// Exit codes of the tool (documented in `varsym --help`).
enum exit_code : int {
    exit_ok = 0,
    exit_failure = 1,   ///< I/O or other run-time failure
    exit_usage = 2,     ///< bad command line or bad input value
    exit_numerical = 3, ///< a step's Newton iteration did not converge
};

/// A bad input value found after parsing (inconsistent options, refused initial state, …).
struct usage_error : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// A run stopped because a step did not converge (exit code 3).
struct numerical_error : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// Option validators: the value must parse as a finite number (and be > 0, or ≥ 0).
extern const CLI::Validator finite_number;
extern const CLI::Validator positive_number;
extern const CLI::Validator positive_integer;
extern const CLI::Validator non_negative_integer;

/// Appends v with 17 significant digits (round-trips a double exactly), locale-independent.
void append_number(std::string& line, double v);

/// An output destination: standard output for "" or "-", else FILE written as FILE.part and
/// renamed to FILE by commit(). Without commit() the .part file is removed, unless
/// keep_partial() was called (a run that failed mid-way keeps its rows for inspection).
/// An existing FILE is untouched until commit().
class output_file {
  public:
    explicit output_file(const std::string& path);
    /// Continues FILE.part of an interrupted run: truncates it to its first `keep` bytes (the
    /// rows a checkpoint covers) and appends from there. Refuses a missing or shorter file.
    output_file(const std::string& path, std::uint64_t keep);
    output_file(const output_file&) = delete;
    output_file& operator=(const output_file&) = delete;
    ~output_file();

    [[nodiscard]] std::FILE* stream() const { return f_; }
    [[nodiscard]] bool is_stdout() const { return path_.empty(); }
    [[nodiscard]] std::string partial_path() const { return path_.string() + ".part"; }
    void write(const std::string& s);
    /// Bytes in the file so far (for a resumed file, counting the kept ones).
    [[nodiscard]] std::uint64_t bytes() const { return bytes_; }
    /// Flushes and fsyncs what was written (before a checkpoint that counts these bytes).
    void sync();
    void commit();
    void keep_partial() { keep_ = true; }

  private:
    std::filesystem::path path_;
    std::FILE* f_ = nullptr;
    bool committed_ = false;
    bool keep_ = false;
    std::uint64_t bytes_ = 0;
};

/// A subcommand's action, run after the whole command line parsed.
using action = std::function<void()>;

} // namespace varsym::cli
