// varsym/models/event.hpp: an ensemble member's event, an expression in q1..qd, p1..pd and t
// whose change of sign stops the member (the tool's --event, Python's event=): compiled once,
// then evaluated through a copy per member, since a tape keeps its registers.
#pragma once

#include <functional>
#include <span>
#include <string>

#include "varsym/expression/tape.hpp"

namespace varsym::models {

/// The event function simulation::run_member takes.
using event_function =
    std::function<double(double, std::span<const double>, std::span<const double>)>;

/// Compiles `text` for d coordinates (inputs q1..qd, p1..pd, t in that order); throws
/// expr::parse_error or std::invalid_argument naming what is wrong.
expr::tape compile_event(const std::string& text, int d);

/// An event function evaluating its own copy of `tape` (safe while other members run).
event_function event_of(const expr::tape& tape);

} // namespace varsym::models
