// varsym/run/energy.hpp: the energy a run watches, for any system and stepper: E at a state and
// time (a time-dependent system takes the time), whether it is conserved, and E − W for a
// stepper with forces (W the forces' work since the start, which makes E − W constant up to the
// scheme's error).
#pragma once

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "varsym/systems/lagrangian_time.hpp"
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

/// Whether the energy a run watches (E, or E − W) is conserved up to the scheme's error: not
/// for a Lagrangian that depends on time, unless ∂L/∂t is known (systems/lagrangian_time.hpp),
/// which the general engine then puts into W (schemes/variational.hpp).
template <class System>
bool conserves_energy(const System& sys) {
    if constexpr (requires { sys.lagrangian(); }) {
        using L = std::remove_cvref_t<decltype(sys.lagrangian())>;
        return lagrangian_time_known<L> || !depends_on_time(sys.lagrangian());
    } else {
        return !timed_system<System>;
    }
}

/// What the energy watch follows: E, or E − W for a stepper with forces, at time t.
template <class Stepper, int D>
double watched_energy(const Stepper& stepper, const phase_state<D>& x, double t) {
    if constexpr (requires { stepper.total_work(); })
        return energy_at(stepper.system(), x, t) - stepper.total_work();
    else
        return energy_at(stepper.system(), x, t);
}

/// The default bound of an energy watch for a scheme of order r at step h, where ω is the highest
/// frequency the step must resolve: the expected relative energy error is about (hω)^r, and the
/// bound is 100 times that, between 1 % and 50 %.
inline double default_energy_bound(int order, double h, double omega) {
    const double z = std::isfinite(omega) && omega > 0.0 ? h * omega : 0.0;
    return std::clamp(100.0 * std::pow(z, order), 0.01, 0.5);
}

/// An energy watch: the relative error |E − E0| / scale of the energy a run follows (scale |E0|,
/// or 1 where |E0| < 1e-8) against a bound (0: off). A NaN or infinite energy exceeds any bound.
class energy_watch {
  public:
    energy_watch() = default;
    energy_watch(double e0, double bound)
        : e0_(e0), scale_(std::abs(e0) >= 1e-8 ? std::abs(e0) : 1.0), bound_(bound) {}
    [[nodiscard]] double error(double e) const { return std::abs(e - e0_) / scale_; }
    [[nodiscard]] bool on() const { return bound_ > 0.0; }
    [[nodiscard]] bool exceeded(double e) const { return on() && !(error(e) <= bound_); }
    [[nodiscard]] double bound() const { return bound_; }

  private:
    double e0_ = 0.0, scale_ = 1.0, bound_ = 0.0;
};

} // namespace varsym
