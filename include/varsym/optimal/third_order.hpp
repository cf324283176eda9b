// varsym/optimal/third_order.hpp: the Hessians an optimal control transcription needs for the
// exact Hessian of its Lagrangian: of ψ_L = aᵀ ∂L/∂q + bᵀ ∂L/∂q̇ in (q, q̇) (L's third derivatives
// contracted with the multipliers' direction (a, b)), and of ψ_f = aᵀ f(q, q̇, t, u) in
// (q, q̇, u). Forward-mode automatic differentiation: second_order scalars, with one directional
// derivative more on top for L (the dual numbers `directional` below).
#pragma once

#include <cmath>

#include "varsym/autodiff/second_order.hpp"
#include "varsym/systems/lagrangian.hpp"

namespace varsym::optimal {

/// x + ε y with ε² = 0 over second-order scalars S (value, gradient and Hessian in z): one
/// directional derivative on top of a Hessian, so that ∂/∂ε of L(z + ε w) carries the Hessian
/// of w · ∇L. A small type of our own rather than Eigen's AutoDiffScalar nested a third time:
/// that one cannot be made from a double (two conversions), so a Lagrangian written with
/// T(0.0) or 0.5 * v would not compile with it; this one takes every operation a Lagrangian
/// for the other engines uses (arithmetic with doubles, the functions of <cmath> below,
/// comparisons on the value).
template <class S>
struct directional {
    S x, y;
    directional() : x(0.0), y(0.0) {}
    directional(double v) : x(v), y(0.0) {} // NOLINT: implicit, as a double literal is used
    directional(const S& v, const S& d) : x(v), y(d) {}
    [[nodiscard]] double value() const { return x.value().value(); }

    friend directional operator+(const directional& a, const directional& b) {
        return {S(a.x + b.x), S(a.y + b.y)};
    }
    friend directional operator-(const directional& a, const directional& b) {
        return {S(a.x - b.x), S(a.y - b.y)};
    }
    friend directional operator*(const directional& a, const directional& b) {
        return {S(a.x * b.x), S(a.x * b.y + a.y * b.x)};
    }
    friend directional operator/(const directional& a, const directional& b) {
        const S q(a.x / b.x);
        return {q, S((a.y - q * b.y) / b.x)};
    }
    friend directional operator-(const directional& a) { return {S(-a.x), S(-a.y)}; }
    friend directional operator+(const directional& a) { return a; }
    directional& operator+=(const directional& b) { return *this = *this + b; }
    directional& operator-=(const directional& b) { return *this = *this - b; }
    directional& operator*=(const directional& b) { return *this = *this * b; }
    directional& operator/=(const directional& b) { return *this = *this / b; }
    friend bool operator<(const directional& a, const directional& b) {
        return a.value() < b.value();
    }
    friend bool operator>(const directional& a, const directional& b) {
        return a.value() > b.value();
    }
    friend bool operator<=(const directional& a, const directional& b) {
        return a.value() <= b.value();
    }
    friend bool operator>=(const directional& a, const directional& b) {
        return a.value() >= b.value();
    }
    friend bool operator==(const directional& a, const directional& b) {
        return a.value() == b.value();
    }

    friend directional sin(const directional& a) {
        using std::cos, std::sin;
        return {S(sin(a.x)), S(cos(a.x) * a.y)};
    }
    friend directional cos(const directional& a) {
        using std::cos, std::sin;
        return {S(cos(a.x)), S(-sin(a.x) * a.y)};
    }
    friend directional tan(const directional& a) {
        using std::tan;
        const S t(tan(a.x));
        return {t, S((1.0 + t * t) * a.y)};
    }
    friend directional exp(const directional& a) {
        using std::exp;
        const S e(exp(a.x));
        return {e, S(e * a.y)};
    }
    friend directional log(const directional& a) {
        using std::log;
        return {S(log(a.x)), S(a.y / a.x)};
    }
    friend directional sqrt(const directional& a) {
        using std::sqrt;
        const S r(sqrt(a.x));
        return {r, S(a.y / (2.0 * r))};
    }
    friend directional pow(const directional& a, double p) {
        using std::pow;
        return {S(pow(a.x, p)), S(p * pow(a.x, p - 1.0) * a.y)};
    }
    friend directional abs(const directional& a) { return a.value() < 0.0 ? -a : a; }
    friend directional atan2(const directional& a, const directional& b) {
        using std::atan2;
        return {S(atan2(a.x, b.x)), S((b.x * a.y - a.x * b.y) / (a.x * a.x + b.x * b.x))};
    }
};

} // namespace varsym::optimal

