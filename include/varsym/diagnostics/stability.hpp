// varsym/diagnostics/stability.hpp: linear stability of a scheme (where the step map of the
// harmonic oscillator stops being stable) and the highest frequency of a system at a state, the
// two numbers that turn "Newton failed" into "this step size is too large by so much".
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "varsym/solvers/eigenvalues.hpp"
#include "varsym/systems/lagrangian.hpp"
#include "varsym/systems/separable.hpp"
#include "varsym/types.hpp"

namespace varsym {

/// The step map of the unit harmonic oscillator (M = 1, V = q²/2, ω = 1) at step h = z:
/// `step(z, x)` advances x (1-dimensional) by one step of size z. Returns the trace of the
/// 2×2 linear map (its columns are the images of (1, 0) and (0, 1)). A symplectic map has
/// determinant 1, so it is stable (bounded powers) when |trace| < 2 and unstable when
/// |trace| > 2. Returns NaN if a step fails.
template <class Step>
double oscillator_trace(Step&& step, double z) {
    phase_state<1> e1{vec<1>{1.0}, vec<1>{0.0}}, e2{vec<1>{0.0}, vec<1>{1.0}};
    if (!step(z, e1) || !step(z, e2)) return std::numeric_limits<double>::quiet_NaN();
    return e1.q(0) + e2.p(0);
}

/// An interval of h·ω on which a scheme's step map of the harmonic oscillator is unstable.
struct instability_interval {
    double from, to; ///< `to` is infinity if it does not end below the scan's end
};

/// Scans z = h·ω over (0, z_max] in steps dz and returns the intervals where |trace| > 2 (ends
/// refined by bisection to ~1e-12). A Gauss member's trace touches −2 at its resonances
/// (the map is −I there) without passing it; `slack` keeps those out.
template <class Step>
std::vector<instability_interval> instability_intervals(Step&& step, double z_max, double dz = 1e-3,
                                                        double slack = 1e-9) {
    auto unstable = [&](double z) {
        const double tr = oscillator_trace(step, z);
        return !(std::abs(tr) <= 2.0 + slack);
    };
    auto edge = [&](double lo, double hi) { // unstable(lo) != unstable(hi)
        const bool at_lo = unstable(lo);
        for (int i = 0; i < 60 && hi - lo > 1e-13 * hi; ++i) {
            const double mid = 0.5 * (lo + hi);
            (unstable(mid) == at_lo ? lo : hi) = mid;
        }
        return 0.5 * (lo + hi);
    };
    std::vector<instability_interval> out;
    bool was = false;
    double prev = 0.0;
    for (double z = dz; z <= z_max + 0.5 * dz; z += dz) {
        const bool now = unstable(z);
        if (now && !was) out.push_back({edge(prev, z), std::numeric_limits<double>::infinity()});
        if (!now && was) out.back().to = edge(prev, z);
        was = now;
        prev = z;
    }
    return out;
}

/// The linear stability limit: the start of the first instability interval below z_max, or
/// infinity if the scheme is stable on the whole scan.
template <class Step>
double linear_stability_limit(Step&& step, double z_max, double dz = 1e-3) {
    const auto intervals = instability_intervals(std::forward<Step>(step), z_max, dz);
    return intervals.empty() ? std::numeric_limits<double>::infinity() : intervals.front().from;
}

/// The highest frequency ω of the linearized motion at q: √λ for the largest λ of
/// ∇²V(q) v = λ M v (0 if no λ is positive). A system may supply a cheaper bound as a member
/// `highest_frequency(x)` (the chain: a Gershgorin bound in O(d)), which is used instead.
template <separable S>
double highest_frequency(const S& sys, const phase_state<S::dim>& x) {
    if constexpr (requires {
                      { sys.highest_frequency(x) } -> std::convertible_to<double>;
                  }) {
        return sys.highest_frequency(x);
    } else {
        constexpr int D = S::dim;
        const mat<D> hess = sys.potential().hessian(x.q);
        mat<D> mass;
        if constexpr (scalar_mass<S>)
            mass = sys.mass() * mat<D>::Identity(hess.rows(), hess.cols());
        else
            mass = sys.mass();
        const auto lambda = generalized_eigenvalues<D>(hess, mass);
        if (!lambda) return std::numeric_limits<double>::quiet_NaN();
        return std::sqrt(std::max(0.0, lambda->maxCoeff()));
    }
}

/// The same for L(q, q̇) at the velocity of (q, p): ∂²L/∂q̇² a = ∂²L/∂q² δq, so λ are the
/// eigenvalues of (−L_qq, L_vv). Velocity-dependent (gyroscopic) terms are left out: they turn
/// frequencies but do not raise the largest one beyond this estimate by much.
/// A time-dependent L is taken at time `time`.
template <class L>
double highest_frequency(const lagrangian_system<L>& sys, const phase_state<L::dim>& x,
                         double time) {
    constexpr int D = L::dim;
    lagrangian_terms<D> t;
    evaluate(sys.lagrangian(), x.q, sys.velocity(x.q, x.p, time), time, t);
    const mat<D> k = -t.lqq;
    const auto lambda = generalized_eigenvalues<D>(k, t.lvv);
    if (!lambda) return std::numeric_limits<double>::quiet_NaN();
    return std::sqrt(std::max(0.0, lambda->maxCoeff()));
}
template <class L>
double highest_frequency(const lagrangian_system<L>& sys,
                         const phase_state<L::dim>& x) requires(!time_dependent_lagrangian<L>) {
    return highest_frequency(sys, x, 0.0);
}

} // namespace varsym
