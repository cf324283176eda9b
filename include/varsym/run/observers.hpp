// varsym/run/observers.hpp: ready-made observers for integrate_from(stepper, run_state, n, obs):
// every E-th step, until a time, checkpoints by steps or by wall time, and several at once. An
// observer is called with the run_state after each step and returns true to stop the run.
#pragma once

#include <chrono>
#include <cstddef>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "varsym/run/state.hpp"

namespace varsym::observe {

/// Calls f(s) after every E-th step (steps E, 2E, …); stops the run if f returns true.
template <class F>
auto every(std::size_t e, F f) {
    if (e == 0) throw std::invalid_argument("observe::every needs a period of at least 1 step");
    return [e, f = std::move(f)](const auto& s) mutable {
        return s.step % e == 0 && observer_stops(f, s);
    };
}

/// Stops the run once its time t_j = t0 + j h reaches t_end (within half a step, so that a
/// t_end meant as a multiple of h is not missed by round-off).
inline auto until_time(double t_end, double h) {
    return [t_end, h](const auto& s) { return s.time(h) >= t_end - 0.5 * h; };
}

/// Calls save(s) every k steps: a checkpoint by steps. save's result is ignored.
template <class F>
auto checkpoint_every_steps(std::size_t k, F save) {
    if (k == 0) throw std::invalid_argument("checkpoint_every_steps needs at least 1 step");
    return [k, save = std::move(save)](const auto& s) mutable {
        if (s.step % k == 0) save(s);
        return false;
    };
}

/// Calls save(s) after the first step that ends at least `seconds` of wall time after the last
/// save (or after the observer was made): a checkpoint by wall time. The clock is read every
/// step; it costs tens of nanoseconds, small against a step.
template <class F, class Clock = std::chrono::steady_clock>
auto checkpoint_every_seconds(double seconds, F save) {
    if (!(seconds > 0.0))
        throw std::invalid_argument("checkpoint_every_seconds needs a positive interval");
    const auto interval = std::chrono::duration_cast<typename Clock::duration>(
        std::chrono::duration<double>(seconds));
    return [interval, last = Clock::now(), save = std::move(save)](const auto& s) mutable {
        const auto now = Clock::now();
        if (now - last >= interval) {
            save(s);
            last = now;
        }
        return false;
    };
}

/// Several observers as one, each called after every step in the order given; the run stops
/// when any of them asks it to (the others still see that step).
template <class... Observers>
auto all(Observers... obs) {
    return [obs = std::make_tuple(std::move(obs)...)](const auto& s) mutable {
        bool stop = false;
        std::apply([&](auto&... o) { ((stop = observer_stops(o, s) || stop), ...); }, obs);
        return stop;
    };
}

} // namespace varsym::observe
