// varsym/optimal/system.hpp: a mechanical system with control inputs whose sizes are known at run
// time only (a URDF robot, a typed Lagrangian, a C++ Lagrangian through automatic derivatives),
// as the one compiled DMOC transcription (varsym::optimal, optimize/transcription.hpp) takes it:
// the Lagrangian's first, second and contracted third derivatives, the input force f(q, q̇, t, u)
// with its Jacobians and contracted Hessian, and optional holonomic constraints. Eigen only.
// See docs/optimal_control.md.
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include <Eigen/Core>

#include "varsym/optimal/problem.hpp"
#include "varsym/optimal/third_order.hpp"
#include "varsym/systems/lagrangian.hpp"
#include "varsym/systems/lagrangian_time.hpp"

namespace varsym::optimal {

using matrix = Eigen::MatrixXd;

/// f(q, q̇, t, u) and its Jacobians in q, q̇ (d × d) and u (d × m).
struct input_terms {
    vector f;
    matrix fq, fv, fu;
};

/// A controlled mechanical system of run-time size: L(q, q̇, t) with d coordinates, a
/// generalized force of m inputs, and k holonomic constraints g(q) = 0 (k may be 0).
/// Implementations are immutable after construction; several threads call one at once only
/// where concurrent() says it may be (a typed Lagrangian's tape keeps scratch of its own).
class controlled_system {
  public:
    controlled_system() = default;
    controlled_system(const controlled_system&) = default;
    controlled_system& operator=(const controlled_system&) = default;
    controlled_system(controlled_system&&) = default;
    controlled_system& operator=(controlled_system&&) = default;
    virtual ~controlled_system() = default;

    [[nodiscard]] virtual int dimension() const = 0;                 ///< d
    [[nodiscard]] virtual int inputs() const = 0;                    ///< m
    [[nodiscard]] virtual int constraint_count() const { return 0; } ///< k
    /// Whether L depends on t explicitly (then a free final time is refused).
    [[nodiscard]] virtual bool time_dependent() const { return false; }
    /// Whether several threads may call this system at once (a URDF robot's: its workspaces are
    /// per thread): the transcription then evaluates its steps' derivatives on several threads.
    [[nodiscard]] virtual bool concurrent() const { return false; }
    /// Whether L is a multibody model (a URDF robot): optimal::solve then refines IPOPT's
    /// linear solves only where their residual asks for it (measured faster on robots only).
    [[nodiscard]] virtual bool multibody() const { return false; }

    /// L, ∂L/∂q and ∂L/∂q̇ at (q, q̇, t) into t.value, t.lq, t.lv (sized here).
    virtual void gradient(const vector& q, const vector& v, double t,
                          lagrangian_terms<dynamic>& out) const = 0;
    /// gradient() and the second derivatives lqq, lqv (∂²L/∂q_i∂q̇_j), lvv.
    virtual void derivatives(const vector& q, const vector& v, double t,
                             lagrangian_terms<dynamic>& out) const = 0;
    /// The Hessian in z = (q, q̇) (2d × 2d) of ψ = aᵀ ∂L/∂q + bᵀ ∂L/∂q̇: the directional
    /// derivative of ∇²L along w = (a, b). By default a central difference of derivatives()
    /// along w (step 6e-6 max(1, |z|)/|w|, relative error about 1e-10 on smooth L: an exact
    /// Hessian of the NLP's Lagrangian to that accuracy); systems built on a Lagrangian with
    /// exact third derivatives override it (lagrangian_part below: L's own, or nested AD).
    virtual void third(const vector& q, const vector& v, double t, const vector& a, const vector& b,
                       matrix& out) const {
        const int d = dimension();
        out.setZero(2 * d, 2 * d);
        const double size = std::max(a.lpNorm<Eigen::Infinity>(), b.lpNorm<Eigen::Infinity>());
        if (size == 0.0) return;
        const double scale =
            std::max({1.0, q.lpNorm<Eigen::Infinity>(), v.lpNorm<Eigen::Infinity>()});
        const double eps = 6e-6 * scale / size;
        thread_local lagrangian_terms<dynamic> lt; // no allocation once sized
        thread_local vector qs, vs;
        for (const double sign : {1.0, -1.0}) {
            qs = q + sign * eps * a;
            vs = v + sign * eps * b;
            derivatives(qs, vs, t, lt);
            const double c = sign / (2.0 * eps);
            out.topLeftCorner(d, d) += c * lt.lqq;
            out.topRightCorner(d, d) += c * lt.lqv;
            out.bottomLeftCorner(d, d) += c * lt.lqv.transpose();
            out.bottomRightCorner(d, d) += c * lt.lvv;
        }
    }
    /// Whether third() is exact (else a difference of exact second derivatives).
    [[nodiscard]] virtual bool exact_third() const { return false; }

