// apps/varsym/options/cli_common.cpp: option validators (correctly rounded, decimal only) and
// number formatting.
#include "options/cli_common.hpp"

#include <charconv>
#include <cmath>

namespace varsym::cli {

namespace {

// std::from_chars over the whole of s after an optional leading '+' ("+-", "++" and "" fail):
// decimal only, correctly rounded for reals, false on trailing text or overflow.
template <class T, class... Format>
bool from_whole(const std::string& s, T& v, Format... format) {
    const char* first = s.data() + (s.starts_with('+') ? 1 : 0);
    const char* last = s.data() + s.size();
    if (first == last || (first != s.data() && (*first == '+' || *first == '-'))) return false;
    auto [ptr, ec] = std::from_chars(first, last, v, format...);
    return ec == std::errc() && ptr == last;
}

bool parse_double(const std::string& s, double& v) {
    return from_whole(s, v, std::chars_format::general);
}

// A whole number in decimal ("010" is ten), or a real that is one exactly (1e3, 1000.0).
bool parse_whole(const std::string& s, long long& v) {
    if (from_whole(s, v)) return true;
    double d = 0.0;
    if (!parse_double(s, d) || d != std::floor(d) || std::abs(d) >= 9.2e18) return false;
    v = static_cast<long long>(d);
    return true;
}

// The comma-separated entries of s ("1,,2" has an empty second one).
std::vector<std::string> list_items(const std::string& s) {
    std::vector<std::string> items;
    std::size_t start = 0;
    for (std::size_t comma; (comma = s.find(',', start)) != std::string::npos; start = comma + 1)
        items.push_back(s.substr(start, comma - start));
    items.push_back(s.substr(start));
    return items;
}

/// A double as a C99 hexadecimal float: what CLI11's strtold-based conversion reads exactly.
std::string exact_text(double v) {
    char buf[48];
    char* out = buf;
    if (std::signbit(v)) *out++ = '-';
    *out++ = '0';
    *out++ = 'x';
    auto [end, ec] = std::to_chars(out, buf + sizeof buf, std::abs(v), std::chars_format::hex);
    return std::string(buf, end);
}

CLI::Validator real_check(const char* name, double lo, double hi, bool open_lo, bool open_hi) {
    return CLI::Validator(
        [lo, hi, open_lo, open_hi](std::string& s) -> std::string {
            double v = 0;
            if (!parse_double(s, v)) return shown(s) + " is not a number";
            if (!std::isfinite(v)) return shown(s) + " is not finite";
            if (open_lo ? !(v > lo) : !(v >= lo)) {
                std::string bound;
                append_number(bound, lo);
                return std::string("must be ") + (open_lo ? "> " : ">= ") + bound + ", got " +
                       shown(s);
            }
            if (open_hi ? !(v < hi) : !(v <= hi)) {
                std::string bound;
                append_number(bound, hi);
                return std::string("must be ") + (open_hi ? "< " : "<= ") + bound + ", got " +
                       shown(s);
            }
            s = exact_text(v);
            return {};
        },
        name);
}

CLI::Validator integer_check(const char* name, long long min) {
    return CLI::Validator(
        [min](std::string& s) -> std::string {
            long long v = 0;
            if (!parse_whole(s, v)) return shown(s) + " is not a whole number";
            if (v < min) return "must be >= " + std::to_string(min) + ", got " + shown(s);
            s = std::to_string(v);
            return {};
        },
        name);
}

constexpr double inf = std::numeric_limits<double>::infinity();

} // namespace

std::string shown(const std::string& s) {
    constexpr std::size_t limit = 40;
    if (s.size() <= limit) return "'" + s + "'";
    return "'" + s.substr(0, limit) + "...' (" + std::to_string(s.size()) + " characters)";
}

const CLI::Validator finite_number = real_check("REAL", -inf, inf, false, false);
const CLI::Validator positive_number = real_check("REAL>0", 0.0, inf, true, false);
const CLI::Validator non_negative_number = real_check("REAL>=0", 0.0, inf, false, false);
const CLI::Validator positive_integer = integer_check("INT>0", 1);
const CLI::Validator non_negative_integer = integer_check("INT>=0", 0);

CLI::Validator number_in(double lo, double hi, const char* name, bool open_hi) {
    return real_check(name, lo, hi, false, open_hi);
}

const CLI::Validator number_list(
    [](std::string& s) -> std::string {
        const std::vector<std::string> items = list_items(s);
        for (std::size_t i = 0; i < items.size(); ++i) {
            const std::string index = std::to_string(i + 1);
            double v = 0;
            if (items[i].empty())
                return "value " + index + " of " + shown(s) +
                       " is empty (give numbers separated by single commas)";
            if (!parse_double(items[i], v))
                return "value " + index + ", " + shown(items[i]) + ", is not a number";
            if (!std::isfinite(v))
                return "value " + index + ", " + shown(items[i]) + ", is not finite";
        }
        return {};
    },
    "");

std::vector<double> parse_number_list(const std::string& s) {
    std::vector<double> out;
    if (s.empty()) return out;
    for (const std::string& item : list_items(s)) {
        out.push_back(0.0);
        parse_double(item, out.back());
    }
    return out;
}

void append_number(std::string& line, double v) {
    char buf[40];
    auto [ptr, ec] = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 17);
    line.append(buf, ptr);
}

} // namespace varsym::cli
