// varsym/systems/lagrangian_time.hpp: ∂L/∂t of a Lagrangian that depends on time, which the
// general engine needs for the energy balance E − E0 − W, W = −∫∂L/∂t dt (+ the forces' work):
// dE/dt = −∂L/∂t along the motion (Lanczos, The Variational Principles of Mechanics, §V.6).
//
// Three ways to have it:
//   - L gives time_derivative(q, v, t) and depends_on_time() (expression_lagrangian does);
//   - L's call takes the time as a template parameter, e.g.
//         template <class T, class S> T operator()(const tvec<T, D>& q, const tvec<T, D>& v,
//                                                  S t) const
//     and returns T when S = T: then forward-mode automatic differentiation in t gives ∂L/∂t
//     exactly (one ad::first_order<1> pass at fixed q and v);
//   - neither (a time argument of type double): ∂L/∂t is not known, and a run watches no energy.
#pragma once

#include "varsym/autodiff/second_order.hpp"
#include "varsym/systems/lagrangian.hpp"

namespace varsym {

/// A Lagrangian that gives ∂L/∂t by hand: time_derivative(q, v, t) and depends_on_time().
template <class L>
concept lagrangian_with_time_derivative = requires(const L& l, const vec<L::dim>& q) {
    { l.time_derivative(q, q, 0.0) } -> std::convertible_to<double>;
    { l.depends_on_time() } -> std::convertible_to<bool>;
};

/// A time-dependent Lagrangian whose call can be differentiated in t: callable with the time
/// as an automatic-differentiation scalar (see the header comment).
template <class L>
concept lagrangian_differentiable_in_time = time_dependent_lagrangian<L> &&
    requires(const L& l, const tvec<ad::first_order<1>, L::dim>& q, const ad::first_order<1>& t) {
    { l(q, q, t) } -> std::convertible_to<ad::first_order<1>>;
};

/// Whether ∂L/∂t is available: by hand, or by differentiation in t; trivially (zero) for a
/// Lagrangian that does not depend on time.
template <class L>
concept lagrangian_time_known = lagrangian<L> &&
    (!time_dependent_lagrangian<L> || lagrangian_with_time_derivative<L> ||
     lagrangian_differentiable_in_time<L>);

/// Whether L depends on time at all (an expression Lagrangian knows: ∂L/∂t simplified to zero
/// means autonomous, whatever its text names).
template <lagrangian L>
bool depends_on_time(const L& l) {
    if constexpr (lagrangian_with_time_derivative<L>)
        return l.depends_on_time();
    else
        return time_dependent_lagrangian<L>;
}

/// ∂L/∂t at (q, q̇ = v, t), for an L with lagrangian_time_known (0 for an autonomous one).
template <lagrangian L>
requires lagrangian_time_known<L>
double time_derivative(const L& l, const vec<L::dim>& q, const vec<L::dim>& v, double t) {
    if constexpr (lagrangian_with_time_derivative<L>) {
        return l.time_derivative(q, v, t);
    } else if constexpr (lagrangian_differentiable_in_time<L>) {
        using J = ad::first_order<1>;
        const tvec<J, L::dim> qj = q.template cast<J>(), vj = v.template cast<J>();
        const J tj(t, 1, 0);
        return J(l(qj, vj, tj)).derivatives()(0);
    } else {
        return 0.0;
    }
}

} // namespace varsym
