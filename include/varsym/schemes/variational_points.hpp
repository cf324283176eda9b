// varsym/schemes/variational_points.hpp: the general engine's step equations (variational.hpp)
// at the step's quadrature points: L's derivatives and the force there, and the residual F with
// its Jacobian in the increments X.
#pragma once

#include "varsym/schemes/variational.hpp"

namespace varsym::general {

/// L and its first (and, if `second`, second) derivatives at every quadrature point
/// (q_k, v_k) for the current increments.
template <lagrangian L, class F>
void stepper<L, F>::evaluate_points(const vec<dim>& q, bool second) {
    work_ = 0.0;
    for (int k = 0; k < r_; ++k) {
        set_point(q, k);
        const double tk = point_time(k);
        if (second)
            evaluate(sys_.lagrangian(), qk_, vk_, tk, terms_[k]);
        else
            evaluate_gradient(sys_.lagrangian(), qk_, vk_, tk, terms_[k]);
        if constexpr (forced) {
            add_force(k, qk_, vk_, tk, second);
            work_ += tab_.quad.weights[static_cast<std::size_t>(k)] *
                     fterms_[static_cast<std::size_t>(k)].f.dot(vk_);
        }
    }
}

/// (q_k, v_k) of quadrature point k for the current increments from q_j = q.
template <lagrangian L, class F>
void stepper<L, F>::set_point(const vec<dim>& q, int k) {
    qk_ = q;
    vk_.setZero();
    for (int l = 0; l < s_; ++l) {
        qk_ += tab_.phi(l + 1, k) * x_.col(l);
        vk_ += tab_.dphi(l + 1, k) * x_.col(l);
    }
    for (int l = 0; l < s_; ++l)
        vk_ += tab_.dphi_lo(l + 1, k) * x_.col(l);
    vk_ /= h_;
}

/// f at point k joins L_q there (and its Jacobians are evaluated if `jacobian`).
template <lagrangian L, class F>
void stepper<L, F>::add_force(int k, const vec<dim>& q, const vec<dim>& v, double t,
                              bool jacobian) {
    auto& f = fterms_[static_cast<std::size_t>(k)];
    evaluate_force(force_, q, v, t, f, jacobian);
    terms_[static_cast<std::size_t>(k)].lq += f.f;
}

/// The residual F (rows i = 0 … s−1) and, if `jacobian`, its Jacobian in the increments.
template <lagrangian L, class F>
void stepper<L, F>::assemble(const vec<dim>& p, bool jacobian) {
    const double h = h_;
    const auto &u = tab_.wphi, &g = tab_.wdphi;
    res_.setZero();
    if (jacobian) jac_.setZero();
    for (int k = 0; k < r_; ++k) {
        const lagrangian_terms<dim>& t = terms_[k];
        for (int i = 0; i < s_; ++i) {
            auto row = block_of<dim>(res_, i, d_);
            row += (h * u.hi(i, k)) * t.lq + g.hi(i, k) * t.lv;
            row += (h * u.lo(i, k)) * t.lq + g.lo(i, k) * t.lv;
            if (!jacobian) continue;
            if (i == 0) lqvt_ = t.lqv.transpose(); // read contiguously below
            for (int l = 0; l < s_; ++l)
                add_jacobian_block(k, i, l);
        }
    }
    block_of<dim>(res_, 0, d_) += p;
}

} // namespace varsym::general
