// varsym/problems/chain.hpp: a chain of n coupled nonlinear oscillators (Fermi–Pasta–Ulam–
// Tsingou β model) with fixed ends, whose Hessian is tridiagonal: Newton's linear solve is O(n).
//
// Units and conventions: q_i is the displacement of mass i (i = 1 … n) from equilibrium, all
// masses m, unit linear springs, q_0 = q_{n+1} = 0 (fixed ends):
//   L = ½ m Σ q̇_i² − Σ_{i=0}^{n} (½ r_i² + ¼ β r_i⁴),   r_i = q_{i+1} − q_i
// p_i = m q̇_i; the energy is conserved (the fixed ends break translation invariance).
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "varsym/solvers/newton.hpp"
#include "varsym/solvers/tridiagonal.hpp"
#include "varsym/types.hpp"

namespace varsym::chain {

/// V(q) = Σ_{i=0}^{n} (½ r_i² + ¼ β r_i⁴): value, gradient, and the Hessian either dense (small
/// n, tests) or as its two diagonals.
struct potential {
    double beta = 1.0;

    /// r_i = q_{i+1} − q_i with the fixed ends q_0 = q_{n+1} = 0, for i = 0 … n.
    static double stretch(const vec<dynamic>& q, Eigen::Index i) {
        const Eigen::Index n = q.size();
        const double right = i < n ? q(i) : 0.0; // q_{i+1} is q(i) in 0-based storage
        const double left = i > 0 ? q(i - 1) : 0.0;
        return right - left;
    }
    [[nodiscard]] double value(const vec<dynamic>& q) const {
        double v = 0.0;
        for (Eigen::Index i = 0; i <= q.size(); ++i) {
            const double r2 = stretch(q, i) * stretch(q, i);
            v += 0.5 * r2 + 0.25 * beta * r2 * r2;
        }
        return v;
    }
    /// ∂V/∂q_i = V'(r_{i−1}) − V'(r_i), V'(r) = r + β r³.
    [[nodiscard]] vec<dynamic> gradient(const vec<dynamic>& q) const {
        vec<dynamic> g(q.size());
        gradient(q, g);
        return g;
    }
    /// The same into g (sized here; no allocation once it has the size): the steppers' path.
    void gradient(const vec<dynamic>& q, vec<dynamic>& g) const {
        const Eigen::Index n = q.size();
        g.resize(n);
        double left = force(stretch(q, 0));
        for (Eigen::Index i = 0; i < n; ++i) {
            const double right = force(stretch(q, i + 1));
            g(i) = left - right;
            left = right;
        }
    }
    /// ∂²V/∂q_i² = V''(r_{i−1}) + V''(r_i), ∂²V/∂q_i∂q_{i+1} = −V''(r_i), V''(r) = 1 + 3βr².
    void hessian_diagonals(const vec<dynamic>& q, Eigen::Ref<Eigen::VectorXd> diag,
                           Eigen::Ref<Eigen::VectorXd> off) const {
        const Eigen::Index n = q.size();
        double left = stiffness(stretch(q, 0));
        for (Eigen::Index i = 0; i < n; ++i) {
            const double right = stiffness(stretch(q, i + 1));
            diag(i) = left + right;
            if (i + 1 < n) off(i) = -right;
            left = right;
        }
    }
    /// The stage equation m δ + c ∇V(q + δ) = r of the Simpson and Newmark steps at δ, in one
    /// pass over the stretches (each r_i's V' and V'' once, at x = q + δ): its residual
    /// m δ + c ∇V(x) − r into res and its Jacobian m I + c ∇²V(x) as diagonal and off-diagonal,
    /// each entry by the same operations as gradient() and hessian_diagonals() followed by
    /// those sums (the steps are the same bit for bit as by the separate passes).
    void stage_terms(double m, double c, const vec<dynamic>& q, const vec<dynamic>& delta,
                     const vec<dynamic>& r, Eigen::VectorXd& res, Eigen::VectorXd& diag,
                     Eigen::VectorXd& off) const {
        const Eigen::Index n = q.size();
        res.resize(n);
        diag.resize(n);
        off.resize(std::max<Eigen::Index>(n - 1, 0));
        double x = q(0) + delta(0);
        const double first = x - 0.0; // r_0 = x_1 − x_0, x_0 = 0 the fixed end
        double force_left = force(first), stiffness_left = stiffness(first);
        for (Eigen::Index i = 0; i < n; ++i) {
            const double next = i + 1 < n ? q(i + 1) + delta(i + 1) : 0.0; // x_{n+1} = 0
            const double stretch_right = next - x;
            const double force_right = force(stretch_right);
            const double stiffness_right = stiffness(stretch_right);
            res(i) = m * delta(i) + c * (force_left - force_right) - r(i);
            diag(i) = m + c * (stiffness_left + stiffness_right);
            if (i + 1 < n) off(i) = -stiffness_right * c;
            x = next;
            force_left = force_right;
            stiffness_left = stiffness_right;
        }
    }
    [[nodiscard]] mat<dynamic> hessian(const vec<dynamic>& q) const {
        const Eigen::Index n = q.size();
        Eigen::VectorXd d(n), o(std::max<Eigen::Index>(n - 1, 0));
        hessian_diagonals(q, d, o);
        mat<dynamic> h = d.asDiagonal();
        for (Eigen::Index i = 0; i + 1 < n; ++i)
            h(i, i + 1) = h(i + 1, i) = o(i);
        return h;
    }