    /// f(q, q̇, t, u) into out.f and, if `jacobians`, its Jacobians fq, fv, fu (sized here).
    virtual void force(const vector& q, const vector& v, double t, const vector& u,
                       input_terms& out, bool jacobians) const = 0;
    /// The Hessian in z = (q, q̇, u) ((2d + m) square) of aᵀ f(q, q̇, t, u); zero for a force
    /// linear in u with a constant input matrix (the default's contract: override otherwise).
    virtual void force_hessian(const vector& q, const vector& v, double t, const vector& u,
                               const vector& a, matrix& out) const {
        (void)q, (void)v, (void)t, (void)u, (void)a;
        const int n = 2 * dimension() + inputs();
        out.setZero(n, n);
    }
    /// B where f = f₀(q, q̇, t) + B u with B constant (d × m), for the sparsity of the optimal
    /// control problem: B's zeros are left out of the equations' Jacobian, and the force's
    /// Hessian has no (q, u), (q̇, u) or (u, u) entries. Null (the default): f may be any
    /// function of u, every entry of ∂f/∂u and of those Hessian blocks may be non-zero.
    [[nodiscard]] virtual const matrix* constant_input_matrix() const { return nullptr; }

    /// g(q) (k) and G = ∂g/∂q (k × d). Only called when constraint_count() > 0.
    virtual void constraint(const vector& q, vector& g, matrix& jac) const {
        (void)q, (void)g, (void)jac;
        throw std::logic_error("constraint(): the system has no constraints");
    }
    /// Σ_a λ_a ∇²g_a(q) (d × d).
    virtual void constraint_curvature(const vector& q, const vector& lambda, matrix& out) const {
        (void)q, (void)lambda, (void)out;
        throw std::logic_error("constraint_curvature(): the system has no constraints");
    }
    /// The Hessian in (q, Λ) ((d + k) square) of −Λᵀ G(q) a + νᵀ g(q).
    virtual void constraint_hessian(const vector& q, const vector& impulse, const vector& a,
                                    const vector& nu, matrix& out) const {
        (void)q, (void)impulse, (void)a, (void)nu, (void)out;
        throw std::logic_error("constraint_hessian(): the system has no constraints");
    }
    /// The momentum p at a node made tangent to the constraints (p − Gᵀμ with G q̇ = 0), and q̇.
    virtual void tangent(const vector& q, vector& p, vector& v, double t) const {
        (void)q, (void)p, (void)v, (void)t;
    }

