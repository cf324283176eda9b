// varsym/systems/separable_failure.hpp: why a step of a separable stepper (Newmark, Simpson, the
// family) failed, where it can be named: the step's start NaN or infinite, or the potential's
// value or gradient NaN or infinite at the start or along the free motion the step begins
// from (what the general engine's diagnosis says of L, schemes/variational_failure.hpp).
#pragma once

#include <array>
#include <cmath>
#include <cstdio>
#include <string>

#include "varsym/systems/separable.hpp"
#include "varsym/types.hpp"

namespace varsym {

/// The cause of a failed step from x over [t, t + h], or empty if none of these is found.
template <separable System>
std::string separable_failure(const System& sys, const phase_state<System::dim>& x, double t,
                              double h) {
    if (!x.q.allFinite() || !x.p.allFinite())
        return "the state the step started from is NaN or infinite";
    vec<System::dim> v;
    if constexpr (scalar_mass<System>)
        v = x.p * sys.inverse_mass();
    else
        v = sys.inverse_mass() * x.p;
    for (const double tau : std::array{0.0, 0.5, 1.0}) {
        const vec<System::dim> q = x.q + (tau * h) * v;
        const double value = sys.potential().value(q);
        if (std::isfinite(value) && sys.potential().gradient(q).allFinite()) continue;
        char buf[200];
        std::snprintf(buf, sizeof buf,
                      "the potential or its gradient is NaN or infinite %s (t = %.9g)",
                      tau == 0.0 ? "at the step's start" : "on the step's free motion q + t M^-1 p",
                      t + tau * h);
        return buf;
    }
    return {};
}

} // namespace varsym
