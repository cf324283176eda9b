// varsym/optimal/system_of.hpp: a C++ Lagrangian L (compile-time dimension), a control force F
// and optional holonomic constraints C as a controlled_system (system.hpp) for the one compiled
// transcription (varsym/optimize/transcription.hpp): every derivative by forward-mode automatic
// differentiation (L's third ones contracted with a direction, third_order.hpp).
// varsym/optimize/transcribe.hpp's transcribe(l, force, problem) makes the transcription
// directly. See docs/optimal_control.md.
#pragma once

#include <memory>
#include <utility>

#include "varsym/optimal/control_force.hpp"
#include "varsym/optimal/replay.hpp"
#include "varsym/optimal/system.hpp"
#include "varsym/optimal/third_order.hpp"
#include "varsym/systems/constraints.hpp"

namespace varsym::optimal {

template <lagrangian L, control_force F, class C = unconstrained>
class system_of final : public lagrangian_part<L> {
  public:
    static constexpr int D = L::dim, M = F::controls, K = constraint_rows<C>;
    static_assert(F::dim == L::dim, "the control force must have the Lagrangian's dimension");
    static_assert(constraints_on<C, D>, "C: holonomic constraints on the Lagrangian's coordinates");
    static_assert(nested_ad<L>, "L: written for any scalar (its third derivatives by AD)");

    system_of(L l, F force, C constraints = {})
        : lagrangian_part<L>(std::move(l)), f_(std::move(force)), c_(std::move(constraints)) {}

    [[nodiscard]] int inputs() const override { return M; }
    [[nodiscard]] int constraint_count() const override { return K; }

    void force(const vector& q, const vector& v, double t, const vector& u, input_terms& out,
               bool jacobians) const override {
        if (!jacobians) {
            out.f = f_(vec<D>(q), vec<D>(v), t, vec<M>(u));
            return;
        }
        control_terms<F> ft;
        ft.evaluate(f_, vec<D>(q), vec<D>(v), t, vec<M>(u));
        out.f = ft.f;
        out.fq = ft.fq;
        out.fv = ft.fv;
        out.fu = ft.fu;
    }
    void force_hessian(const vector& q, const vector& v, double t, const vector& u, const vector& a,
                       matrix& out) const override {
        out = contracted_force_hessian(f_, vec<D>(q), vec<D>(v), t, vec<M>(u), vec<D>(a));
    }

    void constraint(const vector& q, vector& g, matrix& jac) const override {
        if constexpr (K > 0) {
            vec<K> gk;
            constraint_jacobian<D, K> jk;
            evaluate_constraint(c_, vec<D>(q), gk, jk);
            g = gk;
            jac = jk;
        } else {
            controlled_system::constraint(q, g, jac);
        }
    }
    void constraint_curvature(const vector& q, const vector& lambda, matrix& out) const override {
        if constexpr (K > 0) {
            mat<D> c;
            varsym::constraint_curvature(c_, vec<D>(q), vec<K>(lambda), c);
            out = c;
        } else {
            controlled_system::constraint_curvature(q, lambda, out);
        }
    }
    void constraint_hessian(const vector& q, const vector& impulse, const vector& a,
                            const vector& nu, matrix& out) const override {
        if constexpr (K > 0)
            out = contracted_constraint_hessian(c_, vec<D>(q), vec<K>(impulse), vec<D>(a),
                                                vec<K>(nu));
        else
            controlled_system::constraint_hessian(q, impulse, a, nu, out);
    }
    void tangent(const vector& q, vector& p, vector& v, double t) const override {
        if constexpr (K > 0) {
            vec<K> g;
            constraint_jacobian<D, K> jac;
            const vec<D> qd = q;
            evaluate_constraint(c_, qd, g, jac);
            vec<D> pd = p, vd = v;
            pd -= jac.transpose() * tangent_momentum(at(l_, t), qd, pd, jac, vd);
            p = pd;
            v = vd;
        } else {
            (void)q, (void)p, (void)v, (void)t;
        }
    }
    /// With constraints the constrained engine for L and C; without, none of its own (the
    /// optimal library's engine over this system, compiled once).
    [[nodiscard]] std::optional<matrix> own_replay(const trajectory& path) const override {
        if constexpr (K > 0)
            return optimal::replay(l_, c_, f_, path);
        else
            return controlled_system::own_replay(path);
    }

  private:
    using lagrangian_part<L>::l_;
    F f_;
    C c_;
};

} // namespace varsym::optimal
