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

#include "varsym/autodiff/reverse.hpp"
#include "varsym/autodiff/second_order.hpp"
#include "varsym/systems/separable.hpp"
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
template <class L>
concept lagrangian = requires {
    L::dim;
}
&&(L::dim >= 1 || L::dim == dynamic) && requires(const L& l, const tvec<double, L::dim>& q) {
    { l(q, q) } -> std::convertible_to<double>;
}
&&(L::dim != dynamic || requires(const L& l) {
    { l.dimension() } -> std::convertible_to<int>;
});

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

namespace detail {
/// L's first derivatives in one pass of ad::first_order<2D>: 2D + 1 numbers per operation.
template <class L>
void differentiate_first(const L& l, const vec<L::dim>& q, const vec<L::dim>& v,
                         lagrangian_terms<L::dim>& t) {
    constexpr int D = L::dim, N = 2 * D;
    using J = ad::first_order<N>;
    tvec<J, D> qj, vj;
    for (int i = 0; i < D; ++i) {
        qj(i) = J(q(i), N, i);
        vj(i) = J(v(i), N, D + i);
    }
    const J r = l(qj, vj);
    t.value = r.value();
    t.lq = r.derivatives().template head<D>();
    t.lv = r.derivatives().template tail<D>();
}

/// L's first derivatives by reverse mode: one recording of L on the thread's tape and one sweep
/// back, at a cost that does not grow with D.
template <class L>
void differentiate_reverse(const L& l, const vec<L::dim>& q, const vec<L::dim>& v,
                           lagrangian_terms<L::dim>& t) {
    constexpr int D = L::dim;
    ad::tape& tape = ad::tape::local();
    tape.clear();
    tvec<ad::reverse, D> qj, vj;
    for (int i = 0; i < D; ++i)
        qj(i) = ad::reverse::variable(q(i));
    for (int i = 0; i < D; ++i)
        vj(i) = ad::reverse::variable(v(i));
    const ad::reverse r = l(qj, vj);
    t.value = r.value();
    tape.sweep(r.index());
    for (int i = 0; i < D; ++i) {
        t.lq(i) = tape.adjoint(qj(i).index());
        t.lv(i) = tape.adjoint(vj(i).index());
    }
}

/// All of L's second derivatives in one pass of ad::second_order<2D>.
template <class L>
void differentiate_at_once(const L& l, const vec<L::dim>& q, const vec<L::dim>& v,
                           lagrangian_terms<L::dim>& t) {
    constexpr int D = L::dim, N = 2 * D;
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

/// The same, B Hessian columns per pass of ad::directional<2D, B> (large D).
template <int B, class L>
void differentiate_in_blocks(const L& l, const vec<L::dim>& q, const vec<L::dim>& v,
                             lagrangian_terms<L::dim>& t) {
    constexpr int D = L::dim, N = 2 * D;
    using J = ad::directional<N, B>;
    tvec<J, D> qj, vj;
    for (int first = 0; first < N; first += B) {
        for (int i = 0; i < D; ++i) {
            qj(i) = ad::seeded_variable<N, B>(q(i), i, first);
            vj(i) = ad::seeded_variable<N, B>(v(i), D + i, first);
        }
        const J r = l(qj, vj);
        if (first == 0) {
            t.value = r.value().value();
            t.lq = r.value().derivatives().template head<D>();
            t.lv = r.value().derivatives().template tail<D>();
        }
        for (int j = 0; j < B && first + j < N; ++j) {
            // Column c of the Hessian in (q, v): ∂/∂x of ∂L/∂x_c.
            const int c = first + j;
            const auto& col = r.derivatives()(j).derivatives();
            if (c < D) {
                t.lqq.col(c) = col.template head<D>();
                t.lqv.row(c) = col.template tail<D>().transpose(); // ∂²L/∂q_c∂v
            } else {
                t.lvv.col(c - D) = col.template tail<D>();
            }
        }
    }
}
} // namespace detail

/// Fills `t` with L(q, v) and its derivatives: by hand when L provides them, else by
/// forward-mode automatic differentiation in the 2D variables (q, v): one pass for small D,
/// a few passes of a few Hessian columns each for large D (ad::hessian_columns_per_pass).
template <lagrangian L>
void evaluate(const L& l, const vec<L::dim>& q, const vec<L::dim>& v, lagrangian_terms<L::dim>& t) {
    constexpr int D = L::dim;
    if constexpr (lagrangian_with_derivatives<L>) {
        l.derivatives(q, v, t);
    } else {
        static_assert(D != dynamic,
                      "automatic derivatives need a compile-time dimension: give a Lagrangian of "
                      "run-time dimension its derivatives by hand (a member "
                      "derivatives(q, v, lagrangian_terms&))");
        constexpr int B = ad::hessian_columns_per_pass<D>();
        static_assert(B > 0, "dimension too large for automatic derivatives (at most 60): give "
                             "the Lagrangian its derivatives by hand");
        if constexpr (B == 2 * D)
            detail::differentiate_at_once(l, q, v, t);
        else
            detail::differentiate_in_blocks<B>(l, q, v, t);
    }
}

/// evaluate_gradient differentiates L of dimension D by forward mode up to this D, by reverse
/// mode above it.
inline constexpr int reverse_mode_above = 8;

/// Fills lq and lv of `t` (and value with automatic derivatives; the other members are left as
/// they are, or filled too when L gives only derivatives()): by hand, or by first-order
/// automatic differentiation in the 2D variables (forward or reverse mode).
template <lagrangian L>
void evaluate_gradient(const L& l, const vec<L::dim>& q, const vec<L::dim>& v,
                       lagrangian_terms<L::dim>& t) {
    if constexpr (lagrangian_with_gradient<L>) {
        l.gradient(q, v, t);
    } else if constexpr (lagrangian_with_derivatives<L>) {
        l.derivatives(q, v, t);
    } else {
        static_assert(L::dim != dynamic, "automatic derivatives need a compile-time dimension");
        // Forward mode costs 2D + 1 numbers per operation, reverse mode a constant but larger
        // one (a tape entry and a sweep back): measured, forward wins up to D = 8
        // (docs/autodiff.md).
        if constexpr (L::dim <= reverse_mode_above)
            detail::differentiate_first(l, q, v, t);
        else
            detail::differentiate_reverse(l, q, v, t);
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

    [[nodiscard]] int dimension() const {
        if constexpr (dim == dynamic)
            return l_.dimension();
        else
            return dim;
    }
    [[nodiscard]] const L& lagrangian() const { return l_; }

    [[nodiscard]] vec<dim> momentum(const vec<dim>& q, const vec<dim>& v) const {
        lagrangian_terms<dim> t;
        evaluate(l_, q, v, t);
        return t.lv;
    }

    /// Solves ∂L/∂q̇(q, v) = p for v by Newton (one iteration when L is quadratic in q̇).
    /// Throws std::domain_error if ∂²L/∂q̇² is not positive definite there or Newton fails.
    [[nodiscard]] vec<dim> velocity(const vec<dim>& q, const vec<dim>& p) const {
        vec<dim> v = vec<dim>::Zero(q.size());
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
/// hand: lets the general engine run any separable system (and tests compare the two paths).
template <separable Separable>
struct separable_lagrangian {
    static constexpr int dim = Separable::dim;
    Separable sys;
    bool diagonal = is_diagonal(sys); ///< the mass matrix is (then M q̇ is a product of vectors)

    static bool is_diagonal(const Separable& s) {
        if constexpr (scalar_mass<Separable>)
            return true;
        else
            return s.mass().isDiagonal(0.0);
    }

    [[nodiscard]] int dimension() const { return sys.dimension(); }
    double operator()(const vec<dim>& q, const vec<dim>& v) const {
        if constexpr (scalar_mass<Separable>)
            return 0.5 * sys.mass() * v.squaredNorm() - sys.potential().value(q);
        else
            return 0.5 * v.dot(sys.mass() * v) - sys.potential().value(q);
    }
    void gradient(const vec<dim>& q, const vec<dim>& v, lagrangian_terms<dim>& t) const {
        t.lq = -sys.potential().gradient(q);
        if constexpr (scalar_mass<Separable>)
            t.lv = sys.mass() * v;
        else if (diagonal)
            t.lv = sys.mass().diagonal().cwiseProduct(v);
        else
            t.lv.noalias() = sys.mass() * v;
    }
    void derivatives(const vec<dim>& q, const vec<dim>& v, lagrangian_terms<dim>& t) const {
        t.value = (*this)(q, v);
        t.lq = -sys.potential().gradient(q);
        t.lqq = -sys.potential().hessian(q);
        t.lqv.setZero(q.size(), q.size());
        if constexpr (scalar_mass<Separable>) {
            t.lv = sys.mass() * v;
            t.lvv.setZero(q.size(), q.size());
            t.lvv.diagonal().setConstant(sys.mass());
        } else {
            t.lv.noalias() = sys.mass() * v;
            t.lvv = sys.mass();
        }
    }
};

} // namespace varsym
