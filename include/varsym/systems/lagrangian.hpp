// varsym/systems/lagrangian.hpp: general Lagrangians L(q, q̇) on R^D, written once as a function
// templated on the scalar type; first and second derivatives come from forward-mode automatic
// differentiation (autodiff/second_order.hpp), or from the user's own derivatives(q, v, terms).
#pragma once

#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include <Eigen/Eigenvalues>

#include "varsym/autodiff/reverse.hpp"
#include "varsym/autodiff/second_order.hpp"
#include "varsym/solvers/eigenvalues.hpp"
#include "varsym/systems/lagrangian_concepts.hpp"
#include "varsym/systems/separable.hpp"
#include "varsym/types.hpp"

namespace varsym {

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
/// Empty if ∂²L/∂q̇² is positive definite (its smallest eigenvalue above 1e-12 of the largest),
/// else what it is: singular or not positive definite (the smallest eigenvalue ≤ 0), or
/// ill-conditioned (all positive, but the condition number hi/lo above 1e12, where Newton's
/// solves keep fewer than four of a double's 16 digits). `where` (" at the initial state")
/// follows the verdict.
template <int D>
std::string mass_matrix_problem(const mat<D>& m, const char* where = "") {
    const Eigen::VectorXd lambda = symmetric_eigenvalues<D>(m);
    const double lo = lambda.minCoeff(), hi = lambda.maxCoeff();
    if (lo > 1e-12 * std::abs(hi)) return {};
    char buf[240];
    if (lo > 0.0)
        std::snprintf(buf, sizeof buf,
                      "the mass matrix d2L/dqdot2 is ill-conditioned%s: condition number %.3g "
                      "(eigenvalues from %.3g to %.3g)",
                      where, hi / lo, lo, hi);
    else
        std::snprintf(buf, sizeof buf,
                      "the mass matrix d2L/dqdot2 is singular or not positive definite%s "
                      "(eigenvalues from %.3g to %.3g)",
                      where, lo, hi);
    return buf;
}

} // namespace detail

