// varsym/contact/cone_solver.hpp: one step's contact problem with the gaps and slips linearised
// in the impulses, solved by a primal–dual interior-point method on the exact (second-order)
// friction cone, as Dojo's (Howell et al. 2022, §IV) and the conic complementarity literature
// (Alizadeh & Goldfarb 2003).
//
// k contacts; contact i has a normal impulse γ_i and a friction impulse b_i ∈ R² [N s], the end
// of the step's gap φ_i [m] and the slip d_i ∈ R² [m] (its contact point's tangential
// displacement over the step), affine in λ = (γ_1, b_1, …): (φ_i, d_i) = c_i + A_i λ. Wanted:
//   φ_i ≥ 0,  γ_i ≥ 0,  γ_i φ_i = 0                                  (non-penetration)  (C1)
//   (μ_i γ_i, b_i) ∈ K,  (η_i, d_i) ∈ K,  (μγ, b)ᵀ(η, d) = 0           (Coulomb, max. dissipation)
//   (C2)
// with K = {(z₀, z₁) : z₀ ≥ |z₁|} the second-order cone: sticking (d = 0, |b| ≤ μγ) or sliding
// (b = −μγ d/|d|, η = |d|). The central path relaxes the complementarities to γs = κ and
// z∘w = κe (Jordan product z∘w = (zᵀw, z₀w₁ + w₀z₁), e = (1, 0)) with a slack s = φ > 0;
// Newton's method follows it with Mehrotra's centring (σ = (m_aff/m)³) and a step to 0.99 of
// the boundary of the cones; its linear system is reduced to the impulses' 3k unknowns (the whole
// solve on the A1's four feet 2.5 times faster than with the 5k-unknown system; docs/contact.md).
// Unknowns λ (3k), s (k), η (k); equations
//   s − φ(λ) = 0,  γs = κ,  μγη + bᵀd(λ) = κ,  μγ d(λ) + η b = 0.
// A frictionless contact (μ = 0) has b = 0 and η = 1 instead of its cone's rows. Lengths and
// impulses are scaled to order one before the iteration (ℓ the largest |c|, the impulse that
// moves a gap by ℓ); it stops when every residual and complementarity is below
// tolerance/ℓ in those units: gaps and slips within `tolerance` metres of the conditions.
// solve_cone is a template with a defaulted parameter (`template <class = void>`), called as a
// plain function: a source that includes this header and never calls it does not compile its
// dense LU (docs/development.md).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <Eigen/Dense>

#include "varsym/solvers/small_lu.hpp"

