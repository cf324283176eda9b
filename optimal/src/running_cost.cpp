// optimal/src/running_cost.cpp: the running cost c(q, q̇, t, u) of an optimal control problem at
// run-time size (transcription.hpp), integrated by the action's quadrature, with its gradient and
// Hessian in z = (q, q̇, u):
//   effort     ½ uᵀ R u;
//   invariant  ½ τᵀ M(q, q̇)⁻¹ τ, τ = f(q, q̇, t, u) the generalized force of the inputs and
//              M = ∂²L/∂q̇² (Rojas-Quintero et al. 2022: the same for every choice of
//              coordinates); its gradient needs L's third derivatives (controlled_system::third),
//              its Hessian would need the fourth: it runs with the limited-memory Hessian;
//   power      Σ_i √((τ_i q̇_i)² + ε²), the absolute mechanical power of each input's
//              generalized force, smoothed at zero by ε.
#include <Eigen/Cholesky>

#include "varsym/optimize/transcription.hpp"

namespace varsym::optimal {

namespace {

/// Σ_i √(p_i² + ε²), p_i = f_i v_i: ∇p_i = v_i ∇f_i + f_i e_{v_i},
/// ∇²p_i = v_i ∇²f_i + e_{v_i} ∇f_iᵀ + ∇f_i e_{v_i}ᵀ.
double power(const controlled_system& s, double weight, double eps, const vector& q,
             const vector& v, double t, const vector& u, vector* gradient, matrix* hessian) {
    const int d = static_cast<int>(q.size()), m = static_cast<int>(u.size()), n = 2 * d + m;
    input_terms f;
    s.force(q, v, t, u, f, gradient || hessian);
    double sum = 0.0;
    vector a = vector::Zero(d), dp(n);
    for (int i = 0; i < d; ++i) {
        const double p = f.f(i) * v(i), r = std::sqrt(p * p + eps * eps);
        sum += r;
        if (!gradient && !hessian) continue;
        dp << v(i) * f.fq.row(i).transpose(), v(i) * f.fv.row(i).transpose(),
            v(i) * f.fu.row(i).transpose();
        dp(d + i) += f.f(i);
        const double c1 = p / r, c2 = eps * eps / (r * r * r);
        if (gradient) *gradient += weight * c1 * dp;
        if (hessian) {
            *hessian += weight * c2 * dp * dp.transpose();
            vector df(n);
            df << f.fq.row(i).transpose(), f.fv.row(i).transpose(), f.fu.row(i).transpose();
            hessian->row(d + i) += weight * c1 * df.transpose();
            hessian->col(d + i) += weight * c1 * df;
            a(i) = c1 * v(i);
        }
    }
    if (hessian && !a.isZero(0.0)) {
        matrix h;
        s.force_hessian(q, v, t, u, a, h);
        *hessian += weight * h;
    }
    return weight * sum;
}

/// ½ τᵀ M⁻¹ τ: ∂c/∂z_k = (∂τ/∂z_k)ᵀ w − ½ wᵀ (∂M/∂z_k) w, w = M⁻¹τ, the last from L's third
/// derivatives (the Hessian of wᵀ ∂L/∂q̇ times w).
double invariant(const controlled_system& s, double weight, const vector& q, const vector& v,
                 double t, const vector& u, vector* gradient) {
    const int d = static_cast<int>(q.size()), m = static_cast<int>(u.size());
    lagrangian_terms<dynamic> lt;
    s.derivatives(q, v, t, lt);
    input_terms f;
    s.force(q, v, t, u, f, gradient != nullptr);
    const Eigen::LLT<matrix> llt(lt.lvv);
    if (llt.info() != Eigen::Success) return std::nan(""); // M not positive definite
    const vector w = llt.solve(f.f);
    if (gradient) {
        matrix third;
        s.third(q, v, t, vector::Zero(d), w, third);
        const vector bend = third.rightCols(d) * w;
        gradient->head(d) += weight * (f.fq.transpose() * w - 0.5 * bend.head(d));
        gradient->segment(d, d) += weight * (f.fv.transpose() * w - 0.5 * bend.tail(d));
        gradient->tail(m) += weight * (f.fu.transpose() * w);
    }
    return 0.5 * weight * f.f.dot(w);
}

} // namespace

double running_cost_at(const controlled_system& s, const cost_weights& w, const matrix& effort,
                       const vector& q, const vector& v, double t, const vector& u,
                       vector* gradient, matrix* hessian) {
    const int d = static_cast<int>(q.size()), m = static_cast<int>(u.size()), n = 2 * d + m;
    double c = 0.0;
    if (gradient) gradient->setZero(n);
    if (hessian) hessian->setZero(n, n);
    if (w.effort > 0.0) {
        const vector ru = effort * u;
        c += 0.5 * w.effort * u.dot(ru);
        if (gradient) gradient->tail(m) += w.effort * ru;
        if (hessian) hessian->bottomRightCorner(m, m) += w.effort * effort;
    }
    if (w.power > 0.0) c += power(s, w.power, w.power_smoothing, q, v, t, u, gradient, hessian);
    if (w.invariant > 0.0) c += invariant(s, w.invariant, q, v, t, u, gradient);
    return c;
}

} // namespace varsym::optimal
