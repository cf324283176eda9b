// models/src/model.cpp: what every model shares: its parameters' ranges and checks, the lookup
// of models and keys, and the closest names for "did you mean" messages.
#include "varsym/models/model.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace varsym::models {

namespace {

std::string number(double v) {
    std::ostringstream s;
    s.precision(10);
    s << v;
    return s.str();
}

/// The Levenshtein distance of a and b.
std::size_t distance(std::string_view a, std::string_view b) {
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j)
        row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        std::size_t diagonal = row[0];
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t up = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
            diagonal = up;
        }
    }
    return row[b.size()];
}

} // namespace

std::string parameter::option_name() const {
    if (!option.empty()) return option;
    std::string o = name;
    std::replace(o.begin(), o.end(), '_', '-');
    return o;
}

std::string parameter::range() const {
    if (flag) return "0 or 1";
    if (integer) {
        parameter real = *this;
        real.integer = false;
        return "a whole number, " + real.range();
    }
    const bool low = std::isfinite(lower), high = std::isfinite(upper);
    if (low && lower == 0.0 && lower_open && !high) return "positive";
    if (low && lower == 0.0 && !lower_open && !high) return "non-negative";
    std::string r;
    if (low) r += number(lower) + (lower_open ? " < " : " <= ");
    if (low || high) r += name;
    if (high) r += (upper_open ? " < " : " <= ") + number(upper);
    return r.empty() ? "finite" : r;
}

void parameter::check(double v) const {
    if (std::isnan(v) && !nan_means.empty()) return;
    if (flag && v != 0.0 && v != 1.0)
        throw std::invalid_argument(name + " is a switch: 0 (off) or 1 (on), got " + number(v));
    if (integer && std::isfinite(v) && v != std::round(v))
        throw std::invalid_argument(name + " must be a whole number, got " + number(v));
    const bool ok = std::isfinite(v) && (lower_open ? v > lower : v >= lower) &&
                    (upper_open ? v < upper : v <= upper);
    if (!ok)
        throw std::invalid_argument(
            name + " must be " + (range() == "finite" ? "a finite number" : range()) +
            (nan_means.empty() ? "" : " (or NaN: " + nan_means + ")") + ", got " + number(v));
}

std::string list_parameter::option_name() const {
    parameter p;
    p.name = name;
    p.option = option;
    return p.option_name();
}

parameter list_parameter::each() const {
    parameter p;
    p.name = name;
    p.lower = lower;
    p.upper = upper;
    p.lower_open = lower_open;
    return p;
}

std::string list_parameter::range() const {
    parameter p = each();
    p.name = "each";
    return p.range();
}

void list_parameter::check(const std::vector<double>& v) const {
    const parameter p = each();
    for (double x : v)
        p.check(x);
}

std::vector<double> model::defaults() const {
    std::vector<double> v;
    for (const parameter& p : parameters)
        v.push_back(p.value);
    return v;
}

int model::parameter_index(std::string_view key) const {
    for (std::size_t i = 0; i < parameters.size(); ++i)
        if (parameters[i].name == key) return static_cast<int>(i);
    return -1;
}

problem model::prepare(std::span<const double> values, const start& s,
                       const models::lists& given) const {
    auto fail = [&](const std::string& what) { throw std::invalid_argument(name + ": " + what); };
    if (values.size() != parameters.size())
        fail(std::to_string(parameters.size()) + " parameter values needed, got " +
             std::to_string(values.size()));
    if (!given.empty() && given.size() != lists.size())
        fail(std::to_string(lists.size()) + " lists needed, got " + std::to_string(given.size()));
    const models::lists l = given.empty() ? models::lists(lists.size()) : given;
    int d = 0;
    try {
        for (std::size_t i = 0; i < parameters.size(); ++i)
            parameters[i].check(values[i]);
        for (std::size_t i = 0; i < lists.size(); ++i)
            lists[i].check(l[i]);
        d = dimension_at(values, l);
    } catch (const std::invalid_argument& e) {
        fail(e.what());
    }
    if (!fixed_start.empty() && !(s.q0.empty() && s.p0.empty() && s.v0.empty())) fail(fixed_start);
    if (!s.p0.empty() && !s.v0.empty()) fail("give p0 or v0, not both");
    if (!velocities && !s.v0.empty()) fail("p = dq/dt here: give p0, not v0");
    for (const auto& [v, what] : {std::pair{&s.q0, "q0"}, {&s.p0, "p0"}, {&s.v0, "v0"}}) {
        const int n = static_cast<int>(v->size());
        const bool short_one =
            v != &s.p0 && std::find(short_start.begin(), short_start.end(), n) != short_start.end();
        if (n != 0 && n != d && !short_one)
            fail(std::string(what) + " needs " + std::to_string(d) + " value" +
                 (d == 1 ? "" : "s") + " (" + coordinates + ")" +
                 (short_start.empty() || v == &s.p0 ? "" : " or " + short_start_doc) + ", got " +
                 std::to_string(n));
        for (double x : *v)
            if (!std::isfinite(x)) fail(std::string(what) + " must be finite");
    }
    problem pr;
    try {
        pr = make(values, s, l);
    } catch (const std::invalid_argument& e) {
        fail(e.what());
    }
    // Parameters in range may still give a start that is not a number (henon-heiles' energy
    // 1e308: p = inf): refused here, before any step or row.
    for (const auto* v : {&pr.q0, &pr.p0})
        if (!std::all_of(v->begin(), v->end(), [](double x) { return std::isfinite(x); }))
            fail(std::string("the initial state is not finite (") + (v == &pr.q0 ? "q0" : "p0") +
                 "): check the parameters and the start");
    return pr;
}

const model* find(std::string_view name) {
    for (const model& m : registry())
        if (m.name == name) return &m;
    return nullptr;
}

const model& get(std::string_view name) {
    if (const model* m = find(name)) return *m;
    std::vector<std::string> names;
    for (const model& m : registry())
        names.push_back(m.name);
    const auto near = closest(name, names);
    std::string all;
    for (const auto& n : names)
        all += (all.empty() ? "" : ", ") + n;
    throw std::invalid_argument("no model '" + std::string(name) + "'" +
                                (near.empty() ? "" : "; did you mean '" + near.front() + "'?") +
                                " The models: " + all);
}

std::vector<std::string> closest(std::string_view word,
                                 const std::vector<std::string>& candidates) {
    std::vector<std::pair<std::size_t, std::string>> scored;
    const std::size_t limit = word.size() / 3 + 1;
    for (const auto& c : candidates)
        if (const std::size_t d = distance(word, c); d <= limit) scored.emplace_back(d, c);
    std::stable_sort(scored.begin(), scored.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<std::string> out;
    for (auto& [d, c] : scored)
        out.push_back(std::move(c));
    return out;
}

} // namespace varsym::models

namespace varsym::models {

std::vector<std::string> simulation::state_columns() const {
    const int d = dim();
    if (d == 1) return {"q", "p"};
    std::vector<std::string> names;
    for (const char* prefix : {"q_", "p_"})
        for (int i = 1; i <= d; ++i)
            names.push_back(prefix + std::to_string(i));
    return names;
}

void simulation::state_values(std::span<double> out) const {
    const auto qs = q(), ps = p();
    if (out.size() < qs.size() + ps.size())
        throw std::invalid_argument("simulation::state_values: room for " +
                                    std::to_string(qs.size() + ps.size()) + " values needed");
    std::copy(ps.begin(), ps.end(), std::copy(qs.begin(), qs.end(), out.begin()));
}

} // namespace varsym::models
