// apps/varsym/options/cli_common.hpp: what every varsym subcommand shares: validators, errors with exit
// codes, number parsing and formatting.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace varsym::cli {

/// Exit codes of the tool (documented in `varsym --help`).
enum exit_code : int {
    exit_ok = 0,
    exit_failure = 1,   ///< I/O or other run-time failure
    exit_usage = 2,     ///< bad command line or bad input value
    exit_numerical = 3, ///< a step's Newton iteration did not converge
    exit_energy = 4,    ///< the energy error passed --max-energy-error: the rows are meaningless
    exit_sigint = 130,  ///< stopped by SIGINT (128 + 2), after a checkpoint where one is kept
    exit_sigterm = 143, ///< stopped by SIGTERM (128 + 15), likewise
};

/// A bad input value found after parsing (inconsistent options, refused initial state, …).
struct usage_error : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// A run stopped because a step did not converge (exit code 3).
struct numerical_error : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// A run stopped by the energy watch (exit code 4).
struct energy_error : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// A run stopped by SIGINT or SIGTERM after a checkpoint (exit code 128 + signal).
struct interrupted : std::runtime_error {
    interrupted(int sig, const std::string& what) : std::runtime_error(what), signal(sig) {}
    int signal;
};

/// Option validators. Each parses the whole value in decimal (std::from_chars: correctly
/// rounded, no octal or hexadecimal, a leading '+' allowed) and rewrites it in a form CLI11
/// converts exactly (integers in plain decimal, reals as hexadecimal floats), so that the value
/// used is the one a correctly rounded parser gives. Use them with Option::transform.
extern const CLI::Validator finite_number;
extern const CLI::Validator positive_number;
extern const CLI::Validator non_negative_number;
extern const CLI::Validator positive_integer;     ///< also 1e3 and 1000.0: a whole number
extern const CLI::Validator non_negative_integer; ///< also 1e3 and 1000.0: a whole number
/// A real number in [lo, hi], or [lo, hi) if open_hi (the name says the range in --help).
CLI::Validator number_in(double lo, double hi, const char* name, bool open_hi = false);
/// The type name --help shows for a number_list option; config files give such a key a list.
inline constexpr const char* list_type_name = "X1,X2,...";
/// A comma-separated list of finite numbers, none of them empty ("1,2.5,-3").
extern const CLI::Validator number_list;
/// The numbers of a value number_list accepted.
std::vector<double> parse_number_list(const std::string& s);

/// s quoted for a message, cut to its first 40 characters (a value may be megabytes long).
std::string shown(const std::string& s);

/// Appends v with 17 significant digits (round-trips a double exactly), locale-independent.
void append_number(std::string& line, double v);

/// A subcommand's action, run after the whole command line parsed.
using action = std::function<void()>;

} // namespace varsym::cli
