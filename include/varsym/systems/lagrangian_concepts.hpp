// varsym/systems/lagrangian_concepts.hpp: what a Lagrangian L(q, q̇) (or L(q, q̇, t)) is to the
// engines, what it may give by hand (derivatives, gradient, mass matrix and bias forces), and the
// terms its derivatives are evaluated into. systems/lagrangian.hpp differentiates the rest.
#pragma once

#include <concepts>
#include <type_traits>
#include <utility>

#include "varsym/types.hpp"

namespace varsym {

/// A D-vector of scalars T (double, or an automatic-differentiation scalar).
template <class T, int D>
using tvec = Eigen::Matrix<T, D, 1>;

/// L and its first and second derivatives at one point (q, v = q̇):
/// lqv(i, j) = ∂²L/∂q_i∂v_j (so ∂²L/∂v_i∂q_j is lqvᵀ).
template <int D>
struct lagrangian_terms {
    double value = 0.0;
    vec<D> lq, lv;
    mat<D> lqq, lqv, lvv;
};

/// What a Lagrangian must provide: `static constexpr int dim` (D ≥ 1, or `dynamic` with a
/// member `int dimension() const`) and
/// `template <class T> T operator()(const tvec<T, D>& q, const tvec<T, D>& v) const`,
/// callable with T = double and with the automatic-differentiation scalars (so: `using std::sin;`
/// before calling sin, and double literals, 2.0 not 2, in arithmetic with T).
/// A time-dependent Lagrangian L(q, q̇, t) gives instead
/// `template <class T> T operator()(const tvec<T, D>& q, const tvec<T, D>& v, double t) const`
/// (t is not differentiated; see time_dependent_lagrangian).
template <class L>
concept lagrangian_shape = requires {
    L::dim;
}
&&(L::dim >= 1 || L::dim == dynamic) && (L::dim != dynamic || requires(const L& l) {
    { l.dimension() } -> std::convertible_to<int>;
});

/// A Lagrangian L(q, q̇, t) that depends on time explicitly: callable as l(q, v, t). The engines
/// evaluate it at each quadrature point's time t_j + c_k h; its energy is not conserved
/// (dE/dt = −∂L/∂t). Derivatives by hand, if given, take the time too:
/// derivatives(q, v, t, terms) and optionally gradient(q, v, t, terms).
template <class L>
concept time_dependent_lagrangian = lagrangian_shape<L> &&
    requires(const L& l, const tvec<double, L::dim>& q, double t) {
    { l(q, q, t) } -> std::convertible_to<double>;
};

template <class L>
concept lagrangian = lagrangian_shape<L> &&
    (time_dependent_lagrangian<L> || requires(const L& l, const tvec<double, L::dim>& q) {
        { l(q, q) } -> std::convertible_to<double>;
    });

/// A time-dependent Lagrangian frozen at time t: a time-independent view of L(·, ·, t), with
/// L's derivatives by hand where it has them. at(l, t) makes one (and is l itself for a
/// time-independent L); it holds a reference to l.
template <time_dependent_lagrangian L>
struct at_time {
    static constexpr int dim = L::dim;
    const L& l;
    double t;