  private:
    [[nodiscard]] double force(double r) const { return r + beta * r * r * r; }
    [[nodiscard]] double stiffness(double r) const { return 1.0 + 3.0 * beta * r * r; }
};

/// The chain as a system for the Simpson and Newmark steppers: scalar mass m, so M⁻¹ is a number
/// and every step is O(n) (its solve_stage member replaces the dense Newton).
class system {
  public:
    static constexpr int dim = dynamic;

    system(int n, double beta, double m = 1.0) : n_(n), m_(m), minv_(1.0 / m), v_{beta} {
        if (n < 1)
            throw std::invalid_argument("chain length n must be >= 1, got " + std::to_string(n));
        if (!(std::isfinite(m) && m > 0.0))
            throw std::invalid_argument("mass must be a finite positive number, got " +
                                        std::to_string(m));
        if (!(std::isfinite(beta) && beta >= 0.0))
            throw std::invalid_argument("beta must be finite and >= 0, got " +
                                        std::to_string(beta));
    }
    [[nodiscard]] int dimension() const { return n_; }
    [[nodiscard]] const double& mass() const { return m_; }
    [[nodiscard]] const double& inverse_mass() const { return minv_; }
    [[nodiscard]] const chain::potential& potential() const { return v_; }
    [[nodiscard]] double energy(const phase_state<dynamic>& x) const {
        return 0.5 * minv_ * x.p.squaredNorm() + v_.value(x.q);
    }
    /// The lowest linear mode with amplitude a: q_i = a sin(π i/(n+1)), p = 0.
    [[nodiscard]] phase_state<dynamic> lowest_mode(double a) const {
        phase_state<dynamic> x{vec<dynamic>(n_), vec<dynamic>::Zero(n_)};
        for (int i = 0; i < n_; ++i)
            x.q(i) = a * std::sin(std::numbers::pi * (i + 1) / (n_ + 1));
        return x;
    }

    /// An upper bound of the highest frequency at x: √(max Gershgorin row bound of ∇²V(q)) / √m.
    /// The Hessian is tridiagonal, so the bound costs O(n) where an eigensolver would cost O(n³).
    /// Used by varsym::highest_frequency (diagnostics/stability.hpp) in place of an eigensolver.
    [[nodiscard]] double highest_frequency(const phase_state<dynamic>& x) const {
        const Eigen::Index n = x.q.size();
        Eigen::VectorXd diag(n), off(std::max<Eigen::Index>(n - 1, 0));
        v_.hessian_diagonals(x.q, diag, off);
        double bound = 0.0;
        for (Eigen::Index i = 0; i < n; ++i) {
            double row = diag(i);
            if (i > 0) row += std::abs(off(i - 1));
            if (i + 1 < n) row += std::abs(off(i));
            bound = std::max(bound, row);
        }
        return std::sqrt(bound * minv_);
    }

    /// The scratch of solve_stage, kept by the stepper across steps (stage_equation.hpp).
    struct stage_workspace {
        Eigen::VectorXd res, diag, off;
    };

    /// Newton on m δ + c ∇V(q + δ) = r (the stage equation of stage_equation.hpp) with the
    /// tridiagonal Jacobian m I + c ∇²V solved in O(n): the Simpson and Newmark steppers call it
    /// through varsym::solve_stage_increment in place of the dense Newton. Three passes over the
    /// chain an iteration (the equation's terms, the two sweeps of the solve); allocates nothing
    /// once `ws` has the size.
    [[nodiscard]] newton_report solve_stage(double c, const vec<dynamic>& q, const vec<dynamic>& r,
                                            vec<dynamic>& delta, const newton_options& opt,
                                            stage_workspace& ws) const {
        newton_options local = opt;
        local.typical = delta.lpNorm<Eigen::Infinity>();
        local.reference = q.lpNorm<Eigen::Infinity>();
        newton_monitor monitor(local);
        newton_report rep;
        while (!monitor.exhausted()) {
            v_.stage_terms(m_, c, q, delta, r, ws.res, ws.diag, ws.off);
            rep.residual = ws.res.lpNorm<Eigen::Infinity>();
            rep.iterations = monitor.iterations() + 1;
            if (!solve_symmetric_tridiagonal(ws.diag, ws.off, ws.res)) return rep;
            const double step = ws.res.lpNorm<Eigen::Infinity>();
            if (!std::isfinite(step) || !std::isfinite(rep.residual)) return rep;
            delta -= ws.res;
            if (monitor.converged(step, delta.lpNorm<Eigen::Infinity>())) {
                rep.converged = true;
                return rep;
            }
        }
        return rep;
    }

  private:
    int n_;
    double m_, minv_;
    chain::potential v_;
};

} // namespace varsym::chain
