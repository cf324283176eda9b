// varsym/solvers/stage_equation.hpp: the one implicit equation left after reducing a step of a
// separable system, M x + c ∇V(x) = b, solved by Newton with Jacobian M + c ∇²V(x).
#pragma once

#include "varsym/solvers/newton.hpp"

namespace varsym {

/// Solves M x + c ∇V(x) = b for x, starting from the guess in `x`.
/// Newmark: c = h²/4 (x = q̄, the midpoint); Simpson: c = h²/24 (x = q_{j+½}). See DESIGN.md §2.
template <class System>
newton_report solve_stage_equation(const System& sys, double c, const vec<System::dim>& b,
                                   vec<System::dim>& x, const newton_options& opt) {
    constexpr int D = System::dim;
    const auto& m = sys.mass();
    const auto& v = sys.potential();
    return newton_solve<D>(
        x,
        [&](const vec<D>& y, vec<D>& r, mat<D>& jac) {
            r.noalias() = m * y + c * v.gradient(y) - b;
            jac.noalias() = m + c * v.hessian(y);
        },
        opt);
}

} // namespace varsym
