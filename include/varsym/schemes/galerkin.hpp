// varsym/schemes/galerkin.hpp: the variational family beyond the paper. q(t) on a step is a
// polynomial of degree s through control values Q_0 = q_j, Q_1 … Q_{s−1}, Q_s = q_{j+1} at the
// Gauss–Lobatto nodes d_0 = 0 < … < d_s = 1, and the action is integrated by
//   lobatto: the (s+1)-point Gauss–Lobatto rule (s = 1 trapezoidal/Störmer–Verlet, s = 2 the
//            paper's Simpson scheme), or
//   gauss:   the s-point Gauss–Legendre rule (s = 1 the midpoint rule: the paper's Newmark).
// Both have order 2s. For L = ½ q̇ᵀ M q̇ − V(q), with ℓ_i the Lagrange basis on the d_i,
//   L_d = (1/(2h)) Σ_{i,l} A_il Q_iᵀ M Q_l − h Σ_k w_k V(Σ_i ℓ_i(c_k) Q_i),
//   A_il = Σ_k w_k ℓ_i'(c_k) ℓ_l'(c_k)
// (the paper's eq. LLhh is the case lobatto, s = 2).
#pragma once

#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include "varsym/quadrature/rules.hpp"
#include "varsym/solvers/compensated.hpp"
#include "varsym/solvers/newton.hpp"
#include "varsym/systems/separable.hpp"

namespace varsym::galerkin {

enum class rule_kind { lobatto, gauss };

/// Largest degree offered: beyond it the basis on equispaced-in-cosine nodes is still well
/// conditioned, but double precision stops the measurement of orders well before (order 24).
inline constexpr int max_degree = 12;

/// The tables of one member: control nodes d_i, quadrature (c_k, w_k), ℓ_i(c_k), ℓ_i'(c_k), A.
struct tableau {
    int degree = 0;
    rule_kind kind = rule_kind::lobatto;
    std::vector<double> control;   ///< d_0 … d_s (Gauss–Lobatto nodes on [0, 1])
    quadrature::rule quad;         ///< c_k, w_k
    Eigen::MatrixXd phi;           ///< (s+1) × r: ℓ_i(c_k)
    Eigen::MatrixXd dphi;          ///< (s+1) × r: ℓ_i'(c_k)
    Eigen::MatrixXd stiffness;     ///< (s+1) × (s+1): A_il

    /// Builds the tables in long double (64-bit mantissa) and rounds each entry once to double,
    /// so that their errors stay at half an ulp: the scheme's period is then right to ~1 ulp.
    static tableau make(rule_kind kind, int s) {
        using LD = long double;
        if (s < 1 || s > max_degree)
            throw std::invalid_argument("degree must be between 1 and " + std::to_string(max_degree) +
                                        ", got " + std::to_string(s));
        const auto control = quadrature::gauss_lobatto<LD>(s + 1).nodes;
        const auto quad = kind == rule_kind::lobatto ? quadrature::gauss_lobatto<LD>(s + 1)
                                                     : quadrature::gauss_legendre<LD>(s);
        const auto r = static_cast<Eigen::Index>(quad.size());
        using matrix_ld = Eigen::Matrix<LD, Eigen::Dynamic, Eigen::Dynamic>;
        matrix_ld phi(s + 1, r), dphi(s + 1, r);
        for (int i = 0; i <= s; ++i)
            for (Eigen::Index k = 0; k < r; ++k) {
                const LD x = quad.nodes[k];
                LD value = 1, slope = 0;
                for (int m = 0; m <= s; ++m) {
                    if (m == i) continue;
                    const LD inv = 1 / (control[i] - control[m]);
                    slope = slope * (x - control[m]) * inv + value * inv; // product rule
                    value *= (x - control[m]) * inv;
                }
                phi(i, k) = value;
                dphi(i, k) = slope;
            }
        if (kind == rule_kind::lobatto) phi.setIdentity(); // c_k = d_k: ℓ_i(c_k) = δ_ik exactly
        matrix_ld weights = matrix_ld::Zero(r, r);
        for (Eigen::Index k = 0; k < r; ++k) weights(k, k) = quad.weights[k];
        const matrix_ld stiffness = dphi * weights * dphi.transpose();

        tableau t;
        t.degree = s;
        t.kind = kind;
        t.control.assign(control.begin(), control.end());
        t.quad.nodes.assign(quad.nodes.begin(), quad.nodes.end());
        t.quad.weights.assign(quad.weights.begin(), quad.weights.end());
        t.phi = phi.cast<double>();
        t.dphi = dphi.cast<double>();
        t.stiffness = stiffness.cast<double>();
        return t;
    }
    [[nodiscard]] int order() const { return 2 * degree; }
};

/// One step solves, for the increments X_l = Q_l − q_j (l = 1 … s; X_0 = 0), the s·D equations
///   h p_j + Σ_l A_0l M X_l − h² Σ_k w_k ℓ_0(c_k) ∇V(q_k) = 0     (p_j = −∂L_d/∂Q_0)
///           Σ_l A_il M X_l − h² Σ_k w_k ℓ_i(c_k) ∇V(q_k) = 0     (∂L_d/∂Q_i = 0, 0 < i < s)
/// with q_k = q_j + Σ_l ℓ_l(c_k) X_l, by Newton with the exact Jacobian
///   A_il M − h² Σ_k w_k ℓ_i(c_k) ℓ_l(c_k) ∇²V(q_k).
/// Then q_{j+1} = q_j + X_s and p_{j+1} = ∂L_d/∂Q_s, which (the equations summed over i, with
/// Σ_i A_il = 0 and Σ_i ℓ_i = 1) is p_j − h Σ_k w_k ∇V(q_k).
template <class System>
class stepper {
public:
    static constexpr int dim = System::dim;
    using system_type = System;

