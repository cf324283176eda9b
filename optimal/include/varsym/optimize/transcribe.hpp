// varsym/optimize/transcribe.hpp: the one compiled transcription (transcription.hpp) of a C++
// Lagrangian written by the user, in one call: L driven by f = B u − C q̇ (input_system.hpp),
// or L with a control force F and optional holonomic constraints (system_of.hpp). A model of
// the models layer goes through varsym/optimize/model.hpp instead.
#pragma once

#include <memory>
#include <utility>

#include "varsym/optimal/input_system.hpp"
#include "varsym/optimal/system_of.hpp"
#include "varsym/optimize/transcription.hpp"

namespace varsym::optimal {

/// The transcription of `problem` for L driven by f = B u − C q̇, under the constraints g if
/// given (constraint_of_run_time_size).
template <lagrangian L, class C = unconstrained>
std::unique_ptr<dmoc_transcription> transcribe_inputs(L l, matrix b, const control_problem& problem,
                                                      matrix damping = {}, C constraints = {}) {
    return transcribe(std::make_shared<const input_system<L, C>>(
                          std::move(l), std::move(b), std::move(damping), std::move(constraints)),
                      problem);
}

/// The transcription of `problem` for L and F (automatic derivatives).
template <lagrangian L, control_force F>
std::unique_ptr<dmoc_transcription> transcribe(L l, F force, const control_problem& problem) {
    return transcribe(std::make_shared<const system_of<L, F>>(std::move(l), std::move(force)),
                      problem);
}

/// The transcription of `problem` for L under the holonomic constraints C, with F.
template <lagrangian L, holonomic_constraint C, control_force F>
std::unique_ptr<dmoc_transcription> transcribe(L l, C constraints, F force,
                                               const control_problem& problem) {
    return transcribe(std::make_shared<const system_of<L, F, C>>(std::move(l), std::move(force),
                                                                 std::move(constraints)),
                      problem);
}

} // namespace varsym::optimal
