// varsym/optimal/costs.hpp: the running cost c(q, q̇, t, u) of an optimal control problem,
// integrated by the action's quadrature (J = Σ_k h Σ_j w_j c(q_kj, v_kj, t_kj, u_kj)), with its
// gradient and Hessian in z = (q, q̇, u):
//   effort     ½ uᵀ R u;
//   invariant  ½ τᵀ M(q, q̇)⁻¹ τ, τ = f(q, q̇, t, u) the generalized force of the inputs and
//              M = ∂²L/∂q̇² (Rojas-Quintero et al. 2022: the same for every choice of
//              coordinates); its gradient needs L's third derivatives (third_order.hpp), its
//              Hessian would need the fourth: it runs with the limited-memory Hessian;
//   power      Σ_i √((τ_i q̇_i)² + ε²), the absolute mechanical power of each input's
//              generalized force, smoothed at zero by ε.
// See docs/optimal_control.md.
#pragma once

#include <Eigen/Cholesky>

#include "varsym/optimal/control_force.hpp"
#include "varsym/optimal/problem.hpp"
#include "varsym/optimal/third_order.hpp"

namespace varsym::optimal {

template <lagrangian L, class F>
struct running_cost {
    static constexpr int D = L::dim, M = F::controls, N = 2 * D + M;
    using zvec = Eigen::Matrix<double, N, 1>;
    using zmat = Eigen::Matrix<double, N, N>;

    /// c(z) and, if `gradient`, ∇c; if `hessian`, ∇²c (effort and power only).
    static double evaluate(const L& l, const F& f, const cost_weights& w, const Eigen::MatrixXd& r,
                           const vec<D>& q, const vec<D>& v, double t, const vec<M>& u,
                           zvec* gradient, zmat* hessian) {
        double c = 0.0;
        if (gradient) gradient->setZero();
        if (hessian) hessian->setZero();
        if (w.effort > 0.0) {
            c += 0.5 * w.effort * u.dot(r * u);
            if (gradient) gradient->template tail<M>() += w.effort * (r * u);
            if (hessian) hessian->template bottomRightCorner<M, M>() += w.effort * r;
        }
        if (w.power > 0.0) c += power(f, w.power, w.power_smoothing, q, v, t, u, gradient, hessian);
        if (w.invariant > 0.0) c += invariant(l, f, w.invariant, q, v, t, u, gradient);
        return c;
    }

  private:
    static double power(const F& f, double weight, double eps, const vec<D>& q, const vec<D>& v,
                        double t, const vec<M>& u, zvec* gradient, zmat* hessian) {
        using S = typename force_in_z<F>::S;
        const force_in_z<F> z(f, q, v, t, u);
        S sum = S(0.0);
        for (int i = 0; i < D; ++i) {
            using std::sqrt;
            const S p = z.f(i) * z.v(i);
            sum += sqrt(p * p + S(eps * eps));
        }
        zvec g;
        zmat h;
        const double value = ad::unpack(sum, g, h);
        if (gradient) *gradient += weight * g;
        if (hessian) *hessian += weight * h;
        return weight * value;
    }

    static double invariant(const L& l, const F& f, double weight, const vec<D>& q, const vec<D>& v,
                            double t, const vec<M>& u, zvec* gradient) {
        lagrangian_terms<D> lt;
        varsym::evaluate(l, q, v, t, lt);
        control_terms<F> ft;
        ft.evaluate(f, q, v, t, u);
        const Eigen::LLT<mat<D>> llt(lt.lvv);
        if (llt.info() != Eigen::Success) return std::nan(""); // M not positive definite
        const vec<D> w = llt.solve(ft.f);
        if (gradient) {
            // ∂c/∂z_k = (∂τ/∂z_k)ᵀ w − ½ wᵀ (∂M/∂z_k) w, the last from L's third derivatives.
            const mat<2 * D> third = contracted_third(l, q, v, t, vec<D>::Zero(), w);
            const vec<2 * D> bend = third.template rightCols<D>() * w;
            gradient->template head<D>() += weight * (ft.fq.transpose() * w - 0.5 * bend.head(D));
            gradient->template segment<D>(D) +=
                weight * (ft.fv.transpose() * w - 0.5 * bend.tail(D));
            gradient->template tail<M>() += weight * (ft.fu.transpose() * w);
        }
        return 0.5 * weight * ft.f.dot(w);
    }
};

} // namespace varsym::optimal
