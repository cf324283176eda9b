// varsym/solvers/stage_equation.hpp: the one implicit equation left after reducing a step of a
// separable system, M x + c ∇V(x) = b, solved by Newton with Jacobian M + c ∇²V(x).
#pragma once

#include <type_traits>

#include "varsym/solvers/newton.hpp"
#include "varsym/systems/separable.hpp"

namespace varsym {

/// A system that solves its own stage equation (e.g. in O(d) for a banded Hessian): a member
/// `newton_report solve_stage(double c, const vec& q, const vec& r, vec& delta,
/// const newton_options&) const`, used by the Simpson and Newmark steppers instead of the dense
/// Newton below.
template <class System>
concept has_stage_solver = requires(const System& s, const vec<System::dim>& q,
                                    vec<System::dim>& delta, const newton_options& opt) {
    { s.solve_stage(1.0, q, q, delta, opt) } -> std::same_as<newton_report>;
};

/// The stage equation's Jacobian M + c ∇²V, with `hessian` = ∇²V at the point: the Newton matrix
/// of the reduced steps, whose inverse their tangent maps apply (simpson.hpp, newmark.hpp).
template <separable System>
mat<System::dim> stage_jacobian(const System& sys, double c, const mat<System::dim>& hessian) {
    mat<System::dim> j = c * hessian;
    if constexpr (scalar_mass<System>)
        j.diagonal().array() += sys.mass();
    else
        j += sys.mass();
    return j;
}

/// Solves M x + c ∇V(x) = b for x = q + δ, written as  M δ + c ∇V(q + δ) = r  with r = b − M q,
/// for the increment δ (started from the guess in `delta`, whose size sets the scale of the
/// stopping test). Solving for δ rather than x keeps δ's relative accuracy when |δ| ≪ |q|, which
/// is what the update q_{j+1} = q_j + Δq needs. Newmark: c = h²/4, x = q̄ the midpoint; Simpson:
/// c = h²/24, x = q_{j+½} (docs/design.md, "Reduced steps"). A system with its own
/// solve_stage member (has_stage_solver) solves it instead.
template <separable System>
newton_report solve_stage_increment(const System& sys, double c, const vec<System::dim>& q,
                                    const vec<System::dim>& r, vec<System::dim>& delta,
                                    const newton_options& opt) {
    if constexpr (has_stage_solver<System>) {
        return sys.solve_stage(c, q, r, delta, opt);
    } else {
        constexpr int D = System::dim;
        const auto& m = sys.mass();
        const auto& v = sys.potential();
        newton_options local = opt;
        local.typical = delta.template lpNorm<Eigen::Infinity>();
        local.reference = q.template lpNorm<Eigen::Infinity>();
        // x = q + δ, ∇V(x) and ∇²V(x), sized once per solve: at a run-time d a joint_potential's
        // iterations then allocate nothing.
        vec<D> x(q.size()), g(q.size());
        mat<D> hessian(q.size(), q.size());
        return newton_solve<D>(
            delta,
            [&](const vec<D>& y, vec<D>& res, mat<D>& jac) {
                x.noalias() = q + y;
                if constexpr (joint_potential<std::remove_cvref_t<decltype(v)>, D>) {
                    v.gradient_and_hessian(x, g, hessian);
                } else {
                    g = v.gradient(x);
                    hessian = v.hessian(x);
                }
                res.noalias() = m * y + c * g - r;
                if constexpr (scalar_mass<System>) {
                    jac.noalias() = c * hessian;
                    jac.diagonal().array() += m;
                } else {
                    jac.noalias() = m + c * hessian;
                }
            },
            local);
    }
}

} // namespace varsym