    stepper(System sys, double h, std::shared_ptr<const tableau> tab, const newton_options& opt = {})
        : sys_(std::move(sys)), h_(h), opt_(opt), tab_(std::move(tab)) {
        const int s = tab_->degree;
        const int d = sys_.dimension();
        const auto n = static_cast<Eigen::Index>(s) * d;
        x_.resize(n);
        r_.resize(n);
        delta_.resize(n);
        jac_.resize(n, n);
        lu_ = Eigen::PartialPivLU<Eigen::MatrixXd>(n);
        grad_.assign(tab_->quad.size(), vec<dim>::Zero(d));
        hess_.assign(tab_->quad.size(), mat<dim>::Zero(d, d));
        qk_.assign(tab_->quad.size(), vec<dim>::Zero(d));
    }
    stepper(System sys, double h, rule_kind kind, int degree, const newton_options& opt = {})
        : stepper(std::move(sys), h, std::make_shared<const tableau>(tableau::make(kind, degree)), opt) {}

    [[nodiscard]] double step_size() const { return h_; }
    [[nodiscard]] const System& system() const { return sys_; }
    [[nodiscard]] const tableau& table() const { return *tab_; }

    newton_report step(phase_state<dim>& x) {
        const tableau& t = *tab_;
        const int s = t.degree;
        const int d = static_cast<int>(x.q.size());
        const auto r = static_cast<int>(t.quad.size());
        const auto& minv = sys_.inverse_mass();
        const auto& v = sys_.potential();
        const double h = h_;
        // Predictor: Taylor to second order, X_l ≈ d_l h M⁻¹p − (d_l h)²/2 M⁻¹∇V(q_j).
        const vec<dim> vel = minv * x.p, acc = -(minv * v.gradient(x.q));
        for (int l = 1; l <= s; ++l) {
            const double tl = t.control[l] * h;
            x_.segment((l - 1) * d, d) = tl * vel + 0.5 * tl * tl * acc;
        }
        newton_options opt = opt_;
        opt.typical = x_.lpNorm<Eigen::Infinity>();
        newton_monitor monitor(opt);
        newton_report rep;
        while (true) {
            evaluate(x, d, true);
            rep.residual = r_.lpNorm<Eigen::Infinity>();
            if (monitor.exhausted()) return rep;
            lu_.compute(jac_);
            delta_.noalias() = lu_.solve(r_);
            const double step = delta_.lpNorm<Eigen::Infinity>();
            rep.iterations = monitor.iterations() + 1;
            if (!std::isfinite(step) || !std::isfinite(rep.residual)) return rep;
            x_ -= delta_;
            if (monitor.converged(step, x_.lpNorm<Eigen::Infinity>())) break;
        }
        rep.converged = true;
        evaluate(x, d, false); // ∇V at the converged quadrature points
        vec<dim> dp = vec<dim>::Zero(d);
        for (int k = 0; k < r; ++k) dp -= (h * t.quad.weights[k]) * grad_[k];
        sum_.add_q(x, x_.segment((s - 1) * d, d));
        sum_.add_p(x, dp);
        return rep;
    }

private:
    // Fills q_k, ∇V(q_k) and, if `newton`, the residual r_ and Jacobian jac_ at the increments x_.
    void evaluate(const phase_state<dim>& x, int d, bool newton) {
        const tableau& t = *tab_;
        const int s = t.degree;
        const auto r = static_cast<int>(t.quad.size());
        const auto& m = sys_.mass();
        const auto& v = sys_.potential();
        const double h2 = h_ * h_;
        for (int k = 0; k < r; ++k) {
            qk_[k] = x.q;
            for (int l = 1; l <= s; ++l)
                if (t.phi(l, k) != 0.0) qk_[k] += t.phi(l, k) * x_.segment((l - 1) * d, d);
            grad_[k] = v.gradient(qk_[k]);
            if (newton) hess_[k] = v.hessian(qk_[k]);
        }
        if (!newton) return;
        for (int i = 0; i < s; ++i) {
            auto ri = r_.segment(i * d, d);
            ri.setZero();
            if (i == 0) ri = h_ * x.p;
            for (int l = 1; l <= s; ++l) {
                ri += t.stiffness(i, l) * (m * x_.segment((l - 1) * d, d));
                auto block = jac_.block(i * d, (l - 1) * d, d, d);
                block = t.stiffness(i, l) * m;
                for (int k = 0; k < r; ++k) {
                    const double c = h2 * t.quad.weights[k] * t.phi(i, k) * t.phi(l, k);
                    if (c != 0.0) block -= c * hess_[k];
                }
            }
            for (int k = 0; k < r; ++k)
                if (t.phi(i, k) != 0.0) ri -= (h2 * t.quad.weights[k] * t.phi(i, k)) * grad_[k];
        }
    }

    System sys_;
    double h_;
    newton_options opt_;
    std::shared_ptr<const tableau> tab_;
    Eigen::VectorXd x_, r_, delta_;
    Eigen::MatrixXd jac_;
    Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
    std::vector<vec<dim>> grad_, qk_;
    std::vector<mat<dim>> hess_;
    compensated_update<dim> sum_;
};

} // namespace varsym::galerkin
