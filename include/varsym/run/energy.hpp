// varsym/run/energy.hpp: the energy a run watches, for any system and stepper: E at a state and
// time (a time-dependent system takes the time), whether it is conserved, and E − W for a
// stepper with forces (W the forces' work since the start, which makes E − W constant up to the
// scheme's error).
#pragma once

#include "varsym/types.hpp"

namespace varsym {

/// Whether a system is time-dependent (its members take the time).
template <class System>
inline constexpr bool timed_system = requires {
    requires System::time_dependent;
};

/// The energy at state x and time t (t is ignored by a time-independent system).
template <class System, int D>
double energy_at(const System& sys, const phase_state<D>& x, double t) {
    if constexpr (timed_system<System>)
        return sys.energy(x, t);
    else
        return sys.energy(x);
}

/// Whether the system's energy is conserved (not for a Lagrangian that depends on time).
template <class System>
bool conserves_energy(const System& sys) {
    if constexpr (requires { sys.lagrangian().depends_on_time(); })
        return !sys.lagrangian().depends_on_time();
    else
        return !timed_system<System>;
}

/// What the energy watch follows: E, or E − W for a stepper with forces, at time t.
template <class Stepper, int D>
double watched_energy(const Stepper& stepper, const phase_state<D>& x, double t) {
    if constexpr (requires { stepper.total_work(); })
        return energy_at(stepper.system(), x, t) - stepper.total_work();
    else
        return energy_at(stepper.system(), x, t);
}

} // namespace varsym