    /// The closure check's nodes (q above p, 2d × (N + 1)) under the trajectory's controls from
    /// its start, where the system replays itself by another engine (system_of with
    /// constraints: the constrained engine for L and C). None (the default): the optimal
    /// library's general engine steps this system's own derivatives (replay(system, path),
    /// varsym/optimize/transcription.hpp).
    [[nodiscard]] virtual std::optional<matrix> own_replay(const trajectory& path) const {
        (void)path;
        return std::nullopt;
    }
};

/// L's derivatives at (q, q̇, t) by L's own means (by hand, or automatic at a fixed dimension)
/// into terms of run-time size: the first, and the second if `second`.
template <lagrangian L>
void lagrangian_terms_of(const L& l, const vector& q, const vector& v, double t,
                         lagrangian_terms<dynamic>& out, bool second) {
    constexpr int D = L::dim;
    if constexpr (D == dynamic) {
        if (second)
            evaluate(l, q, v, t, out);
        else
            evaluate_gradient(l, q, v, t, out);
    } else {
        lagrangian_terms<D> lt;
        if (second)
            evaluate(l, vec<D>(q), vec<D>(v), t, lt);
        else
            evaluate_gradient(l, vec<D>(q), vec<D>(v), t, lt);
        out.value = lt.value;
        out.lq = lt.lq;
        out.lv = lt.lv;
        if (!second) return;
        out.lqq = lt.lqq;
        out.lqv = lt.lqv;
        out.lvv = lt.lvv;
    }
}

/// A Lagrangian that gives its own exact contracted third derivatives (the Hessian in (q, q̇)
/// of aᵀ ∂L/∂q + bᵀ ∂L/∂q̇): l.third(q, v, t, a, b, out), or l.third(q, v, a, b, out) for one
/// that does not depend on t. The typed Lagrangian (symbolic code run forward along (a, b)), the
/// URDF robot (dual numbers through the recursive algorithms) and the arm (by hand) have them.
template <class L>
concept lagrangian_with_third = requires(const L& l, const vector& x, double t, matrix& out) {
    l.third(x, x, t, x, x, out);
}
|| requires(const L& l, const vector& x, matrix& out) {
    l.third(x, x, x, x, out);
};

/// A C++ Lagrangian of fixed dimension written for any scalar: its third derivatives by
/// nested forward-mode AD (third_order.hpp's contracted_third).
template <class L>
concept nested_ad = (L::dim != dynamic) &&
                    (
                        requires(const L& l, const tvec<third_scalar<L>, L::dim>& x) { l(x, x); } ||
                        requires(const L& l, const tvec<third_scalar<L>, L::dim>& x, double t) {
                            l(x, x, t);
                        });

/// What a controlled system built on a Lagrangian L (held by value) takes from L alone: its
/// dimension, its dependence on t, whether it is a multibody model, and its first and second
/// derivatives by L's own means (lagrangian_terms_of). input_system.hpp and system_of.hpp build
/// on it.
template <lagrangian L>
class lagrangian_part : public controlled_system {
  public:
    static constexpr int D = L::dim;

    explicit lagrangian_part(L l) : l_(std::move(l)) {}

    [[nodiscard]] const L& lagrangian() const { return l_; }
    [[nodiscard]] int dimension() const override {
        if constexpr (D == dynamic)
            return l_.dimension();
        else
            return D;
    }
    [[nodiscard]] bool multibody() const override {
        if constexpr (requires { L::multibody; })
            return L::multibody;
        else
            return false;
    }
    [[nodiscard]] bool time_dependent() const override {
        if constexpr (lagrangian_time_known<L>)
            return depends_on_time(l_);
        else
            return time_dependent_lagrangian<L>;
    }
    void gradient(const vector& q, const vector& v, double t,
                  lagrangian_terms<dynamic>& out) const override {
        lagrangian_terms_of(l_, q, v, t, out, false);
    }
    void derivatives(const vector& q, const vector& v, double t,
                     lagrangian_terms<dynamic>& out) const override {
        lagrangian_terms_of(l_, q, v, t, out, true);
    }
    /// L's own exact third derivatives where it has them (lagrangian_with_third), else nested
    /// AD for a C++ L of fixed dimension (nested_ad), else the difference of its exact second
    /// ones (controlled_system::third).
    void third(const vector& q, const vector& v, double t, const vector& a, const vector& b,
               matrix& out) const override {
        if constexpr (requires { l_.third(q, v, t, a, b, out); })
            l_.third(q, v, t, a, b, out);
        else if constexpr (requires { l_.third(q, v, a, b, out); })
            l_.third(q, v, a, b, out);
        else if constexpr (nested_ad<L>)
            out = contracted_third(l_, vec<D>(q), vec<D>(v), t, vec<D>(a), vec<D>(b));
        else
            controlled_system::third(q, v, t, a, b, out);
    }
    [[nodiscard]] bool exact_third() const override {
        return lagrangian_with_third<L> || nested_ad<L>;
    }

  protected:
    L l_; // NOLINT(misc-non-private-member-variables-in-classes): the systems' own L
};

/// f = B u with a constant input matrix B (d × m): joint torques, a push.
class input_matrix {
  public:
    explicit input_matrix(matrix b) : b_(std::move(b)) {
        if (b_.rows() < 1 || b_.cols() < 1 || !b_.allFinite())
            throw std::invalid_argument("the input matrix must be finite, d x m with m >= 1");
    }
    [[nodiscard]] const matrix& b() const { return b_; }
    void evaluate(const vector& u, input_terms& out, bool jacobians) const {
        out.f.noalias() = b_ * u;
        if (!jacobians) return;
        out.fq.setZero(b_.rows(), b_.rows());
        out.fv.setZero(b_.rows(), b_.rows());
        out.fu = b_;
    }

  private:
    matrix b_;
};

} // namespace varsym::optimal