/// Fills `t` with L(q, v) and its derivatives: by hand when L provides them, else by
/// forward-mode automatic differentiation in the 2D variables (q, v): one pass for small D,
/// a few passes of a few Hessian columns each for large D (ad::hessian_columns_per_pass).
template <lagrangian L>
void evaluate(const L& l, const vec<L::dim>& q, const vec<L::dim>& v, lagrangian_terms<L::dim>& t) {
    constexpr int D = L::dim;
    static_assert(!time_dependent_lagrangian<L>,
                  "this Lagrangian depends on time: evaluate(l, q, v, time, terms)");
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
    static_assert(!time_dependent_lagrangian<L>,
                  "this Lagrangian depends on time: evaluate_gradient(l, q, v, time, terms)");
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

/// evaluate and evaluate_gradient at time `time` (ignored by a time-independent L).
template <lagrangian L>
void evaluate(const L& l, const vec<L::dim>& q, const vec<L::dim>& v, double time,
              lagrangian_terms<L::dim>& t) {
    evaluate(at(l, time), q, v, t);
}
template <lagrangian L>
void evaluate_gradient(const L& l, const vec<L::dim>& q, const vec<L::dim>& v, double time,
                       lagrangian_terms<L::dim>& t) {
    evaluate_gradient(at(l, time), q, v, t);
}

/// A mechanical system given by its Lagrangian: momenta p = ∂L/∂q̇, velocities from momenta,
/// and the energy E = q̇ᵀp − L (the Hamiltonian), which a time-independent L conserves.
template <lagrangian L>
class lagrangian_system {
  public:
    static constexpr int dim = L::dim;
    static constexpr bool time_dependent = time_dependent_lagrangian<L>;
    using lagrangian_type = L;

    explicit lagrangian_system(L l) : l_(std::move(l)) {}

    [[nodiscard]] int dimension() const {
        if constexpr (dim == dynamic)
            return l_.dimension();
        else
            return dim;
    }
    [[nodiscard]] const L& lagrangian() const { return l_; }

    /// p = ∂L/∂q̇(q, v) (at time t, for a time-dependent L: every member below takes a
    /// trailing time argument, which only a time-independent L may leave out).
    [[nodiscard]] vec<dim> momentum(const vec<dim>& q, const vec<dim>& v, double t) const {
        lagrangian_terms<dim> terms;
        evaluate(l_, q, v, t, terms);
        return terms.lv;
    }
    [[nodiscard]] vec<dim> momentum(const vec<dim>& q, const vec<dim>& v) const
        requires(!time_dependent) {
        return momentum(q, v, 0.0);
    }

    /// Solves ∂L/∂q̇(q, v) = p for v by Newton from v = 0 (one iteration when L is quadratic
    /// in q̇). Where ∂²L/∂q̇² is singular on the way but not at the solution (L = q̇⁴/4 at
    /// q̇ = 0), Newton starts again from v = p. Converged when a correction is below 1e-13 |v|,
    /// or below the round-off floor of the solve, 100 ε κ |v| with κ the condition number's
    /// estimate (LLT's rcond): an ill-conditioned mass matrix (a 40-link chain: κ ~ 1e7) leaves
    /// corrections of ε κ |v| that no iteration removes. A floor above 1e-4 (κ > 4.5e9) is not
    /// accepted. Throws std::domain_error if ∂²L/∂q̇² is not positive definite from both
    /// starts, or Newton fails.
    /// With lagrangian_with_mass_matrix: q̇ = M(q)⁻¹p by one Cholesky factorisation, refined
    /// (p − M q̇ solved again) to the same floor.
    [[nodiscard]] vec<dim> velocity(const vec<dim>& q, const vec<dim>& p, double time) const {
        if constexpr (lagrangian_with_mass_matrix<L>) return quadratic_velocity(q, p);
        lagrangian_terms<dim> t;
        for (const bool from_p : {false, true}) {
            vec<dim> v = from_p ? vec<dim>(p) : vec<dim>(vec<dim>::Zero(q.size()));
            for (int it = 0; it < 50; ++it) {
                evaluate(l_, q, v, time, t);
                const Eigen::LLT<mat<dim>> llt(t.lvv);
                if (llt.info() != Eigen::Success || !t.lvv.allFinite()) {
                    if (!from_p) break; // the second start
                    throw std::domain_error("the mass matrix d2L/dqdot2 is singular or not "
                                            "positive definite at this state");
                }
                const vec<dim> dv = llt.solve(p - t.lv);
                v += dv;
                if (!v.allFinite()) break;
                // Quadratic Lagrangians are done after one iteration; the next confirms it.
                const double rcond = llt.rcond();
                const double floor =
                    rcond > 0.0 ? std::clamp(100.0 * std::numeric_limits<double>::epsilon() / rcond,
                                             1e-13, 1e-4)
                                : 1e-13;
                if (it > 0 && dv.template lpNorm<Eigen::Infinity>() <=
                                  floor * v.template lpNorm<Eigen::Infinity>())
                    return v;
                if (dv.isZero(0.0)) return v;
            }
        }
        throw std::domain_error("could not solve dL/dqdot = p for the velocity (the mass matrix "
                                "d2L/dqdot2 may be too ill-conditioned)");
    }
    [[nodiscard]] vec<dim> velocity(const vec<dim>& q, const vec<dim>& p) const
        requires(!time_dependent) {
        return velocity(q, p, 0.0);
    }

    /// E(q, p) = q̇ᵀ p − L(q, q̇) with q̇ from velocity(q, p).
    [[nodiscard]] double energy(const phase_state<dim>& x, double t) const {
        const vec<dim> v = velocity(x.q, x.p, t);
        return v.dot(x.p) - at(l_, t)(x.q, v);
    }
    [[nodiscard]] double energy(const phase_state<dim>& x) const requires(!time_dependent) {
        return energy(x, 0.0);
    }

    /// Refuses a state where ∂²L/∂q̇² is singular, indefinite, ill-conditioned (condition number
    /// above 1e12) or not finite, naming the cause.
    void check_regular(const vec<dim>& q, const vec<dim>& v, double time) const {
        lagrangian_terms<dim> t;
        evaluate(l_, q, v, time, t);
        if (!t.lvv.allFinite() || !t.lv.allFinite() || !t.lq.allFinite() || !std::isfinite(t.value))
            throw std::invalid_argument(
                "the Lagrangian or its derivatives are NaN or infinite at the "
                "initial state");
        // Eigenvalues, not a Cholesky attempt: round-off can let a singular matrix pass LLᵀ.
        if (std::string m = detail::mass_matrix_problem<dim>(t.lvv, " at the initial state");
            !m.empty())
            throw std::invalid_argument(m);
    }
    void check_regular(const vec<dim>& q, const vec<dim>& v) const requires(!time_dependent) {
        check_regular(q, v, 0.0);
    }

  private:
    L l_;

    [[nodiscard]] vec<dim> quadratic_velocity(const vec<dim>& q, const vec<dim>& p) const {
        mat<dim> m(q.size(), q.size());
        l_.mass_matrix(q, m);
        const Eigen::LLT<mat<dim>> llt(m);
        if (llt.info() != Eigen::Success || !m.allFinite())
            throw std::domain_error("the mass matrix d2L/dqdot2 is singular or not positive "
                                    "definite at this state");
        // Iterative refinement to velocity()'s floor: one correction, which confirms the solve,
        // unless M is ill-conditioned.
        const double rcond = llt.rcond();
        const double floor =
            rcond > 0.0
                ? std::clamp(100.0 * std::numeric_limits<double>::epsilon() / rcond, 1e-13, 1e-4)
                : 1e-13;
        vec<dim> v = llt.solve(p);
        for (int it = 0; it < 50 && v.allFinite(); ++it) {
            const vec<dim> dv = llt.solve(p - m * v);
            v += dv;
            if (dv.template lpNorm<Eigen::Infinity>() <=
                floor * v.template lpNorm<Eigen::Infinity>())
                return v;
        }
        throw std::domain_error("could not solve dL/dqdot = p for the velocity (the mass matrix "
                                "d2L/dqdot2 may be too ill-conditioned)");
    }
};

} // namespace varsym

#include "varsym/systems/separable_lagrangian.hpp"