    [[nodiscard]] int dimension() const {
        if constexpr (dim == dynamic)
            return l.dimension();
        else
            return dim;
    }
    template <class T>
    T operator()(const tvec<T, dim>& q, const tvec<T, dim>& v) const {
        return l(q, v, t);
    }
    template <class Terms>
    void derivatives(const vec<dim>& q, const vec<dim>& v, Terms& terms) const requires
        requires(const L& ll, double tt) {
        ll.derivatives(q, v, tt, terms);
    }
    { l.derivatives(q, v, t, terms); }
    template <class Terms>
    void gradient(const vec<dim>& q, const vec<dim>& v, Terms& terms) const requires
        requires(const L& ll, double tt) {
        ll.gradient(q, v, tt, terms);
    }
    { l.gradient(q, v, t, terms); }
};

/// L at time t as a time-independent Lagrangian: at_time<L>{l, t}, or l itself (a reference)
/// when L does not depend on time.
template <lagrangian L>
decltype(auto) at(const L& l, double t) {
    if constexpr (time_dependent_lagrangian<L>)
        return at_time<L>{l, t};
    else
        return (l);
}

/// The type at(l, t) returns, by value: at_time<L> or L.
template <lagrangian L>
using at_time_t = std::remove_cvref_t<decltype(at(std::declval<const L&>(), 0.0))>;

/// A Lagrangian that also supplies its derivatives by hand (used instead of differentiation).
template <class L>
concept lagrangian_with_derivatives = lagrangian<L> &&
    requires(const L& l, const vec<L::dim>& q, lagrangian_terms<L::dim>& t) {
    l.derivatives(q, q, t);
};

/// A Lagrangian that also gives its first derivatives alone by hand, in
/// gradient(q, v, terms) filling lq and lv (value need not be set): what the linear iterations
/// of the general engine evaluate at every sweep (without it they call derivatives()).
template <class L>
concept lagrangian_with_gradient = lagrangian_with_derivatives<L> &&
    requires(const L& l, const vec<L::dim>& q, lagrangian_terms<L::dim>& t) {
    l.gradient(q, q, t);
};

/// A Lagrangian L = ½ q̇ᵀM(q)q̇ − V(q), quadratic in q̇ without a linear term (p = M(q)q̇), that
/// gives M(q) alone by hand, in mass_matrix(q, M), more cheaply than its second derivatives (a
/// robot's composite-rigid-body algorithm): lagrangian_system::velocity and the general
/// engine's predictor then solve p = M(q)q̇ with it. Time-independent only.
template <class L>
concept lagrangian_with_mass_matrix =
    lagrangian_with_derivatives<L> && !time_dependent_lagrangian<L> &&
    requires(const L& l, const vec<L::dim>& q, mat<L::dim>& m) {
    l.mass_matrix(q, m);
};

/// A lagrangian_with_mass_matrix that also gives the bias forces by hand, in
/// bias_forces(q, v, b): b = (∂²L/∂q̇∂q) q̇ − ∂L/∂q, so that M(q)q̈ + b = 0 are the Euler–Lagrange
/// equations (a robot's C(q, q̇)q̇ + g(q), by the recursive Newton–Euler algorithm). The general
/// engine's Newton predictor then needs no second derivatives at the step's start.
template <class L>
concept lagrangian_with_bias_forces = lagrangian_with_mass_matrix<L> &&
    requires(const L& l, const vec<L::dim>& q, const vec<L::dim>& v, vec<L::dim>& b) {
    l.bias_forces(q, v, b);
};

/// A lagrangian_with_mass_matrix that gives the bias forces after its mass matrix, at the same q
/// and on the same thread, in bias_forces_after_mass_matrix(q, v, b) (b as bias_forces' above):
/// a free base's (multibody/floating_dynamics.hpp). The constrained stepper's predictor then
/// needs no second derivatives at the step's start. It keeps no jerk history (that is
/// lagrangian_with_bias_forces').
template <class L>
concept lagrangian_with_bias_after_mass_matrix = lagrangian_with_mass_matrix<L> &&
    requires(const L& l, const vec<L::dim>& q, const vec<L::dim>& v, vec<L::dim>& b) {
    l.bias_forces_after_mass_matrix(q, v, b);
};

/// A Lagrangian that solves with its mass matrix by hand (a robot: multibody/articulated.hpp, in
/// O(n)): factor_mass(q), false where M(q) is not positive definite, then on the same thread
/// solve_mass(x), x ← M(q)⁻¹x, and mass_diagonal(), M(q)'s diagonal. The general engine's
/// articulated iteration takes them (schemes/variational_articulated.hpp); a solve_mass that
/// accepts an Eigen::Map of a d × s matrix is handed the s blocks at once, as its columns.
template <class L>
concept lagrangian_with_mass_solves = lagrangian_with_bias_forces<L> &&
    requires(const L& l, const vec<L::dim>& q, vec<L::dim>& x) {
    { l.factor_mass(q) } -> std::convertible_to<bool>;
    l.solve_mass(x);
    { l.mass_diagonal() } -> std::convertible_to<const Eigen::VectorXd&>;
};

} // namespace varsym
