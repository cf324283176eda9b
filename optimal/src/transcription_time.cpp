// optimal/src/transcription_time.cpp: the Hessian's row of a free final time T (transcription.hpp,
// control_problem::free_time). h = T/N enters each quadrature point's term of the equations as
// its factor h and through q̇ = V/h, V = Σ ℓ_l' Q_l, and the bounds' velocity rows through V/h;
// so the Lagrangian's second derivatives in (T, T), (T, Q) and (T, u) follow from the point's first
// and second derivatives and the Hessian in z = (q, q̇, u) the steps already form.
#include "varsym/optimize/transcription.hpp"

namespace varsym::optimal {

/// At step k's point j: the term w [h Ψ(z) + B(z)] with Ψ = aᵀ(∂L/∂q + f) + σ c (a = Σ ℓ_i λ_i,
/// c the running cost) and B = b̃ᵀ ∂L/∂q̇ (b̃ = Σ ℓ_i' λ_i), z = (q, V/h, u): with e = ∂z/∂h =
/// (0, −q̇/h, 0) and ∂²z/∂h² = (0, 2q̇/h², 0),
///   ∂²/∂h²   = 2w ∇Ψ·e + eᵀ H e + w ∇_q̇(hΨ + B)·2q̇/h²,
///   ∂²/∂h∂Q_l = w (ℓ_l ∇_qΨ + ℓ_l'/h ∇_q̇Ψ) + (ℓ_l H_q,q̇ + ℓ_l'/h H_q̇,q̇) e − w ℓ_l'/h² ∇_q̇(hΨ + B),
///   ∂²/∂h∂u   = w ∇_uΨ + H_u,q̇ e,
/// where H = w (h ∇²Ψ + ∇²B) is `hz`, the point's Hessian in z; ∂/∂T = ∂/∂h / N. `at` is
/// the point as step_hessians has it: z, t, c's gradient ∇c in z, a and b = b̃/h.
void dmoc_transcription::add_time_point(const time_point& at, double sigma, int k, int j, double h,
                                        const matrix& hz, vector& row) const {
    const vector &q = at.q, &v = at.v, &u = at.u, &gc = at.cost_gradient, &a = at.a;
    const double t = at.t, w = weight(j);
    lagrangian_terms<dynamic> lt;
    input_terms ft;
    sys_->derivatives(q, v, t, lt);
    sys_->force(q, v, t, u, ft, true);
    const vector gq = (lt.lqq + ft.fq).transpose() * a + sigma * gc.head(d_),
                 gv = (lt.lqv + ft.fv).transpose() * a + sigma * gc.segment(d_, d_),
                 gu = ft.fu.transpose() * a + sigma * gc.tail(m_),
                 wv = h * gv + lt.lvv * (h * at.b), e = -v / h;
    const vector hvv_e = hz.block(d_, d_, d_, d_) * e, hqv_e = hz.block(0, d_, d_, d_) * e;
    const double n = n_;
    row(time_index()) +=
        (2.0 * w * gv.dot(e) + e.dot(hvv_e) + w * wv.dot(2.0 * v / (h * h))) / (n * n);
    for (int l = 0; l <= s_; ++l) {
        const double pl = tab_.phi(l, j), dl = tab_.dphi(l, j) / h;
        row.segment((k * s_ + l) * d_, d_) +=
            (w * (pl * gq + dl * gv) + pl * hqv_e + dl * hvv_e - w * dl / h * wv) / n;
    }
    row.segment(control_index(k * r_ + j), m_) += (w * gu + hz.block(2 * d_, d_, m_, d_) * e) / n;
}

/// The bounds' velocity rows V/h with their multipliers μ: ∂²/∂h² = 2 μ V/h³, ∂²/∂h∂Q_l
/// = −μ ℓ_l'(τ)/h²; and the row's entries after the others (pattern or values).
void dmoc_transcription::add_time_hessian(cvector x, cvector lambda, vector* row, sparsity* pattern,
                                          std::vector<double>* values) const {
    if (!p_.free_time) return;
    const int last = time_index();
    const auto columns = [&](const auto& each) {
        for (int c = 0; c < points_ * d_; ++c)
            each(c);
        for (int c = control_index(0); c < control_index(n_ * r_); ++c)
            each(c);
        each(last);
    };
    if (pattern) {
        columns([&](int c) { pattern->add(last, c); });
        return;
    }
    const double h = h_of(x), n = n_;
    vector g = vector::Zero(constraints()); // the rows' values: V/h for the velocity rows
    add_path_residual(x, g);
    int r = path_row();
    for (const path_bound& b : path_bounds_)
        for (int k = 0; k < n_; ++k)
            for (Eigen::Index e = 0; e < b.weights.cols(); ++e)
                for (const int i : b.coordinates) {
                    const double mu = lambda(r), speed = g(r);
                    ++r;
                    if (!b.velocity) continue;
                    (*row)(last) += 2.0 * mu * speed / (h * h * n * n);
                    for (int l = 0; l <= s_; ++l)
                        (*row)((k * s_ + l) * d_ + i) -= mu * b.weights(l, e) / (h * h * n);
                }
    columns([&](int c) { values->push_back((*row)(c)); });
}

} // namespace varsym::optimal
