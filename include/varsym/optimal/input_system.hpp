// varsym/optimal/input_system.hpp: a Lagrangian L driven by inputs through a constant input
// matrix, with optional linear damping: f = B u − C q̇ (joint torques, a push, the inputs on named
// coordinates of a typed Lagrangian), as a controlled_system (system.hpp) for the one compiled
// transcription. L's first and second derivatives are its own (by hand, as a URDF robot's recursive
// ones and a typed Lagrangian's symbolic ones, or automatic for a C++ Lagrangian of fixed
// dimension, the ones its simulation already uses). The third derivatives the exact Hessian needs
// are exact too (lagrangian_part::third): the robot's dual numbers, the typed L's code run along
// a direction, nested AD for a C++ L of fixed dimension; only a C++ L of run-time dimension (the
// arm) takes a central difference of its exact second ones (controlled_system::third).
#pragma once

#include <memory>
#include <type_traits>
#include <utility>

#include "varsym/optimal/system.hpp"
#include "varsym/systems/constraints.hpp"
#include "varsym/systems/lagrangian.hpp"
#include "varsym/systems/lagrangian_time.hpp"

namespace varsym::optimal {

/// Holonomic constraints g(q) = 0 of run-time size with their derivatives by hand, as a typed
/// constraint has them: g, G = ∂g/∂q, Σ_a λ_a ∇²g_a (curvature) and its rate along a direction
/// (curvature_rate: g's third derivatives, for the exact Hessian).
template <class C>
concept constraint_of_run_time_size = constraint_with_derivatives<C> &&
                                      C::dim == dynamic&& C::count ==
                                      dynamic&& requires(const C& c, const vec<dynamic>& q,
                                                         mat<dynamic>& h) {
    c.curvature_rate(q, q, q, h);
};

template <lagrangian L, class C = unconstrained>
class input_system final : public lagrangian_part<L> {
  public:
    using lagrangian_part<L>::dimension;
    static constexpr bool constrained = !std::is_same_v<C, unconstrained>;
    static_assert(!constrained || constraint_of_run_time_size<C>,
                  "C: constraints of run-time size with their derivatives by hand");

    /// L, the input matrix B (d × m: column j is the generalized force of unit input j), the
    /// damping C (d × d, symmetric positive semi-definite [N m s/rad, N s/m]; empty: none) and
    /// the constraints, if any.
    input_system(L l, matrix b, matrix damping = {}, C constraints = {})
        : lagrangian_part<L>(std::move(l)), b_(std::move(b)), c_(std::move(damping)),
          g_(std::move(constraints)) {
        const int d = dimension();
        if (b_.b().rows() != d)
            throw std::invalid_argument("the input matrix has " + std::to_string(b_.b().rows()) +
                                        " rows; the system has " + std::to_string(d) +
                                        " coordinates");
        if (c_.size() != 0 && (c_.rows() != d || c_.cols() != d || !c_.allFinite()))
            throw std::invalid_argument("the damping matrix must be finite and d x d");
        if constexpr (constrained)
            if (g_.dimension() != d)
                throw std::invalid_argument("the constraints must be on the Lagrangian's " +
                                            std::to_string(d) + " coordinates");
    }

    [[nodiscard]] int inputs() const override { return static_cast<int>(b_.b().cols()); }
    /// Where L says so (L::concurrent: the URDF robot's per-thread workspaces) and there are no
    /// constraints (a typed constraint's tape keeps scratch of its own, and the declaration is
    /// the whole system's); B u − C q̇ is pure.
    [[nodiscard]] bool concurrent() const override {
        if constexpr (requires { L::concurrent; })
            return L::concurrent && !constrained;
        else
            return false;
    }
    [[nodiscard]] int constraint_count() const override {
        if constexpr (constrained)
            return g_.size();
        else
            return 0;
    }

    void force(const vector& q, const vector& v, double t, const vector& u, input_terms& out,
               bool jacobians) const override {
        (void)q, (void)t;
        b_.evaluate(u, out, jacobians);
        if (c_.size() == 0) return;
        out.f.noalias() -= c_ * v;
        if (jacobians) out.fv = -c_;
    }

    [[nodiscard]] const matrix* constant_input_matrix() const override { return &b_.b(); }

    void constraint(const vector& q, vector& g, matrix& jac) const override {
        if constexpr (constrained) {
            g = g_(q);
            g_.jacobian(q, jac);
        } else {
            controlled_system::constraint(q, g, jac);
        }
    }
    void constraint_curvature(const vector& q, const vector& lambda, matrix& out) const override {
        if constexpr (constrained)
            g_.curvature(q, lambda, out);
        else
            controlled_system::constraint_curvature(q, lambda, out);
    }
    /// The Hessian in (q, Λ) of −Λᵀ G(q) a + νᵀ g(q): in q, Σ_k ν_k ∇²g_k − Σ_k Λ_k (∇²g_k's
    /// rate along a); in (q, Λ_k), −∇²g_k a; none in Λ alone.
    void constraint_hessian(const vector& q, const vector& impulse, const vector& a,
                            const vector& nu, matrix& out) const override {
        if constexpr (constrained) {
            const int d = dimension(), k = g_.size();
            out.setZero(d + k, d + k);
            matrix h;
            g_.curvature(q, nu, h);
            out.topLeftCorner(d, d) = h;
            g_.curvature_rate(q, a, impulse, h);
            out.topLeftCorner(d, d) -= h;
            vector unit = vector::Zero(k);
            for (int j = 0; j < k; ++j) {
                unit.setZero();
                unit(j) = 1.0;
                g_.curvature(q, unit, h);
                out.block(0, d + j, d, 1) = -h * a;
                out.block(d + j, 0, 1, d) = out.block(0, d + j, d, 1).transpose();
            }
        } else {
            controlled_system::constraint_hessian(q, impulse, a, nu, out);
        }
    }
    void tangent(const vector& q, vector& p, vector& v, double t) const override {
        if constexpr (constrained) {
            matrix jac;
            g_.jacobian(q, jac);
            p -= jac.transpose() * tangent_momentum(at(this->l_, t), q, p, jac, v);
        } else {
            (void)q, (void)p, (void)v, (void)t;
        }
    }

  private:
    input_matrix b_;
    matrix c_;
    C g_;
};

} // namespace varsym::optimal
