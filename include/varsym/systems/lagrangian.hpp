// varsym/systems/lagrangian.hpp: general Lagrangians L(q, q̇) on R^D, written once as a function
// templated on the scalar type; first and second derivatives come from forward-mode automatic
// differentiation (autodiff/second_order.hpp), or from the user's own derivatives(q, v, terms).
#pragma once

#include <cmath>
#include <concepts>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <utility>

#include <Eigen/Eigenvalues>

#include "varsym/autodiff/second_order.hpp"
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

/// What a Lagrangian must provide: `static constexpr int dim` (D ≥ 1) and
/// `template <class T> T operator()(const tvec<T, D>& q, const tvec<T, D>& v) const`,
/// callable with T = double and T = ad::second_order<2D> (so: `using std::sin;` before calling
/// sin, and double literals, 2.0 not 2, in arithmetic with T).
template <class L>
concept lagrangian = requires {
    L::dim;
}
&&(L::dim >= 1) && requires(const L& l, const tvec<double, L::dim>& q) {
    { l(q, q) } -> std::convertible_to<double>;
};

/// A Lagrangian that also supplies its derivatives by hand (used instead of differentiation).
template <class L>
concept lagrangian_with_derivatives = lagrangian<L> &&
    requires(const L& l, const vec<L::dim>& q, lagrangian_terms<L::dim>& t) {
    l.derivatives(q, q, t);
};

/// Fills `t` with L(q, v) and its derivatives: by hand when L provides them, else with one
/// pass of L over automatic-differentiation scalars seeded with the 2D variables (q, v).
template <lagrangian L>
void evaluate(const L& l, const vec<L::dim>& q, const vec<L::dim>& v, lagrangian_terms<L::dim>& t) {
    constexpr int D = L::dim;
    if constexpr (lagrangian_with_derivatives<L>) {
        l.derivatives(q, v, t);
    } else {
        constexpr int N = 2 * D;
        using J = ad::second_order<N>;
        tvec<J, D> qj, vj;
        for (int i = 0; i < D; ++i) {
            qj(i) = ad::variable<N>(q(i), i);
            vj(i) = ad::variable<N>(v(i), D + i);
        }
        const J r = l(qj, vj);
        Eigen::Matrix<double, N, 1> g;
        Eigen::Matrix<double, N, N> h;
        t.value = ad::unpack<N>(r, g, h);
        t.lq = g.template head<D>();
        t.lv = g.template tail<D>();
        t.lqq = h.template topLeftCorner<D, D>();
        t.lqv = h.template topRightCorner<D, D>();
        t.lvv = h.template bottomRightCorner<D, D>();
    }
}

/// A mechanical system given by its Lagrangian: momenta p = ∂L/∂q̇, velocities from momenta,
/// and the energy E = q̇ᵀp − L (the Hamiltonian), which a time-independent L conserves.
template <lagrangian L>
class lagrangian_system {
  public:
    static constexpr int dim = L::dim;
    using lagrangian_type = L;

    explicit lagrangian_system(L l) : l_(std::move(l)) {}

    [[nodiscard]] int dimension() const { return dim; }
    [[nodiscard]] const L& lagrangian() const { return l_; }

    [[nodiscard]] vec<dim> momentum(const vec<dim>& q, const vec<dim>& v) const {
        lagrangian_terms<dim> t;
        evaluate(l_, q, v, t);
        return t.lv;
    }

    /// Solves ∂L/∂q̇(q, v) = p for v by Newton (one iteration when L is quadratic in q̇).
    /// Throws std::domain_error if ∂²L/∂q̇² is not positive definite there or Newton fails.
    [[nodiscard]] vec<dim> velocity(const vec<dim>& q, const vec<dim>& p) const {
        vec<dim> v = vec<dim>::Zero();
        lagrangian_terms<dim> t;
        for (int it = 0; it < 50; ++it) {
            evaluate(l_, q, v, t);
            const Eigen::LLT<mat<dim>> llt(t.lvv);
            if (llt.info() != Eigen::Success || !t.lvv.allFinite())
                throw std::domain_error("the mass matrix d2L/dqdot2 is singular or not positive "
                                        "definite at this state");
            const vec<dim> dv = llt.solve(p - t.lv);
            v += dv;
            if (!v.allFinite()) break;
            // Quadratic Lagrangians are done after one iteration; the next confirms it.
            if (it > 0 && dv.template lpNorm<Eigen::Infinity>() <=
                              1e-13 * v.template lpNorm<Eigen::Infinity>())
                return v;
            if (dv.isZero(0.0)) return v;
        }
        throw std::domain_error("could not solve dL/dqdot = p for the velocity");
    }

    /// E(q, p) = q̇ᵀ p − L(q, q̇) with q̇ from velocity(q, p).
    [[nodiscard]] double energy(const phase_state<dim>& x) const {
        const vec<dim> v = velocity(x.q, x.p);
        return v.dot(x.p) - l_(x.q, v);
    }

    /// Refuses a state where ∂²L/∂q̇² is singular, indefinite or not finite, naming the cause.
    void check_regular(const vec<dim>& q, const vec<dim>& v) const {
        lagrangian_terms<dim> t;
        evaluate(l_, q, v, t);
        if (!t.lvv.allFinite() || !t.lv.allFinite() || !t.lq.allFinite() || !std::isfinite(t.value))
            throw std::invalid_argument(
                "the Lagrangian or its derivatives are NaN or infinite at the "
                "initial state");
        // Eigenvalues, not a Cholesky attempt: round-off can let a singular matrix pass LLᵀ.
        const Eigen::SelfAdjointEigenSolver<mat<dim>> eig(t.lvv, Eigen::EigenvaluesOnly);
        const double lo = eig.eigenvalues().minCoeff(), hi = eig.eigenvalues().maxCoeff();
        if (!(lo > 1e-12 * hi)) {
            char range[80];
            std::snprintf(range, sizeof range, " (eigenvalues from %.3g to %.3g)", lo, hi);
            throw std::invalid_argument("the mass matrix d2L/dqdot2 is singular or not positive "
                                        "definite at the initial state" +
                                        std::string(range));
        }
    }

  private:
    L l_;
};

/// A separable system L = ½ q̇ᵀMq̇ − V(q) seen as a general Lagrangian, with its derivatives by
/// hand: lets the general engine run any separable_system (and tests compare the two paths).
template <class Separable>
struct separable_lagrangian {
    static constexpr int dim = Separable::dim;
    static_assert(dim >= 1, "separable_lagrangian needs a compile-time dimension");
    Separable sys;

    double operator()(const vec<dim>& q, const vec<dim>& v) const {
        return 0.5 * v.dot(sys.mass() * v) - sys.potential().value(q);
    }
    void derivatives(const vec<dim>& q, const vec<dim>& v, lagrangian_terms<dim>& t) const {
        t.value = (*this)(q, v);
        t.lq = -sys.potential().gradient(q);
        t.lv = sys.mass() * v;
        t.lqq = -sys.potential().hessian(q);
        t.lqv.setZero();
        t.lvv = sys.mass();
    }
};

} // namespace varsym
