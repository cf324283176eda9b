// varsym/solvers/solver_name.hpp: the names of how a step is solved, as the tool, its bench and
// the Python package spell them: ITERATION[+START], e.g. fixed-point+forces.
#pragma once

#include <array>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

#include "varsym/solvers/newton.hpp"

namespace varsym {

inline constexpr std::array<std::pair<std::string_view, iteration_kind>, 5> iteration_names{{
    {"automatic", iteration_kind::automatic},
    {"newton", iteration_kind::newton},
    {"simplified", iteration_kind::simplified},
    {"fixed-point", iteration_kind::fixed_point},
    {"articulated", iteration_kind::articulated},
}};

inline constexpr std::array<std::pair<std::string_view, predictor_kind>, 3> predictor_names{{
    {"taylor", predictor_kind::taylor},
    {"previous", predictor_kind::previous},
    {"forces", predictor_kind::forces},
}};

/// The enumerator named `name` in `table`, or nothing.
template <class Table>
constexpr auto named(const Table& table, std::string_view name)
    -> std::optional<typename Table::value_type::second_type> {
    for (const auto& [n, value] : table)
        if (n == name) return value;
    return std::nullopt;
}

/// The name of `value` in `table`.
template <class Table>
constexpr std::string_view name_of(const Table& table,
                                   typename Table::value_type::second_type value) {
    for (const auto& [n, v] : table)
        if (v == value) return n;
    return "?";
}

/// ITERATION[+START] (newton+previous, fixed-point+forces, simplified, ...) into `base`'s
/// iteration and start; a name without +START keeps `base`'s. Throws std::invalid_argument
/// naming the choices.
inline newton_options parse_solver(std::string_view name, newton_options base = {}) {
    const auto plus = name.find('+');
    const auto iteration = named(iteration_names, name.substr(0, plus));
    const auto start = plus == std::string_view::npos
                           ? std::optional<predictor_kind>(base.predictor)
                           : named(predictor_names, name.substr(plus + 1));
    if (!iteration || !start)
        throw std::invalid_argument("unknown solver '" + std::string(name) +
                                    "': automatic, newton, simplified, fixed-point or "
                                    "articulated, optionally "
                                    "followed by +taylor, +previous or +forces (the start)");
    base.iteration = *iteration;
    base.predictor = *start;
    return base;
}

/// The name parse_solver reads back into `opt`'s iteration and start.
inline std::string solver_name(const newton_options& opt) {
    std::string name(name_of(iteration_names, opt.iteration));
    if (opt.predictor != predictor_kind::taylor)
        name += "+" + std::string(name_of(predictor_names, opt.predictor));
    return name;
}

} // namespace varsym
