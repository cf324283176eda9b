// varsym/optimal/dmoc_constraints.hpp: holonomic constraints g(q) = 0 in the DMOC transcription
// (dmoc.hpp), the discrete constrained Lagrange–d'Alembert equations of the constrained engine
// (schemes/constrained.hpp; Marsden & West 2001, §3.5; for optimal control Leyendecker,
// Ober-Blöbaum, Marsden & Ortiz 2010): the discrete action augmented by −Σ_g Λ_gᵀ g(Q_g) at every
// control value, so that
//   E_g − G(Q_g)ᵀ Λ_g = 0 (g = 0 … Ns),   g(Q_g) = 0 (0 < g < Ns; the ends are given on it).
// The impulse Λ_g at a node is the constrained engine's projection impulse μ of the step before
// plus its Λ_0 of the step after: the positions are the engine's, which the closure checks.
// Included by dmoc.hpp; each function does nothing without constraints (K = 0).
#pragma once

#include <cstdio>
#include <stdexcept>
#include <string>

namespace varsym::optimal {

/// Refuses boundary states off the constraints (|g(q)| or |G q̇| above 1e-10 relative to |G|
/// and the state's size) or at dependent constraints, and a free final state (not supported
/// with constraints).
template <lagrangian L, control_force F, class C>
void dmoc<L, F, C>::check_boundary_constraints() const {
    if constexpr (K > 0) {
        if (free_end_)
            throw std::invalid_argument("a free final state with holonomic constraints is not "
                                        "supported: fix the final state on the constraints");
        for (const bool start : {true, false}) {
            const vec<D> q = start ? p_.q_start : p_.q_end, v = start ? p_.v_start : p_.v_end;
            const char* which = start ? "start" : "end";
            vec<K> g;
            constraint_jacobian<D, K> jac;
            evaluate_constraint(c_, q, g, jac);
            check_independent<D, K>(jac, std::string("at the ") + which + " position");
            const double scale = jac.template lpNorm<Eigen::Infinity>(), tolerance = 1e-10;
            const double off = g.template lpNorm<Eigen::Infinity>(),
                         across = (jac * v).template lpNorm<Eigen::Infinity>();
            char buf[240];
            if (!(off <= tolerance * scale * std::max(1.0, q.template lpNorm<Eigen::Infinity>()))) {
                std::snprintf(buf, sizeof buf,
                              "the %s position violates the constraints (max |g(q)| = %.3g): "
                              "give a position on them",
                              which, off);
                throw std::invalid_argument(buf);
            }
            if (!(across <=
                  tolerance * scale * std::max(1.0, v.template lpNorm<Eigen::Infinity>()))) {
                std::snprintf(buf, sizeof buf,
                              "the %s velocity is not tangent to the constraints (max |G q'| = "
                              "%.3g): give a velocity along them",
                              which, across);
                throw std::invalid_argument(buf);
            }
        }
    }
}

template <lagrangian L, control_force F, class C>
void dmoc<L, F, C>::add_constraint_residual(cvector x, vector& e) const {
    if constexpr (K > 0) {
        vec<K> g;
        constraint_jacobian<D, K> jac;
        for (int n = 0; n < points_; ++n) {
            evaluate_constraint(c_, vec<D>(x.segment<D>(n * D)), g, jac);
            e.segment<D>(n * D) -= jac.transpose() * x.segment<K>(multiplier_index(n));
            if (n > 0 && n + 1 < points_) e.segment<K>(points_ * D + (n - 1) * K) = g;
        }
    }
}

/// The pattern (if `pattern`) or the values (appended to `values`): per control value n, the
/// rows of E_n against Q_n (−Σ_a Λ_a ∇²g_a) and Λ_n (−Gᵀ), and the rows of g(Q_n) against Q_n
/// (G) between the ends.
template <lagrangian L, control_force F, class C>
void dmoc<L, F, C>::add_constraint_jacobian(cvector x, sparsity* pattern,
                                            std::vector<double>* values) const {
    if constexpr (K > 0) {
        vec<K> g;
        constraint_jacobian<D, K> jac;
        mat<D> curvature;
        for (int n = 0; n < points_; ++n) {
            const bool inner = n > 0 && n + 1 < points_;
            if (values) {
                const vec<D> q = x.segment<D>(n * D);
                evaluate_constraint(c_, q, g, jac);
                constraint_curvature(c_, q, vec<K>(x.segment<K>(multiplier_index(n))), curvature);
            }
            for (int row = 0; row < D; ++row) {
                for (int col = 0; col < D; ++col)
                    pattern ? pattern->add(n * D + row, n * D + col)
                            : values->push_back(-curvature(row, col));
                for (int a = 0; a < K; ++a)
                    pattern ? pattern->add(n * D + row, multiplier_index(n) + a)
                            : values->push_back(-jac(a, row));
            }
            for (int a = 0; inner && a < K; ++a)
                for (int col = 0; col < D; ++col)
                    pattern ? pattern->add(points_ * D + (n - 1) * K + a, n * D + col)
                            : values->push_back(jac(a, col));
        }
    }
}

/// The lower triangle over (Q_n, Λ_n) of the Hessian of −λ_nᵀG(Q_n)ᵀΛ_n + ν_nᵀg(Q_n)
/// (third_order.hpp), ν_n the multipliers of g(Q_n) = 0 (none at the ends).
template <lagrangian L, control_force F, class C>
void dmoc<L, F, C>::add_constraint_hessian(cvector x, cvector lambda, sparsity* pattern,
                                           std::vector<double>* values) const {
    if constexpr (K > 0) {
        const auto index = [&](int n, int i) {
            return i < D ? n * D + i : multiplier_index(n) + i - D;
        };
        Eigen::Matrix<double, D + K, D + K> h;
        for (int n = 0; n < points_; ++n) {
            if (values) {
                const bool inner = n > 0 && n + 1 < points_;
                h = contracted_constraint_hessian(
                    c_, vec<D>(x.segment<D>(n * D)), vec<K>(x.segment<K>(multiplier_index(n))),
                    vec<D>(lambda.segment<D>(n * D)),
                    inner ? vec<K>(lambda.segment<K>(points_ * D + (n - 1) * K)) : vec<K>::Zero());
            }
            for (int row = 0; row < D + K; ++row)
                for (int col = 0; col <= std::min(row, D - 1); ++col) // Λ×Λ is zero
                    pattern ? pattern->add(index(n, row), index(n, col))
                            : values->push_back(h(row, col));
        }
    }
}

template <lagrangian L, control_force F, class C>
void dmoc<L, F, C>::tangent_node(const vec<D>& q, vec<D>& p, vec<D>& v, double t) const {
    if constexpr (K > 0) {
        vec<K> g;
        constraint_jacobian<D, K> jac;
        evaluate_constraint(c_, q, g, jac);
        p -= jac.transpose() * tangent_momentum(at(l_, t), q, p, jac, v);
    } else {
        (void)q, (void)p, (void)v, (void)t;
    }
}

} // namespace varsym::optimal
