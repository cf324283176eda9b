// varsym/solvers/stage_equation.hpp: the one implicit equation left after reducing a step of a
// separable system, M x + c ∇V(x) = b, solved by Newton with Jacobian M + c ∇²V(x).
#pragma once

#include <type_traits>

#include "varsym/solvers/newton.hpp"
#include "varsym/systems/separable.hpp"

namespace varsym {

/// The scratch of the dense stage Newton below: x = q + δ, ∇V(x), ∇²V(x) and Newton's own
/// (newton_workspace), kept by the stepper so that a step at a run-time d allocates none of them.
template <int D>
struct dense_stage_workspace {
    vec<D> x, gradient;
    mat<D> hessian;
    newton_workspace<D> newton;
};

/// A system that solves its own stage equation (e.g. in O(d) for a banded Hessian): a type
/// `stage_workspace` (its scratch, default-constructible, sized by the solve itself and kept
/// by the stepper across steps) and a member `newton_report solve_stage(double c, const vec& q,
/// const vec& r, vec& delta, const newton_options&, stage_workspace&) const`, used by the
/// Simpson and Newmark steppers instead of the dense Newton below.
template <class System>
concept has_stage_solver = requires(const System& s, const vec<System::dim>& q,
                                    vec<System::dim>& delta, const newton_options& opt,
                                    typename System::stage_workspace& ws) {
    { s.solve_stage(1.0, q, q, delta, opt, ws) } -> std::same_as<newton_report>;
};

/// The scratch a stepper keeps for solve_stage_increment on System.
template <class System>
struct stage_workspace_for {
    using type = dense_stage_workspace<System::dim>;
};
template <has_stage_solver System>
struct stage_workspace_for<System> {
    using type = typename System::stage_workspace;
};
template <class System>
using stage_workspace_of = typename stage_workspace_for<System>::type;

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
/// solve_stage member (has_stage_solver) solves it instead. The vectors and matrices are `ws`'s.
template <separable System>
newton_report solve_stage_increment(const System& sys, double c, const vec<System::dim>& q,
                                    const vec<System::dim>& r, vec<System::dim>& delta,
                                    const newton_options& opt, stage_workspace_of<System>& ws) {
    if constexpr (has_stage_solver<System>) {
        return sys.solve_stage(c, q, r, delta, opt, ws);
    } else {
        constexpr int D = System::dim;
        const auto& m = sys.mass();
        const auto& v = sys.potential();
        newton_options local = opt;
        local.typical = delta.template lpNorm<Eigen::Infinity>();
        local.reference = q.template lpNorm<Eigen::Infinity>();
        ws.x.resize(q.size());
        ws.gradient.resize(q.size());
        ws.hessian.resize(q.size(), q.size());
        return newton_solve<D>(
            delta,
            [&](const vec<D>& y, vec<D>& res, mat<D>& jac) {
                ws.x.noalias() = q + y;
                if constexpr (joint_potential<std::remove_cvref_t<decltype(v)>, D>) {
                    v.gradient_and_hessian(ws.x, ws.gradient, ws.hessian);
                } else {
                    gradient_into(v, ws.x, ws.gradient);
                    ws.hessian = v.hessian(ws.x);
                }
                if constexpr (scalar_mass<System> || D != dynamic) {
                    res.noalias() = m * y + c * ws.gradient - r;
                } else {
                    // (M y + c ∇V) − r in that order, the product into res itself (inside a
                    // sum at a run-time size Eigen would evaluate it into a temporary).
                    res.noalias() = m * y;
                    res += c * ws.gradient;
                    res -= r;
                }
                if constexpr (scalar_mass<System>) {
                    jac.noalias() = c * ws.hessian;
                    jac.diagonal().array() += m;
                } else {
                    jac.noalias() = m + c * ws.hessian;
                }
            },
            local, ws.newton);
    }
}

} // namespace varsym
