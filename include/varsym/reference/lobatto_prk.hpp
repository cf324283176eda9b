// varsym/reference/lobatto_prk.hpp: the (s+1)-stage Lobatto IIIA–IIIB partitioned Runge–Kutta
// method for separable Hamiltonians H = ½ pᵀM⁻¹p + V(q), written from its Butcher tableaux and
// solved by fixed-point iteration: an implementation independent of the variational
// (galerkin.hpp) one, which for constant M it must equal step by step (Hairer, Lubich &
// Wanner, Geometric Numerical Integration, §VI.6).
#pragma once

#include <cmath>
#include <stdexcept>
#include <vector>

#include "varsym/quadrature/rules.hpp"
#include "varsym/solvers/newton.hpp"
#include "varsym/systems/separable.hpp"

namespace varsym::lobatto_prk {

/// Tableaux on the s+1 Lobatto nodes c_i with weights b_i:
///   IIIA: a_ij = ∫₀^{c_i} ℓ_j(τ) dτ (collocation), IIIB: â_ij = b_j (1 − a_ji / b_i).
struct tableau {
    std::vector<double> b;
    Eigen::MatrixXd a, a_hat;

    static tableau make(int s) {
        using LD = long double;
        const auto lob = quadrature::gauss_lobatto<LD>(s + 1);
        const auto gl = quadrature::gauss_legendre<LD>(s + 1); // exact for degree ≤ 2s + 1
        const int n = s + 1;
        Eigen::Matrix<LD, Eigen::Dynamic, Eigen::Dynamic> a(n, n);
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) {
                LD integral = 0;
                for (std::size_t k = 0; k < gl.size(); ++k) {
                    const LD tau = lob.nodes[i] * gl.nodes[k];
                    LD l = 1;
                    for (int m = 0; m < n; ++m)
                        if (m != j) l *= (tau - lob.nodes[m]) / (lob.nodes[j] - lob.nodes[m]);
                    integral += gl.weights[k] * l;
                }
                a(i, j) = lob.nodes[i] * integral;
            }
        tableau t;
        t.a = a.cast<double>();
        t.a_hat.resize(n, n);
        t.b.assign(lob.weights.begin(), lob.weights.end());
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j)
                t.a_hat(i, j) =
                    static_cast<double>(lob.weights[j] * (1 - a(j, i) / lob.weights[i]));
        return t;
    }
};

/// Stages Q_i = q₀ + h Σ_j a_ij M⁻¹P_j, P_i = p₀ − h Σ_j â_ij ∇V(Q_j), then
/// q₁ = q₀ + h Σ b_j M⁻¹P_j, p₁ = p₀ − h Σ b_j ∇V(Q_j). The stage equations are solved by
/// fixed-point iteration (a contraction for h small against the system's frequencies) until
/// the stages stop changing; the report counts sweeps.
template <class System>
class stepper {
  public:
    static constexpr int dim = System::dim;
    using system_type = System;

    stepper(System sys, double h, int degree, int max_sweeps = 1000)
        : sys_(std::move(sys)), h_(h), tab_(tableau::make(degree)), max_sweeps_(max_sweeps) {}
    [[nodiscard]] double step_size() const { return h_; }
    [[nodiscard]] const System& system() const { return sys_; }

    newton_report step(phase_state<dim>& x) {
        const auto n = static_cast<int>(tab_.b.size());
        const auto& minv = sys_.inverse_mass();
        const auto& v = sys_.potential();
        const double h = h_;
        std::vector<vec<dim>> q(n, x.q), p(n, x.p), f(n);
        newton_report rep;
        double previous = std::numeric_limits<double>::infinity();
        for (rep.iterations = 1; rep.iterations <= max_sweeps_; ++rep.iterations) {
            double change = 0;
            for (int i = 0; i < n; ++i) {
                vec<dim> qi = x.q;
                for (int j = 0; j < n; ++j)
                    qi += (h * tab_.a(i, j)) * (minv * p[j]);
                change = std::max(change, (qi - q[i]).template lpNorm<Eigen::Infinity>());
                q[i] = qi;
            }
            for (int i = 0; i < n; ++i)
                f[i] = v.gradient(q[i]);
            for (int i = 0; i < n; ++i) {
                vec<dim> pi = x.p;
                for (int j = 0; j < n; ++j)
                    pi -= (h * tab_.a_hat(i, j)) * f[j];
                change = std::max(change, (pi - p[i]).template lpNorm<Eigen::Infinity>());
                p[i] = pi;
            }
            rep.residual = change;
            if (!std::isfinite(change)) return rep;
            // Converged once the sweeps stop shrinking the change at the round-off level.
            const double scale = std::max(x.q.template lpNorm<Eigen::Infinity>(),
                                          x.p.template lpNorm<Eigen::Infinity>());
            if (change == 0 || (change <= 64 * std::numeric_limits<double>::epsilon() * scale &&
                                change >= 0.5 * previous)) {
                rep.converged = true;
                break;
            }
            previous = change;
        }
        if (!rep.converged) return rep;
        vec<dim> dq = vec<dim>::Zero(x.q.size()), dp = vec<dim>::Zero(x.q.size());
        for (int j = 0; j < n; ++j) {
            dq += (h * tab_.b[j]) * (minv * p[j]);
            dp -= (h * tab_.b[j]) * f[j];
        }
        x.q += dq;
        x.p += dp;
        return rep;
    }

  private:
    System sys_;
    double h_;
    tableau tab_;
    int max_sweeps_;
};

} // namespace varsym::lobatto_prk
