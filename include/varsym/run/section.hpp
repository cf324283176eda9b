// varsym/run/section.hpp: Poincaré sections. A crossing of the plane q_i = c (or p_i = c) in a
// given direction is found on each step: first on the scheme's own interpolating polynomial
// over the step (dense output: `dense_output` of the simpson, newmark and family steppers and of
// the general engine), then refined by Newton on the scheme's own map of the shortened step from
// (q_j, p_j), so that the point lies on the discrete flow to the scheme's order, not to the
// polynomial's.
#pragma once

#include <cmath>
#include <optional>
#include <type_traits>
#include <utility>

#include "varsym/systems/forcing.hpp"
#include "varsym/systems/lagrangian.hpp"
#include "varsym/systems/separable.hpp"
#include "varsym/types.hpp"

namespace varsym {

/// The plane q_index = value (momentum = false) or p_index = value, crossed with the coordinate
/// increasing (direction +1), decreasing (−1) or either (0).
struct section_plane {
    bool momentum = false;
    int index = 0;
    double value = 0.0;
    int direction = 1;

    template <int D>
    [[nodiscard]] double distance(const phase_state<D>& x) const {
        return (momentum ? x.p(index) : x.q(index)) - value;
    }
    /// Whether the values g0 at the step's start and g1 at its end cross in the direction.
    [[nodiscard]] bool crossed(double g0, double g1) const {
        const bool up = g0 < 0.0 && g1 >= 0.0, down = g0 > 0.0 && g1 <= 0.0;
        return direction > 0 ? up : direction < 0 ? down : (up || down);
    }
};

/// What a section needs of a stepper's system at time t: the state on a step's polynomial from
/// q and q̇ there, and the rate of the plane's coordinate at a state. For a separable system
/// p = M q̇, q̇ = M⁻¹p and ṗ = −∇V(q); for a Lagrangian system (the general engine)
/// p = ∂L/∂q̇(q, q̇, t), q̇ from ∂L/∂q̇ = p, and ṗ = ∂L/∂q(q, q̇, t) + f(q, q̇, t) with a force.
namespace section_detail {
template <class S>
concept on_separable = separable<std::remove_cvref_t<decltype(std::declval<const S&>().system())>>;
template <class S>
concept on_lagrangian = requires(const S& s) {
    s.system().lagrangian();
};

template <on_separable S>
phase_state<S::dim> state_on(const S& s, const vec<S::dim>& q, const vec<S::dim>& qdot, double) {
    return {q, vec<S::dim>(s.system().mass() * qdot)};
}
template <on_separable S>
double rate_of(const S& s, const section_plane& plane, const phase_state<S::dim>& y, double) {
    if (plane.momentum) return -s.system().potential().gradient(y.q)(plane.index);
    return vec<S::dim>(s.system().inverse_mass() * y.p)(plane.index);
}
template <on_lagrangian S>
phase_state<S::dim> state_on(const S& s, const vec<S::dim>& q, const vec<S::dim>& qdot, double t) {
    return {q, s.system().momentum(q, qdot, t)};
}
template <on_lagrangian S>
double rate_of(const S& s, const section_plane& plane, const phase_state<S::dim>& y, double t) {
    constexpr int D = S::dim;
    const vec<D> v = s.system().velocity(y.q, y.p, t);
    if (!plane.momentum) return v(plane.index);
    lagrangian_terms<D> terms;
    evaluate_gradient(s.system().lagrangian(), y.q, v, t, terms);
    double rate = terms.lq(plane.index);
    if constexpr (S::forced) {
        const auto d = y.q.size();
        force_terms<D> f;
        f.f.setZero(d);
        f.fq.setZero(d, d);
        f.fv.setZero(d, d);
        evaluate_force(s.force(), y.q, v, t, f, false);
        rate += f.f(plane.index);
    }
    return rate;
}
} // namespace section_detail

/// A stepper with dense output and a copy at another step size (the separable steppers and the
/// general engine; not the constrained one, whose copy is of another type).
template <class S>
concept dense_stepper = requires(const S& s, const phase_state<S::dim>& x, vec<S::dim>& q, double h,
                                 const section_plane& plane) {
    s.dense_output(x, 0.5, q, q);
    { s.with_step_size(h) } -> std::same_as<S>;
    section_detail::state_on(s, x.q, x.q, h);
    section_detail::rate_of(s, plane, x, h);
};

/// A point of a section: the time t_j + τh and the state there.
template <int D>
struct section_point {
    double time = 0.0;
    phase_state<D> x;
    int refinements = 0; ///< Newton iterations on the scheme's map (0: on the polynomial alone)
};

/// The crossing of `plane` on the step just taken by s from `from` (at time t) to `to`, if the
/// step crosses it. `refine` = false stops at the polynomial's root (tests compare the two).
template <dense_stepper S>
std::optional<section_point<S::dim>> find_crossing(const S& s, const phase_state<S::dim>& from,
                                                   const phase_state<S::dim>& to, double t,
                                                   const section_plane& plane, bool refine = true) {
    constexpr int D = S::dim;
    const double g0 = plane.distance(from), g1 = plane.distance(to);
    if (!plane.crossed(g0, g1)) return std::nullopt;
    const double h = s.step_size();
    // The polynomial's state at τ: q(τ), and p(τ) from q̇(τ) = (dq/dτ)/h.
    vec<D> q(from.q.size()), dq(from.q.size());
    auto dense = [&](double tau) {
        s.dense_output(from, tau, q, dq);
        return section_detail::state_on(s, q, vec<D>(dq / h), t + tau * h);
    };
    // Regula falsi (Illinois) on the polynomial, bracketed by the step's two ends.
    double a = 0.0, b = 1.0, ga = g0, gb = g1, tau = g0 / (g0 - g1);
    for (int k = 0; k < 60 && b - a > 1e-15; ++k) {
        tau = (a * gb - b * ga) / (gb - ga);
        if (!(tau > a && tau < b)) tau = 0.5 * (a + b);
        const double g = plane.distance(dense(tau));
        if ((g < 0.0) == (ga < 0.0)) {
            a = tau;
            ga = g;
            gb *= 0.5;
        } else {
            b = tau;
            gb = g;
            ga *= 0.5;
        }
        if (g == 0.0) break;
    }
    section_point<D> out{t + tau * h, dense(tau), 0};
    if (!refine) return out;
    // Newton on τ ↦ plane(Φ_{τh}(q_j, p_j)), the scheme's own step of size τh; the derivative is
    // h times the plane coordinate's rate (q̇_i or ṗ_i, section_detail::rate_of).
    for (int k = 0; k < 8; ++k) {
        phase_state<D> y = from;
        if (tau > 0.0) {
            S part = s.with_step_size(tau * h);
            if constexpr (requires { part.set_time(t); }) part.set_time(t);
            if (!part.step(y).converged) break;
        }
        const double g = plane.distance(y);
        const double rate = section_detail::rate_of(s, plane, y, t + tau * h);
        out = {t + tau * h, y, k};
        if (g == 0.0 || rate == 0.0) break;
        const double next = tau - g / (h * rate);
        if (!(next > 0.0 && next <= 1.0)) break;
        if (std::abs(next - tau) <= 4e-16) {
            out.refinements = k + 1;
            break;
        }
        tau = next;
    }
    return out;
}

} // namespace varsym
