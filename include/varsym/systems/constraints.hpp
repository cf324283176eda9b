// varsym/systems/constraints.hpp: holonomic constraints g(q) = 0 (m equations on the
// configuration), written once, templated on the scalar type like a Lagrangian, with their
// Jacobian G = ∂g/∂q and the curvature term Σ_a λ_a ∇²g_a by automatic differentiation or by
// hand; checks of independence (rank of G) and of initial data, and the projections that put
// (q, p) on the constraint manifold and its hidden (velocity) constraint G(q) q̇ = 0.
// The constrained stepper is schemes/constrained.hpp; docs/mechanisms.md.
#pragma once

#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>

#include <Eigen/Dense>

#include "varsym/autodiff/second_order.hpp"
#include "varsym/solvers/small_ldlt.hpp"
#include "varsym/systems/lagrangian.hpp"
#include "varsym/types.hpp"

namespace varsym {

/// What a set of holonomic constraints must provide: `static constexpr int dim` (the
/// Lagrangian's), `static constexpr int count` (m ≥ 1, or `dynamic` with a member
/// `int size() const` giving m) and
/// `template <class T> tvec<T, count> operator()(const tvec<T, dim>& q) const`, the residuals
/// g(q) (zero on the manifold), callable with double and the automatic-differentiation scalars.
/// A constraint may give its derivatives by hand instead: jacobian(q, G) (G: m × dim) and
/// curvature(q, λ, H) (H = Σ_a λ_a ∇²g_a, dim × dim); with dim or count `dynamic` it must.
template <class C>
concept holonomic_constraint = requires {
    C::dim;
    C::count;
}
&&(C::count >= 1 || (C::count == dynamic &&
                     requires(const C& c) {
                         { c.size() } -> std::convertible_to<int>;
                     })) &&
    requires(const C& c, const vec<C::dim>& q) {
    { c(q) } -> std::convertible_to<vec<C::count>>;
};

/// m, the number of constraint equations.
template <holonomic_constraint C>
int constraint_count(const C& c) {
    if constexpr (C::count == dynamic)
        return c.size();
    else
        return C::count;
}

template <class C>
concept constraint_with_derivatives = holonomic_constraint<C> &&
    requires(const C& c, const vec<C::dim>& q, const vec<C::count>& l,
             Eigen::Matrix<double, C::count, C::dim>& g, mat<C::dim>& h) {
    c.jacobian(q, g);
    c.curvature(q, l, h);
};

/// G = ∂g/∂q (m × d), the rows of the constraint forces Gᵀλ.
template <int D, int M>
using constraint_jacobian = Eigen::Matrix<double, M, D>;

/// g(q) and G(q): by hand, or by forward-mode automatic differentiation in the d coordinates.
template <holonomic_constraint C>
void evaluate_constraint(const C& c, const vec<C::dim>& q, vec<C::count>& g,
                         constraint_jacobian<C::dim, C::count>& jac) {
    constexpr int D = C::dim, M = C::count;
    if constexpr (constraint_with_derivatives<C>) {
        g = c(q);
        c.jacobian(q, jac);
    } else {
        static_assert(D != dynamic && M != dynamic,
                      "automatic derivatives need compile-time sizes: give the constraint "
                      "jacobian() and curvature() by hand");
        using J = ad::first_order<D>;
        tvec<J, D> qj;
        for (int i = 0; i < D; ++i)
            qj(i) = J(q(i), D, i);
        const tvec<J, M> out = c(qj);
        for (int a = 0; a < M; ++a) {
            g(a) = out(a).value();
            jac.row(a) = out(a).derivatives().transpose();
        }
    }
}

/// H = Σ_a λ_a ∇²g_a(q) = ∂(Gᵀλ)/∂q: the constraint forces' part of the step's Jacobian.
template <holonomic_constraint C>
void constraint_curvature(const C& c, const vec<C::dim>& q, const vec<C::count>& lambda,
                          mat<C::dim>& h) {
    constexpr int D = C::dim, M = C::count;
    if constexpr (constraint_with_derivatives<C>) {
        c.curvature(q, lambda, h);
    } else {
        static_assert(D != dynamic && M != dynamic,
                      "automatic derivatives need compile-time sizes: give the constraint "
                      "jacobian() and curvature() by hand");
        using J = ad::second_order<D>;
        tvec<J, D> qj;
        for (int i = 0; i < D; ++i)
            qj(i) = ad::variable<D>(q(i), i);
        const tvec<J, M> out = c(qj);
        J sum = lambda(0) * out(0);
        for (int a = 1; a < M; ++a)
            sum += lambda(a) * out(a);
        vec<D> grad;
        ad::unpack<D>(sum, grad, h);
    }
}

/// The singular values of a constraint Jacobian, largest first: Householder QR of J (or Jᵀ, the
/// taller of the two), then two-sided Jacobi on the square R. What Eigen::JacobiSVD does with its
/// default preconditioner, without instantiating two column-pivoting QRs in every translation
/// unit (about 3 s of compile time each).
inline Eigen::VectorXd singular_values(const Eigen::MatrixXd& jac) {
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(
        jac.rows() >= jac.cols() ? jac : Eigen::MatrixXd(jac.transpose()));
    const Eigen::Index k = std::min(jac.rows(), jac.cols());
    const Eigen::MatrixXd r = qr.matrixQR().topLeftCorner(k, k).triangularView<Eigen::Upper>();
    return Eigen::JacobiSVD<Eigen::MatrixXd, Eigen::NoQRPreconditioner>(r).singularValues();
}

/// Refuses a constraint Jacobian whose rows are dependent (redundant constraints), naming each
/// row that is a combination of the rows before it (numbered from 1), at relative tolerance
/// 1e-10 of the largest singular value.
template <int D, int M>
void check_independent(const constraint_jacobian<D, M>& jac, const std::string& where) {
    const double top = singular_values(jac)(0);
    std::string dependent;
    for (int rows = 1; rows <= jac.rows(); ++rows) {
        const Eigen::MatrixXd part = jac.topRows(rows);
        const Eigen::VectorXd sv = singular_values(part);
        if (!(sv(rows - 1) > 1e-10 * top)) {
            dependent += (dependent.empty() ? "" : ", ") + std::to_string(rows);
            if (rows == 1) break; // a zero first row: everything after is measured against it
        }
    }
    if (dependent == "1")
        throw std::invalid_argument("the constraint Jacobian is singular " + where +
                                    ": its row 1 is zero; start away from a singular "
                                    "configuration, or remove the constraint");
    if (!dependent.empty())
        throw std::invalid_argument("the constraints are dependent " + where + ": row(s) " +
                                    dependent +
                                    " of the constraint Jacobian are combinations of the rows "
                                    "before them; remove the redundant constraints, or start "
                                    "away from a singular configuration");
}

namespace detail {

/// The saddle-point system [[M, Gᵀ], [G, 0]] (v, μ) = (a, b) for M positive definite, by M's
/// factors (small_ldlt at a run-time size, else Cholesky) and the Schur complement
/// S = G M⁻¹ Gᵀ (m × m, positive definite where G has independent rows):
/// μ = S⁻¹(G M⁻¹a − b), v = M⁻¹(a − Gᵀμ). For a 19-coordinate floating robot with its
/// quaternion's constraint, the projection takes 0.4 times the time of a full-pivoting LU of the
/// (d + m)² matrix (docs/performance.md, "The step's linear algebra").
template <int D, int M>
struct saddle_point {
    std::conditional_t<D == dynamic, small_ldlt, Eigen::LLT<mat<D>>> mass;
    Eigen::Matrix<double, D, M> y; // M⁻¹Gᵀ
    // S at run-time size (GCC 12 warns falsely on a pivoting LU of a fixed 1 × 1 matrix).
    Eigen::MatrixXd s;
    Eigen::FullPivLU<Eigen::MatrixXd> schur;
    Eigen::VectorXd r;
    vec<D> column, x;

