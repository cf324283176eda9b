// varsym/run/state.hpp: the state of a run that a library user keeps, saves and resumes: (q, p),
// the compensated-summation carries, the stepper's history (the previous step, for a predictor
// that continues it), the step index and the Newton statistics. A stepper put
// back into a saved run_state continues bit for bit as the uninterrupted run would have.
#pragma once

#include <concepts>
#include <cstddef>
#include <type_traits>
#include <utility>
#include <vector>

#include "varsym/integrate.hpp"
#include "varsym/stepper.hpp"

namespace varsym {

/// Everything the next step of a resumable stepper depends on, and where the run stands.
template <int D>
struct run_state {
    phase_state<D> x;        ///< (q_j, p_j)
    vec<D> carry_q, carry_p; ///< low-order bits not yet added to q and p (compensated summation)
    std::size_t step = 0;    ///< j: x is the state at t_j = t0 + j h
    double t0 = 0.0;         ///< the time of step 0
    run_summary stats;       ///< Newton statistics of steps 1 … j
    /// What else the stepper's next step depends on (galerkin::stepper::save_history: the
    /// previous step's increments, a kept Jacobian's point); empty for most steppers and options.
    std::vector<double> history;

    /// A run that starts at x at time t0, with no carries.
    static run_state start(const phase_state<D>& x, double t0 = 0.0) {
        run_state s;
        s.x = x;
        s.carry_q = vec<D>::Zero(x.q.size());
        s.carry_p = vec<D>::Zero(x.p.size());
        s.t0 = t0;
        return s;
    }
    /// t_j = t0 + j h.
    [[nodiscard]] double time(double h) const { return t0 + static_cast<double>(step) * h; }
};

/// A stepper whose next step may also depend on its previous ones, and that hands that history
/// over as numbers and takes it back.
template <class S>
concept history_stepper = requires(const S& cs, S& s, std::vector<double>& out,
                                   const phase_state<S::dim>& x) {
    cs.save_history(out);
    s.restore_history(x, out);
};

/// Copies the stepper's carries and history into s (s.x, s.step and s.stats are kept by
/// integrate_from).
template <resumable_stepper S>
void snapshot(S& stepper, run_state<S::dim>& s) {
    s.carry_q = stepper.summation().carry_q();
    s.carry_p = stepper.summation().carry_p();
    if constexpr (history_stepper<S>) stepper.save_history(s.history);
}

/// Puts the stepper's compensated summation and history back into the state s was saved in, so
/// that its next step from s.x is the step the saved run would have taken.
template <resumable_stepper S>
void restore(S& stepper, const run_state<S::dim>& s) {
    stepper.summation().restore(s.x, s.carry_q, s.carry_p);
    if constexpr (history_stepper<S>) stepper.restore_history(s.x, s.history);
}

/// Calls an observer that returns bool (true: stop the run) or nothing (never stops).
template <class Observer, class State>
bool observer_stops(Observer& observe, const State& s) {
    if constexpr (std::is_void_v<std::invoke_result_t<Observer&, const State&>>) {
        observe(s);
        return false;
    } else {
        return static_cast<bool>(observe(s));
    }
}

/// Steps s from s.step to step n (t_j = s.t0 + j h), keeping s whole after every step (x,
/// carries, step, statistics) and calling observe(s) then; observe may return true to stop the
/// run. Returns true when step n was reached, false when an observer stopped it. Throws
/// step_failure if a step does not converge; s is then the state of the last good step.
template <stepper S, class Observer>
bool integrate_from(S& stepper, run_state<S::dim>& s, std::size_t n, Observer&& observe) {
    while (s.step < n) {
        varsym::advance(stepper, s.x, s.t0, s.step + 1, s.stats);
        ++s.step;
        if constexpr (resumable_stepper<S>) snapshot(stepper, s);
        if (observer_stops(observe, std::as_const(s))) return s.step == n;
    }
    return true;
}

} // namespace varsym
