// varsym/solvers/stage_equation.hpp: the one implicit equation left after reducing a step of a
// separable system, M x + c ∇V(x) = b, solved by Newton with Jacobian M + c ∇²V(x).
#pragma once

#include "varsym/solvers/newton.hpp"

namespace varsym {

/// Solves M x + c ∇V(x) = b for x = q + δ, written as  M δ + c ∇V(q + δ) = r  with r = b − M q,
/// for the increment δ (started from the guess in `delta`, whose size sets the scale of the
/// stopping test). Solving for δ rather than x keeps
/// δ's relative accuracy when |δ| ≪ |q|, which is what the update q_{j+1} = q_j + Δq needs.
/// Newmark: c = h²/4, x = q̄ the midpoint; Simpson: c = h²/24, x = q_{j+½}. See DESIGN.md §2.
template <class System>
newton_report solve_stage_increment(const System& sys, double c, const vec<System::dim>& q,
                                    const vec<System::dim>& r, vec<System::dim>& delta,
                                    const newton_options& opt) {
    constexpr int D = System::dim;
    const auto& m = sys.mass();
    const auto& v = sys.potential();
    newton_options local = opt;
    local.typical = delta.template lpNorm<Eigen::Infinity>();
    local.reference = q.template lpNorm<Eigen::Infinity>();
    return newton_solve<D>(
        delta,
        [&](const vec<D>& y, vec<D>& res, mat<D>& jac) {
            const vec<D> x = q + y;
            res.noalias() = m * y + c * v.gradient(x) - r;
            jac.noalias() = m + c * v.hessian(x);
        },
        local);
}

} // namespace varsym