namespace Eigen {
template <class S>
struct NumTraits<varsym::optimal::directional<S>> : GenericNumTraits<double> {
    using Real = varsym::optimal::directional<S>;
    using NonInteger = Real;
    using Nested = Real;
    using Literal = double;
    enum {
        IsComplex = 0,
        IsInteger = 0,
        IsSigned = 1,
        RequireInitialization = 1,
        ReadCost = 1,
        AddCost = 8,
        MulCost = 16
    };
};
template <class S, typename BinaryOp>
struct ScalarBinaryOpTraits<varsym::optimal::directional<S>, double, BinaryOp> {
    using ReturnType = varsym::optimal::directional<S>;
};
template <class S, typename BinaryOp>
struct ScalarBinaryOpTraits<double, varsym::optimal::directional<S>, BinaryOp> {
    using ReturnType = varsym::optimal::directional<S>;
};
} // namespace Eigen

namespace varsym::optimal {

/// The scalar contracted_third evaluates a Lagrangian of fixed dimension in.
template <class L>
using third_scalar = directional<ad::second_order<2 * L::dim>>;

/// The Hessian in z = (q, v) (2D × 2D) of aᵀ ∂L/∂q(q, v, t) + bᵀ ∂L/∂v(q, v, t).
template <lagrangian L>
mat<2 * L::dim> contracted_third(const L& l, const vec<L::dim>& q, const vec<L::dim>& v, double t,
                                 const vec<L::dim>& a, const vec<L::dim>& b) {
    constexpr int D = L::dim, N = 2 * D;
    using S = ad::second_order<N>;
    using E = third_scalar<L>; // d/dε along (a, b)
    tvec<E, D> qe, ve;
    for (int i = 0; i < D; ++i) {
        qe(i) = E(ad::variable<N>(q(i), i), S(a(i)));
        ve(i) = E(ad::variable<N>(v(i), D + i), S(b(i)));
    }
    const E out = at(l, t)(qe, ve);
    vec<N> g;
    mat<N> h;
    ad::unpack(out.y, g, h);
    return h;
}

/// f(q, v, t, u) in second-order scalars over z = (q, v, u): its values carry their gradients
/// and Hessians in z. Also the velocities v as such scalars (the power cost multiplies by them).
template <class F>
struct force_in_z {
    static constexpr int D = F::dim, M = F::controls, N = 2 * D + M;
    using S = ad::second_order<N>;
    tvec<S, D> f, v;
    force_in_z(const F& force, const vec<D>& q, const vec<D>& vel, double t, const vec<M>& u) {
        tvec<S, D> qs;
        tvec<S, M> us;
        for (int i = 0; i < D; ++i) {
            qs(i) = ad::variable<N>(q(i), i);
            v(i) = ad::variable<N>(vel(i), D + i);
        }
        for (int i = 0; i < M; ++i)
            us(i) = ad::variable<N>(u(i), 2 * D + i);
        f = force(qs, v, t, us);
    }
};

/// The Hessian in z = (q, v, u) of aᵀ f(q, v, t, u) for a control force F (dim D, controls M).
template <class F>
Eigen::Matrix<double, 2 * F::dim + F::controls, 2 * F::dim + F::controls>
contracted_force_hessian(const F& f, const vec<F::dim>& q, const vec<F::dim>& v, double t,
                         const vec<F::controls>& u, const vec<F::dim>& a) {
    constexpr int N = force_in_z<F>::N;
    const force_in_z<F> z(f, q, v, t, u);
    typename force_in_z<F>::S psi = z.f(0) * a(0);
    for (int i = 1; i < F::dim; ++i)
        psi += z.f(i) * a(i);
    vec<N> g;
    Eigen::Matrix<double, N, N> h;
    ad::unpack(psi, g, h);
    return h;
}

/// The Hessian in z = (q, Λ) (d + m square) of ψ = −Λᵀ G(q) a + νᵀ g(q) for holonomic
/// constraints g (count m, G = ∂g/∂q): the constraint impulses' and the constraints' terms in the
/// Lagrangian of a constrained transcription, a the multipliers of the impulses' equations, ν of
/// g = 0. G(q) a is g's directional derivative along a (the dual part of `directional`).
template <class C>
Eigen::Matrix<double, C::dim + C::count, C::dim + C::count>
contracted_constraint_hessian(const C& c, const vec<C::dim>& q, const vec<C::count>& impulse,
                              const vec<C::dim>& a, const vec<C::count>& nu) {
    constexpr int D = C::dim, K = C::count, N = D + K;
    using S = ad::second_order<N>;
    using E = directional<S>;
    tvec<E, D> qe;
    for (int i = 0; i < D; ++i)
        qe(i) = E(ad::variable<N>(q(i), i), S(a(i)));
    const tvec<E, K> g = c(qe);
    S psi(0.0);
    for (int k = 0; k < K; ++k)
        psi += nu(k) * g(k).x - ad::variable<N>(impulse(k), D + k) * g(k).y;
    vec<N> grad;
    Eigen::Matrix<double, N, N> h;
    ad::unpack(psi, grad, h);
    return h;
}

} // namespace varsym::optimal
