// varsym/solvers/newton.hpp: Newton's method for the small nonlinear systems of one time step.
#pragma once

#include <cmath>
#include <limits>

#include "varsym/types.hpp"

namespace varsym {

/// When Newton stops. The default asks for machine precision: the update must fall below
/// `tolerance` relative to max(|x|, typical) in the max norm. `typical` is the size the unknown
/// is expected to have (solvers set it from their starting guess when they solve for small
/// increments, so that those are resolved to their own relative precision).
struct newton_options {
    double tolerance = 2.0 * std::numeric_limits<double>::epsilon();
    int max_iterations = 25;
    double typical = 1.0;
};

/// What one Newton solve did. `iterations` counts linear solves (one per Jacobian).
struct newton_report {
    bool converged = false;
    int iterations = 0;
    double residual = 0.0; ///< max-norm residual at the last iterate that was evaluated
};

/// Solves F(x) = 0 from the starting guess in `x`. `f(x, r, J)` writes F(x) into r and the
/// Jacobian dF(x) into J. Stops when the update is at the round-off level:
///  - |δ_k| ≤ tol·scale with scale = max(|x|, typical), or
///  - the quadratic model predicts the next update below that (|δ_k|³/|δ_{k−1}|² ≤ tol·scale),
///  - or the updates stop decreasing once already tiny (round-off floor, |δ_k| ≤ 1e3·tol·scale).
/// Fails (converged = false) on NaN or infinity, or after `max_iterations` linear solves.
template <int N, class Function>
newton_report newton_solve(vec<N>& x, Function&& f, const newton_options& opt = {}) {
    vec<N> r(x.size());
    mat<N> jac(x.size(), x.size());
    newton_report rep;
    double previous = std::numeric_limits<double>::infinity();
    while (rep.iterations < opt.max_iterations) {
        f(x, r, jac);
        rep.residual = r.template lpNorm<Eigen::Infinity>();
        const vec<N> delta = solve_dense<N>(jac, r);
        ++rep.iterations;
        const double step = delta.template lpNorm<Eigen::Infinity>();
        if (!std::isfinite(step) || !std::isfinite(rep.residual)) return rep;
        x -= delta;
        const double scale =
            opt.tolerance * std::max(opt.typical, x.template lpNorm<Eigen::Infinity>());
        const bool tiny = step <= scale;
        const bool predicted = rep.iterations > 1 && step * step * step <= scale * previous * previous;
        const bool floor = rep.iterations > 1 && step <= 1e3 * scale && step >= 0.5 * previous;
        if (tiny || predicted || floor) {
            rep.converged = true;
            return rep;
        }
        previous = step;
    }
    f(x, r, jac);
    rep.residual = r.template lpNorm<Eigen::Infinity>();
    return rep;
}

} // namespace varsym
