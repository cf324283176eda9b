// varsym/stepper.hpp: the stepper protocol, written as concepts. Every scheme of the library
// (simpson, newmark, galerkin, general) satisfies `resumable_stepper`; integrate() and the run
// state (run/state.hpp) are constrained by them, and a user's own stepper that satisfies them
// runs through the same drivers.
#pragma once

#include <concepts>

#include "varsym/solvers/newton.hpp"
#include "varsym/types.hpp"

namespace varsym {

/// Advances a phase_state<dim> by one step of fixed size and says how Newton fared.
template <class S>
concept stepper = requires {
    S::dim;
}
&&requires(S& s, const S& cs, phase_state<S::dim>& x) {
    { s.step(x) } -> std::same_as<newton_report>;
    { cs.step_size() } -> std::convertible_to<double>;
};

/// A stepper whose next step depends on (q, p) and its compensated-summation carries only, and
/// that can be put back into that state: what a bit-exact resume needs.
template <class S>
concept resumable_stepper = stepper<S> && requires(S& s, const phase_state<S::dim>& x) {
    { s.summation().carry_q() } -> std::convertible_to<vec<S::dim>>;
    { s.summation().carry_p() } -> std::convertible_to<vec<S::dim>>;
    s.summation().restore(x, x.q, x.p);
};

} // namespace varsym
