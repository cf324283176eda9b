// varsym/optimal/third_order.hpp: the Hessians an optimal control transcription needs for the
// exact Hessian of its Lagrangian: of ψ_L = aᵀ ∂L/∂q + bᵀ ∂L/∂q̇ in (q, q̇) (L's third derivatives
// contracted with the multipliers' direction (a, b)), and of ψ_f = aᵀ f(q, q̇, t, u) in
// (q, q̇, u). Forward-mode automatic differentiation: second_order scalars, with one directional
// derivative more on top for L (Eigen's AutoDiffScalar nested three deep).
#pragma once

#include <type_traits>

#include "varsym/autodiff/second_order.hpp"
#include "varsym/systems/lagrangian.hpp"

namespace varsym::optimal::detail {

/// An AutoDiffScalar over second-order scalars (three levels): Eigen gives it arithmetic with its
/// own kind only, since a double reaches it through two conversions. The operators below take
/// the double literals of a Lagrangian (0.5 * v * v) by converting them once, exactly.
template <class T>
struct is_autodiff : std::false_type {};
template <class D>
struct is_autodiff<Eigen::AutoDiffScalar<D>> : std::true_type {};
template <class T>
struct is_second_order : std::false_type {};
template <class D>
struct is_second_order<Eigen::AutoDiffScalar<D>>
    : is_autodiff<typename Eigen::internal::remove_all<D>::type::Scalar> {};

/// An AutoDiffScalar (or one of its expressions) whose derivatives are second-order scalars S
/// (S = AutoDiffScalar<Matrix<F, N, 1>>, F an AutoDiffScalar); `plain` is its value type.
template <class T>
struct is_third_order : std::false_type {};
template <class D>
struct is_third_order<Eigen::AutoDiffScalar<D>> {
    using derivatives = typename Eigen::internal::remove_all<D>::type::PlainObject;
    using S = typename derivatives::Scalar;
    static constexpr bool value = is_second_order<S>::value;
    using plain = Eigen::AutoDiffScalar<derivatives>;
};

template <class T>
concept third_order = is_third_order<T>::value;

template <third_order T>
typename is_third_order<T>::plain lift(double x) {
    using P = typename is_third_order<T>::plain;
    using S = typename P::Scalar; // second order
    using F = typename S::Scalar; // first order
    return P(S(F(x)));
}

} // namespace varsym::optimal::detail

namespace Eigen {

#define VARSYM_THIRD_ORDER_OP(op)                                                                  \
    template <class T, std::enable_if_t<varsym::optimal::detail::third_order<T>, int> = 0>         \
    typename varsym::optimal::detail::is_third_order<T>::plain operator op(double a, const T& b) { \
        return typename varsym::optimal::detail::is_third_order<T>::plain(                         \
            varsym::optimal::detail::lift<T>(a) op b);                                             \
    }                                                                                              \
    template <class T, std::enable_if_t<varsym::optimal::detail::third_order<T>, int> = 0>         \
    typename varsym::optimal::detail::is_third_order<T>::plain operator op(const T& a, double b) { \
        return typename varsym::optimal::detail::is_third_order<T>::plain(                         \
            a op varsym::optimal::detail::lift<T>(b));                                             \
    }
VARSYM_THIRD_ORDER_OP(+)
VARSYM_THIRD_ORDER_OP(-)
VARSYM_THIRD_ORDER_OP(*)
VARSYM_THIRD_ORDER_OP(/)
#undef VARSYM_THIRD_ORDER_OP

} // namespace Eigen

namespace varsym::optimal {

/// The Hessian in z = (q, v) (2D × 2D) of aᵀ ∂L/∂q(q, v, t) + bᵀ ∂L/∂v(q, v, t).
template <lagrangian L>
mat<2 * L::dim> contracted_third(const L& l, const vec<L::dim>& q, const vec<L::dim>& v, double t,
                                 const vec<L::dim>& a, const vec<L::dim>& b) {
    constexpr int D = L::dim, N = 2 * D;
    using S = ad::second_order<N>;
    using E = Eigen::AutoDiffScalar<Eigen::Matrix<S, 1, 1>>; // d/dε along (a, b)
    tvec<E, D> qe, ve;
    for (int i = 0; i < D; ++i) {
        qe(i) = E(ad::variable<N>(q(i), i), Eigen::Matrix<S, 1, 1>::Constant(S(a(i))));
        ve(i) = E(ad::variable<N>(v(i), D + i), Eigen::Matrix<S, 1, 1>::Constant(S(b(i))));
    }
    const E out = at(l, t)(qe, ve);
    vec<N> g;
    mat<N> h;
    ad::unpack(out.derivatives()(0), g, h);
    return h;
}

/// The Hessian in z = (q, v, u) of aᵀ f(q, v, t, u) for a control force F (dim D, controls M).
template <class F>
Eigen::Matrix<double, 2 * F::dim + F::controls, 2 * F::dim + F::controls>
contracted_force_hessian(const F& f, const vec<F::dim>& q, const vec<F::dim>& v, double t,
                         const vec<F::controls>& u, const vec<F::dim>& a) {
    constexpr int D = F::dim, M = F::controls, N = 2 * D + M;
    using S = ad::second_order<N>;
    tvec<S, D> qs, vs;
    tvec<S, M> us;
    for (int i = 0; i < D; ++i) {
        qs(i) = ad::variable<N>(q(i), i);
        vs(i) = ad::variable<N>(v(i), D + i);
    }
    for (int i = 0; i < M; ++i)
        us(i) = ad::variable<N>(u(i), 2 * D + i);
    const tvec<S, D> out = f(qs, vs, t, us);
    S psi = out(0) * a(0);
    for (int i = 1; i < D; ++i)
        psi += out(i) * a(i);
    vec<N> g;
    Eigen::Matrix<double, N, N> h;
    ad::unpack(psi, g, h);
    return h;
}

} // namespace varsym::optimal