namespace varsym::contact {

/// The linearised problem: (φ, d) = c + A λ, rows 3i (gap), 3i+1, 3i+2 (slip) per contact, λ in
/// the same order (γ_i, b_i).
struct cone_problem {
    Eigen::VectorXd c;  ///< 3k
    Eigen::MatrixXd a;  ///< 3k × 3k
    Eigen::VectorXd mu; ///< k friction coefficients ≥ 0
};

struct cone_options {
    double tolerance = 1e-13; ///< [m] on the gaps' and slips' conditions
    int max_iterations = 80;
};

struct cone_result {
    Eigen::VectorXd lambda; ///< (γ_i, b_i) [N s]
    Eigen::VectorXd values; ///< (φ_i, d_i) = c + A λ [m]
    int iterations = 0;
    bool converged = false;
    std::string failure; ///< why it stopped unconverged, where it can say
};

namespace cone_detail {

/// The largest α ≤ ∞ keeping (z₀ + α a₀, z₁ + α a₁) inside K, for z inside it.
inline double cone_step(double z0, const Eigen::Vector2d& z1, double a0,
                        const Eigen::Vector2d& a1) {
    const double qa = a0 * a0 - a1.squaredNorm(), qb = z0 * a0 - z1.dot(a1),
                 qc = z0 * z0 - z1.squaredNorm();
    double best = std::numeric_limits<double>::infinity();
    auto take = [&](double r) {
        if (r > 0.0) best = std::min(best, r);
    };
    if (std::abs(qa) < 1e-300) {
        if (qb < 0.0) take(-qc / (2.0 * qb));
    } else {
        const double disc = qb * qb - qa * qc;
        if (disc >= 0.0) {
            const double root = std::sqrt(disc);
            // The roots of qa α² + 2 qb α + qc, the smaller one without cancellation.
            const double q = -(qb + std::copysign(root, qb));
            if (q != 0.0) {
                take(qc / q);
                take(q / qa);
            }
        }
    }
    if (a0 < 0.0) take(-z0 / a0); // z₀ stays positive
    return best;
}

} // namespace cone_detail

/// Solves the linearised contact problem (the header comment).
template <class = void>
cone_result solve_cone(const cone_problem& p, const cone_options& o = {}) {
    using Eigen::VectorXd;
    const int k = static_cast<int>(p.mu.size()), n = 5 * k;
    cone_result out;
    out.lambda.setZero(3 * k);
    out.values = p.c;
    if (k == 0) {
        out.converged = true;
        return out;
    }
    // Scales: ℓ for lengths, g for impulses (moving the stiffest gap by ℓ).
    const double ell = std::max(p.c.lpNorm<Eigen::Infinity>(), 1e3 * o.tolerance);
    double stiff = 0.0;
    for (int i = 0; i < k; ++i)
        stiff = std::max(stiff, p.a(3 * i, 3 * i));
    const double g = stiff > 0.0 ? ell / stiff : 1.0;
    const VectorXd c = p.c / ell;
    const Eigen::MatrixXd a = p.a * (g / ell);
    const double tol = std::max(o.tolerance / ell, 1e-15);
    // v = (λ, s, η).
    VectorXd v(n), r(n), dv(n), da(n);
    v.setZero();
    for (int i = 0; i < k; ++i)
        v(3 * i) = 1.0;
    VectorXd y = c + a * v.head(3 * k); // (φ, d) at λ
    for (int i = 0; i < k; ++i) {
        v(3 * k + i) = std::max(y(3 * i), 0.0) + 1.0;
        v(4 * k + i) = p.mu(i) > 0.0 ? y.segment<2>(3 * i + 1).norm() + 1.0 : 1.0;
    }
    // Residual at centring κ into r; complementarity measure returned.
    auto residual = [&](const VectorXd& x, const VectorXd& phi, double kappa, VectorXd& res) {
        double m = 0.0;
        int cones = 0;
        for (int i = 0; i < k; ++i) {
            const double gam = x(3 * i), s = x(3 * k + i), eta = x(4 * k + i), mu = p.mu(i);
            const Eigen::Vector2d b = x.segment<2>(3 * i + 1), d = phi.segment<2>(3 * i + 1);
            res(i) = s - phi(3 * i);
            res(k + i) = gam * s - kappa;
            m += gam * s;
            if (mu > 0.0) {
                res(2 * k + i) = mu * gam * eta + b.dot(d) - kappa;
                res.segment<2>(3 * k + 2 * i) = mu * gam * d + eta * b;
                m += mu * gam * eta + b.dot(d);
                ++cones;
            } else {
                res(2 * k + i) = eta - 1.0;
                res.segment<2>(3 * k + 2 * i) = b;
            }
        }
        return m / (k + cones);
    };
    // Newton's system in v, J dv = −r, is solved reduced to λ alone (3k unknowns instead of 5k):
    // per contact the gap's row gives ds = A_n dλ − r₁, the cone's first row
    // dη = −(r₃ + μη dγ + dᵀ db + bᵀ A_t dλ)/(μγ) (γ > 0 inside the cone), and both are put into
    // the rows γs = κ and μγd + ηb = 0. A contact without friction keeps db = −r₄, dη = −r₃.
    Eigen::MatrixXd red(3 * k, 3 * k);
    small_lu lu(3 * k);
    VectorXd rr(3 * k), dl(3 * k);
    Eigen::RowVectorXd bt(3 * k);
    auto reduce = [&](const VectorXd& x, const VectorXd& phi) {
        for (int i = 0; i < k; ++i) {
            const double gam = x(3 * i), s = x(3 * k + i), eta = x(4 * k + i), mu = p.mu(i);
            red.row(3 * i) = gam * a.row(3 * i);
            red(3 * i, 3 * i) += s;
            if (mu > 0.0) {
                const Eigen::Vector2d b = x.segment<2>(3 * i + 1), d = phi.segment<2>(3 * i + 1);
                const double mg = mu * gam;
                bt.noalias() = b.transpose() * a.middleRows<2>(3 * i + 1);
                red.middleRows<2>(3 * i + 1).noalias() = mg * a.middleRows<2>(3 * i + 1);
                red.middleRows<2>(3 * i + 1).noalias() -= (b / mg) * bt;
                red.block<2, 1>(3 * i + 1, 3 * i) += mu * d - (eta / gam) * b;
                red.block<2, 2>(3 * i + 1, 3 * i + 1) +=
                    eta * Eigen::Matrix2d::Identity() - (b / mg) * d.transpose();
            } else {
                red.middleRows<2>(3 * i + 1).setZero();
                red.block<2, 2>(3 * i + 1, 3 * i + 1).setIdentity();
            }
        }
        lu.compute(red);
    };
    // The step dx for the residual res: the reduced right-hand side, its solve, then ds and dη.
    auto direction = [&](const VectorXd& x, const VectorXd& phi, const VectorXd& res,
                         VectorXd& dx) {
        for (int i = 0; i < k; ++i) {
            const double gam = x(3 * i), mu = p.mu(i);
            rr(3 * i) = -res(k + i) + gam * res(i);
            if (mu > 0.0)
                rr.segment<2>(3 * i + 1) = -res.segment<2>(3 * k + 2 * i) +
                                           x.segment<2>(3 * i + 1) * (res(2 * k + i) / (mu * gam));
            else
                rr.segment<2>(3 * i + 1) = -res.segment<2>(3 * k + 2 * i);
        }
        lu.solve(rr, dl);
        dx.head(3 * k) = dl;
        for (int i = 0; i < k; ++i) {
            const double gam = x(3 * i), eta = x(4 * k + i), mu = p.mu(i);
            dx(3 * k + i) = a.row(3 * i).dot(dl) - res(i);
            if (mu > 0.0) {
                const Eigen::Vector2d b = x.segment<2>(3 * i + 1), d = phi.segment<2>(3 * i + 1);
                dx(4 * k + i) =
                    (-res(2 * k + i) - mu * eta * dl(3 * i) - d.dot(dl.segment<2>(3 * i + 1)) -
                     b.dot(a.middleRows<2>(3 * i + 1) * dl)) /
                    (mu * gam);
            } else {
                dx(4 * k + i) = -res(2 * k + i);
            }
        }
    };
    VectorXd dphi(3 * k);
    // The largest step to the boundary along dx.
    auto longest = [&](const VectorXd& x, const VectorXd& phi, const VectorXd& dx) {
        dphi.noalias() = a * dx.head(3 * k);
        double alpha = std::numeric_limits<double>::infinity();
        for (int i = 0; i < k; ++i) {
            for (const int j : {3 * i, 3 * k + i})
                if (dx(j) < 0.0) alpha = std::min(alpha, -x(j) / dx(j));
            const double mu = p.mu(i);
            if (mu <= 0.0) continue;
            alpha =
                std::min(alpha, cone_detail::cone_step(mu * x(3 * i), x.segment<2>(3 * i + 1),
                                                       mu * dx(3 * i), dx.segment<2>(3 * i + 1)));
            alpha =
                std::min(alpha, cone_detail::cone_step(x(4 * k + i), phi.segment<2>(3 * i + 1),
                                                       dx(4 * k + i), dphi.segment<2>(3 * i + 1)));
        }
        return alpha;
    };
    VectorXd trial(n), phi_trial(3 * k), scratch(n);
    for (int it = 0; it < o.max_iterations; ++it) {
        y.noalias() = c + a * v.head(3 * k);
        const double m = residual(v, y, 0.0, r);
        double worst = 0.0;
        for (int i = 0; i < k; ++i) {
            worst = std::max(worst, std::abs(r(i)));
            worst = std::max(worst, std::abs(r(k + i)));
            worst = std::max(worst, std::abs(r(2 * k + i)));
            worst = std::max(worst, r.segment<2>(3 * k + 2 * i).lpNorm<Eigen::Infinity>());
        }
        out.iterations = it;
        if (!r.allFinite() || !std::isfinite(m)) {
            out.failure = "met a value that is not finite (an infinite friction or gap?)";
            break;
        }
        if (worst <= tol) {
            out.converged = true;
            break;
        }
        out.iterations = it + 1;
        reduce(v, y);
        direction(v, y, r, da); // the affine (predictor) direction
        if (!da.allFinite()) {
            out.failure = "met a singular system (a value that is not finite?)";
            break;
        }
        const double alpha_aff = std::min(1.0, longest(v, y, da));
        trial = v + alpha_aff * da;
        phi_trial.noalias() = c + a * trial.head(3 * k);
        const double m_aff = residual(trial, phi_trial, 0.0, scratch);
        const double sigma = std::clamp(std::pow(std::max(m_aff, 0.0) / m, 3), 0.0, 1.0);
        residual(v, y, sigma * m, r);
        direction(v, y, r, dv);
        if (!dv.allFinite()) {
            out.failure = "met a singular system (a value that is not finite?)";
            break;
        }
        const double alpha = std::min(1.0, 0.99 * longest(v, y, dv));
        v += alpha * dv;
    }
    // Purification: a contact whose impulse moves its own gap less than the gap stays open is
    // inactive (γ = 0, b = 0). The central path leaves γ ~ s ~ √tolerance on a contact that
    // touches without pressing (a ball at rest against a wall); those impulses would push.
    if (out.converged)
        for (int i = 0; i < k; ++i)
            if (a(3 * i, 3 * i) * v(3 * i) < v(3 * k + i)) v.segment<3>(3 * i).setZero();
    out.lambda = g * v.head(3 * k);
    out.values = p.c + p.a * out.lambda;
    return out;
}

} // namespace varsym::contact
