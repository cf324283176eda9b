// varsym/optimal/control_force.hpp: a generalized force with control inputs f(q, q̇, t, u), as
// the optimal control transcriptions take it, and its value with Jacobians in q, q̇ and u.
#pragma once

#include "varsym/autodiff/second_order.hpp"
#include "varsym/systems/lagrangian.hpp"

namespace varsym::optimal {

/// A generalized force with control inputs, as controlled<F> takes (systems/forcing.hpp):
/// `static constexpr int dim, controls` and
/// `template <class T> tvec<T, dim> operator()(q, v, double t, const tvec<T, controls>& u)`.
template <class F>
concept control_force = requires {
    F::dim;
    F::controls;
}
&&(F::dim >= 1) && (F::controls >= 1);

/// f(q, v, t, u) and its Jacobians in q, v and u (one forward-mode pass).
template <control_force F>
struct control_terms {
    static constexpr int D = F::dim, M = F::controls;
    vec<D> f;
    mat<D> fq, fv;
    Eigen::Matrix<double, D, M> fu;

    void evaluate(const F& force, const vec<D>& q, const vec<D>& v, double t, const vec<M>& u) {
        using J = ad::first_order<2 * D + M>;
        tvec<J, D> qj, vj;
        tvec<J, M> uj;
        for (int i = 0; i < D; ++i) {
            qj(i) = J(q(i), 2 * D + M, i);
            vj(i) = J(v(i), 2 * D + M, D + i);
        }
        for (int i = 0; i < M; ++i)
            uj(i) = J(u(i), 2 * D + M, 2 * D + i);
        const tvec<J, D> out = force(qj, vj, t, uj);
        for (int i = 0; i < D; ++i) {
            f(i) = out(i).value();
            fq.row(i) = out(i).derivatives().template head<D>().transpose();
            fv.row(i) = out(i).derivatives().template segment<D>(D).transpose();
            fu.row(i) = out(i).derivatives().template tail<M>().transpose();
        }
    }
};

} // namespace varsym::optimal
