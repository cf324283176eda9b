// optimal/src/transcription_constraints.cpp: holonomic constraints g(q) = 0 in the DMOC
// transcription (transcription.hpp), the discrete constrained Lagrange–d'Alembert equations of
// the constrained engine (schemes/constrained.hpp; Marsden & West 2001, §3.5; for optimal control
// Leyendecker, Ober-Blöbaum, Marsden & Ortiz 2010): the discrete action augmented by
// −Σ_g Λ_gᵀ g(Q_g) at every control value, so that
//   E_g − G(Q_g)ᵀ Λ_g = 0 (g = 0 … Ns),   g(Q_g) = 0 (0 < g < Ns; the ends are given on it).
// Each function does nothing without constraints (k = 0).
#include <cstdio>

#include <Eigen/LU>

#include "varsym/optimize/transcription.hpp"

namespace varsym::optimal {

/// Refuses boundary states off the constraints (|g(q)| or |G q̇| above 1e-10 relative to |G|
/// and the state's size) or at dependent constraints, and a free final state.
void dmoc_transcription::check_boundary_constraints() const {
    if (k_ == 0) return;
    if (free_end_)
        throw std::invalid_argument("a free final state with holonomic constraints is not "
                                    "supported: fix the final state on the constraints");
    vector g;
    matrix jac;
    for (const bool first : {true, false}) {
        const vector &q = first ? p_.q_start : p_.q_end, &v = first ? p_.v_start : p_.v_end;
        const char* which = first ? "start" : "end";
        sys_->constraint(q, g, jac);
        char buf[240];
        if (Eigen::FullPivLU<matrix>(jac).rank() < k_) {
            std::snprintf(buf, sizeof buf,
                          "the constraints are dependent at the %s position (G has rank below "
                          "%d): give independent constraints",
                          which, k_);
            throw std::invalid_argument(buf);
        }
        const double scale = jac.lpNorm<Eigen::Infinity>(), tolerance = 1e-10;
        const double off = g.lpNorm<Eigen::Infinity>(),
                     across = (jac * v).lpNorm<Eigen::Infinity>();
        if (!(off <= tolerance * scale * std::max(1.0, q.lpNorm<Eigen::Infinity>()))) {
            std::snprintf(buf, sizeof buf,
                          "the %s position violates the constraints (max |g(q)| = %.3g): give a "
                          "position on them",
                          which, off);
            throw std::invalid_argument(buf);
        }
        if (!(across <= tolerance * scale * std::max(1.0, v.lpNorm<Eigen::Infinity>()))) {
            std::snprintf(buf, sizeof buf,
                          "the %s velocity is not tangent to the constraints (max |G q'| = %.3g): "
                          "give a velocity along them",
                          which, across);
            throw std::invalid_argument(buf);
        }
    }
}

void dmoc_transcription::add_constraint_residual(cvector x, vector& e) const {
    vector g;
    matrix jac;
    for (int n = 0; k_ > 0 && n < points_; ++n) {
        sys_->constraint(x.segment(n * d_, d_), g, jac);
        e.segment(n * d_, d_) -= jac.transpose() * x.segment(multiplier_index(n), k_);
        if (n > 0 && n + 1 < points_) e.segment(points_ * d_ + (n - 1) * k_, k_) = g;
    }
}

/// The pattern (if `pattern`) or the values (appended to `values`): per control value n, the
/// rows of E_n against Q_n (−Σ_a Λ_a ∇²g_a) and Λ_n (−Gᵀ), and the rows of g(Q_n) against Q_n
/// (G) between the ends.
void dmoc_transcription::add_constraint_jacobian(cvector x, sparsity* pattern,
                                                 std::vector<double>* values) const {
    vector g;
    matrix jac, curvature;
    for (int n = 0; k_ > 0 && n < points_; ++n) {
        const bool inner = n > 0 && n + 1 < points_;
        if (values) {
            const vector q = x.segment(n * d_, d_);
            sys_->constraint(q, g, jac);
            sys_->constraint_curvature(q, x.segment(multiplier_index(n), k_), curvature);
        }
        for (int row = 0; row < d_; ++row) {
            for (int col = 0; col < d_; ++col)
                pattern ? pattern->add(n * d_ + row, n * d_ + col)
                        : values->push_back(-curvature(row, col));
            for (int a = 0; a < k_; ++a)
                pattern ? pattern->add(n * d_ + row, multiplier_index(n) + a)
                        : values->push_back(-jac(a, row));
        }
        for (int a = 0; inner && a < k_; ++a)
            for (int col = 0; col < d_; ++col)
                pattern ? pattern->add(points_ * d_ + (n - 1) * k_ + a, n * d_ + col)
                        : values->push_back(jac(a, col));
    }
}

/// The lower triangle over (Q_n, Λ_n) of the Hessian of −λ_nᵀG(Q_n)ᵀΛ_n + ν_nᵀg(Q_n),
/// ν_n the multipliers of g(Q_n) = 0 (none at the ends).
void dmoc_transcription::add_constraint_hessian(cvector x, cvector lambda, sparsity* pattern,
                                                std::vector<double>* values) const {
    const auto index = [&](int n, int i) {
        return i < d_ ? n * d_ + i : multiplier_index(n) + i - d_;
    };
    matrix h;
    for (int n = 0; k_ > 0 && n < points_; ++n) {
        if (values) {
            const bool inner = n > 0 && n + 1 < points_;
            sys_->constraint_hessian(x.segment(n * d_, d_), x.segment(multiplier_index(n), k_),
                                     lambda.segment(n * d_, d_),
                                     inner ? vector(lambda.segment(points_ * d_ + (n - 1) * k_, k_))
                                           : vector(vector::Zero(k_)),
                                     h);
        }
        for (int row = 0; row < d_ + k_; ++row)
            for (int col = 0; col <= std::min(row, d_ - 1); ++col) // Λ×Λ is zero
                pattern ? pattern->add(index(n, row), index(n, col))
                        : values->push_back(h(row, col));
    }
}

// The end target φ(Q_{Ns}) (control_problem::end_target): t_ rows φ = 0 after the constraints'
// as a constraint, or the terminal cost ½ w |φ|² (terminal_cost). Nothing without one.

double dmoc_transcription::target_cost(cvector x, vector* gradient) const {
    if (!p_.end_target || t_ > 0) return 0.0;
    vector phi;
    matrix jac;
    p_.end_target->evaluate(x.segment((points_ - 1) * d_, d_), phi, gradient ? &jac : nullptr);
    const double w = p_.end_target_weight;
    if (gradient) gradient->segment((points_ - 1) * d_, d_) += w * (jac.transpose() * phi);
    return 0.5 * w * phi.squaredNorm();
}

vector dmoc_transcription::end_guess() const {
    vector q = p_.q_end.cwiseMax(p_.position_lower).cwiseMin(p_.position_upper);
    if (!p_.end_target) return q;
    // Levenberg–Marquardt: (JᵀJ + μ diag) δ = −Jᵀφ, μ shrunk on success and grown on failure,
    // the step clipped into the bounds. From a singular pose (an arm stretched straight) the
    // damping still moves along Jᵀφ.
    vector phi, trial_phi;
    matrix jac;
    p_.end_target->evaluate(q, phi, &jac);
    double mu = 1e-3;
    for (int it = 0; it < 200 && phi.norm() > 1e-12; ++it) {
        const matrix a = jac.transpose() * jac;
        matrix damped = a;
        damped.diagonal().array() += mu * (1.0 + a.diagonal().maxCoeff());
        const vector step = damped.ldlt().solve(-(jac.transpose() * phi));
        const vector trial = (q + step).cwiseMax(p_.position_lower).cwiseMin(p_.position_upper);
        p_.end_target->evaluate(trial, trial_phi, nullptr);
        if (trial_phi.allFinite() && trial_phi.norm() < phi.norm()) {
            q = trial;
            p_.end_target->evaluate(q, phi, &jac);
            mu = std::max(mu / 3.0, 1e-12);
        } else if ((mu *= 4.0) > 1e8) {
            break;
        }
    }
    return q;
}

void dmoc_transcription::add_target_residual(cvector x, vector& e) const {
    if (t_ == 0) return;
    vector phi;
    p_.end_target->evaluate(x.segment((points_ - 1) * d_, d_), phi, nullptr);
    e.segment(target_row(), t_) = phi;
}

/// The rows of φ against Q_{Ns}: ∂φ/∂q, dense.
void dmoc_transcription::add_target_jacobian(cvector x, sparsity* pattern,
                                             std::vector<double>* values) const {
    if (t_ == 0) return;
    vector phi;
    matrix jac;
    if (values) p_.end_target->evaluate(x.segment((points_ - 1) * d_, d_), phi, &jac);
    for (int row = 0; row < t_; ++row)
        for (int col = 0; col < d_; ++col)
            pattern ? pattern->add(target_row() + row, (points_ - 1) * d_ + col)
                    : values->push_back(jac(row, col));
}

void dmoc_transcription::add_target_hessian(cvector x, double sigma, cvector lambda,
                                            matrix& he) const {
    if (!p_.end_target) return;
    const vector q = x.segment((points_ - 1) * d_, d_);
    matrix curvature;
    if (t_ > 0) {
        p_.end_target->curvature(q, lambda.segment(target_row(), t_), curvature);
        he.topLeftCorner(d_, d_) += curvature;
        return;
    }
    vector phi;
    matrix jac;
    p_.end_target->evaluate(q, phi, &jac);
    p_.end_target->curvature(q, phi, curvature);
    he.topLeftCorner(d_, d_) += sigma * p_.end_target_weight * (jac.transpose() * jac + curvature);
}

} // namespace varsym::optimal