    /// False where M is not positive definite, or S is singular to (d + m) ε of its largest
    /// pivot (dependent rows of G: the full matrix's LU's threshold, relative to S).
    bool compute(const mat<D>& m, const constraint_jacobian<D, M>& g) {
        if constexpr (D == dynamic) {
            if (!mass.compute(m)) return false;
        } else {
            mass.compute(m);
            if (mass.info() != Eigen::Success) return false;
        }
        y.resize(m.rows(), g.rows());
        for (Eigen::Index j = 0; j < g.rows(); ++j) {
            column = g.row(j).transpose();
            solve_mass(column, x);
            y.col(j) = x;
        }
        s.noalias() = g * y;
        schur.setThreshold(static_cast<double>(m.rows() + g.rows()) *
                           std::numeric_limits<double>::epsilon());
        schur.compute(s);
        return schur.isInvertible();
    }
    /// v and μ from a and b (v must not be a).
    void solve(const vec<D>& a, const vec<M>& b, const constraint_jacobian<D, M>& g, vec<D>& v,
               vec<M>& mu) {
        solve_mass(a, v);
        r.noalias() = g * v;
        r -= b;
        mu = schur.solve(r);
        v.noalias() -= y * mu;
    }
    void solve_mass(const vec<D>& a, vec<D>& out) const {
        if constexpr (D == dynamic)
            mass.solve(a, out);
        else
            out = mass.solve(a);
    }
};

} // namespace detail

/// The hidden constraint's projection: the momentum p − Gᵀμ nearest p (in the metric of the
/// mass matrix) whose velocity is tangent to the manifold, G(q) q̇ = 0, with q̇ from
/// ∂L/∂q̇(q, q̇) = p − Gᵀμ. Newton on (q̇, μ) with the saddle-point matrix [[L_vv, Gᵀ], [G, 0]]:
/// one iteration when L is quadratic in q̇ (a second confirms it). With M(q) by hand
/// (lagrangian_with_mass_matrix) the system is linear, M q̇ + Gᵀμ = p, G q̇ = 0: one solve by
/// M's factors and the Schur complement (detail::saddle_point), and one refinement with
/// the same factors; by a full-pivoting LU of the saddle-point matrix where M is not positive
/// definite or not finite, or S is singular. Returns μ; v holds q̇ on entry (a start) and on
/// return. Throws std::domain_error if the saddle-point matrix is singular (its LU's rank).
template <lagrangian L, int M>
vec<M> tangent_momentum(const L& l, const vec<L::dim>& q, const vec<L::dim>& p,
                        const constraint_jacobian<L::dim, M>& jac, vec<L::dim>& v) {
    const int d = static_cast<int>(q.size()), m = static_cast<int>(jac.rows());
    lagrangian_terms<L::dim> t;
    vec<M> mu = vec<M>::Zero(m);
    if constexpr (lagrangian_with_mass_matrix<L>) {
        // M, its factors and the vectors kept per thread; v is written only on success.
        thread_local mat<L::dim> mass;
        thread_local detail::saddle_point<L::dim, M> f;
        thread_local vec<L::dim> w, dw, res;
        thread_local vec<M> b, dmu;
        l.mass_matrix(q, mass);
        if (mass.allFinite() && f.compute(mass, jac)) {
            b.setZero(m);
            f.solve(p, b, jac, w, mu);
            res = p; // one step of iterative refinement: the residual, solved with the factors
            res.noalias() -= mass * w;
            res.noalias() -= jac.transpose() * mu;
            b.noalias() = jac * w;
            b = -b;
            f.solve(res, b, jac, dw, dmu);
            w += dw;
            mu += dmu;
            if (!w.allFinite() || !mu.allFinite())
                throw std::domain_error("could not make the momentum tangent to the constraints");
            v = w;
            return mu;
        }
    }
    Eigen::MatrixXd k = Eigen::MatrixXd::Zero(d + m, d + m);
    Eigen::VectorXd r(d + m);
    if constexpr (lagrangian_with_mass_matrix<L>) {
        mat<L::dim> mass;
        l.mass_matrix(q, mass);
        k.topLeftCorner(d, d) = mass;
        k.topRightCorner(d, m) = jac.transpose();
        k.bottomLeftCorner(m, d) = jac;
        const Eigen::FullPivLU<Eigen::MatrixXd> lu(k);
        if (!lu.isInvertible() || !mass.allFinite())
            throw std::domain_error("the mass matrix is singular on the constraint manifold, or "
                                    "the constraint Jacobian has dependent rows");
        r.head(d) = p;
        r.tail(m).setZero();
        Eigen::VectorXd x = lu.solve(r);
        x += lu.solve(Eigen::VectorXd(r - k * x)); // one step of iterative refinement
        if (!x.allFinite())
            throw std::domain_error("could not make the momentum tangent to the constraints");
        v = x.head(d);
        mu = x.tail(m);
        return mu;
    }
    double previous = std::numeric_limits<double>::infinity();
    for (int it = 0; it < 20; ++it) {
        evaluate(l, q, v, t);
        k.topLeftCorner(d, d) = t.lvv;
        k.topRightCorner(d, m) = jac.transpose();
        k.bottomLeftCorner(m, d) = jac;
        r.head(d) = t.lv + jac.transpose() * mu - p;
        r.tail(m) = jac * v;
        const Eigen::FullPivLU<Eigen::MatrixXd> lu(k);
        if (!lu.isInvertible())
            throw std::domain_error("the mass matrix is singular on the constraint manifold, or "
                                    "the constraint Jacobian has dependent rows");
        const Eigen::VectorXd delta = lu.solve(r);
        v -= delta.head(d);
        mu -= delta.tail(m);
        if (!v.allFinite()) break;
        // Done at 1e-14 relative, or at the round-off floor (updates that stop shrinking: near
        // rest q̇ is tiny and its updates are round-off of p, not of q̇).
        const double step = delta.head(d).template lpNorm<Eigen::Infinity>();
        if (it > 0 &&
            (step <= 1e-14 * v.template lpNorm<Eigen::Infinity>() || step >= 0.5 * previous))
            return mu;
        previous = step;
    }
    throw std::domain_error("could not make the momentum tangent to the constraints");
}

/// Moves q onto g(q) = 0 along the rows of G (Gauss–Newton, q ← q − Gᵀ(GGᵀ)⁻¹g); throws
/// std::domain_error if it does not converge to round-off.
template <holonomic_constraint C>
void project_position(const C& c, vec<C::dim>& q) {
    vec<C::count> g;
    constraint_jacobian<C::dim, C::count> jac(constraint_count(c), q.size());
    for (int it = 0; it < 50; ++it) {
        evaluate_constraint(c, q, g, jac);
        const mat<C::count> ggt = jac * jac.transpose();
        vec<C::count> y;
        if constexpr (C::count == 1) // one constraint: a division (GCC 12 sees a false
            y(0) = g(0) / ggt(0, 0); // -Warray-bounds in the 1×1 LDLᵀ's pivoting)
        else
            y = ggt.ldlt().solve(g);
        const vec<C::dim> dq = jac.transpose() * y;
        q -= dq;
        if (!q.allFinite()) break;
        if (dq.template lpNorm<Eigen::Infinity>() <=
            4e-16 * std::max(1.0, q.template lpNorm<Eigen::Infinity>()))
            return;
    }
    throw std::domain_error("could not project the initial position onto the constraints");
}

} // namespace varsym
