// varsym/optimal/solution_check.hpp: varsym's own check of a solver's answer, independent of
// what the solver reports: the equations g(x) = 0 re-evaluated, the bounds on x, every boundary
// value of the trajectory (the start and end positions and velocities, the velocities through
// the inverse Legendre transform of the boundary momenta), and the closure (the general engine's
// replay of the controls). A solver told to loosen its tolerances (an options file) can say
// "solved" of a point that meets none of these; this check does not read its verdict.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "varsym/optimal/problem.hpp"

namespace varsym::optimal {

/// The largest relative miss a solution may have in its equations (max |g| over 1 + max |p|),
/// its bounds and its boundary values (over 1 + |the value|). IPOPT's own tolerance on |g| is
/// 1e-12 (solver_options::constraint_tolerance); sound solutions measure 1e-16 to 1e-12, and
/// an "acceptable" one (IPOPT's looser level, up to 1e-2) is refused above this.
inline constexpr double solution_tolerance = 1e-8;

struct solution_check {
    double residual = std::numeric_limits<double>::quiet_NaN(); ///< max |g(x)|, re-evaluated
    double residual_scale = 1.0;                                ///< 1 + max |p| on the nodes
    double bounds = 0.0;        ///< the largest relative excursion of x beyond its bounds
    double boundary = 0.0;      ///< the largest relative miss of a fixed boundary value
    std::string boundary_entry; ///< which one, e.g. "v2(T)"
    /// Active bounds: control values (of path.u's m × N r) and node positions (of d × (N + 1))
    /// on a finite bound, to 1e-9 relative. A saturated optimum (bang-bang) is no error, but
    /// the user should know the answer is the bound's.
    int controls_at_bound = 0, positions_at_bound = 0;
    /// How far the node velocities (from the momenta: trajectory::v) exceed the velocity bounds,
    /// relative to the bound (0: within, to round-off, where they are unknowns of their own;
    /// with holonomic constraints the bounds hold on the steps' polynomials and the nodes'
    /// velocities approach them as the steps shrink). Reported, not refused.
    double velocity_excess = 0.0;
    closure_check closure;

    [[nodiscard]] bool equations_ok() const {
        return residual <= solution_tolerance * residual_scale;
    }
    [[nodiscard]] bool ok() const {
        return equations_ok() && bounds <= solution_tolerance && boundary <= solution_tolerance &&
               closure.ok();
    }
    /// One line for a message: the first check that failed, and what to do.
    [[nodiscard]] std::string advice() const {
        if (!equations_ok())
            return "the discrete equations are not met: max |g| = " + std::to_string(residual) +
                   " (solver options too loose, or the solver's answer is wrong)";
        if (bounds > solution_tolerance)
            return "the solution leaves its bounds by " + std::to_string(bounds) + " (relative)";
        if (boundary > solution_tolerance)
            return "the solution misses the boundary value " + boundary_entry + " by " +
                   std::to_string(boundary) + " (relative)";
        return closure.advice();
    }
};

/// Checks `result` (the solver's x) and its trajectory `path` against transcription `t`'s
/// problem; closure by check_closure.
inline solution_check check_solution(const transcription& t, const nlp_result& result,
                                     const trajectory& path) {
    solution_check c;
    if (result.x.size() != t.variables()) {
        c.closure.failure = "no iterate";
        return c;
    }
    const vector g = t.constraint_violation(result.x); // beyond the rows' bounds
    c.residual = g.size() ? g.cwiseAbs().maxCoeff() : 0.0;
    if (!g.allFinite()) c.residual = std::numeric_limits<double>::infinity();
    c.residual_scale = 1.0 + (path.p.size() ? path.p.cwiseAbs().maxCoeff() : 0.0);
    vector lower, upper;
    t.bounds(lower, upper);
    for (Eigen::Index i = 0; i < result.x.size(); ++i) {
        const double x = result.x(i);
        const double out = std::max(lower(i) - x, x - upper(i));
        if (out > 0.0) c.bounds = std::max(c.bounds, out / (1.0 + std::min(std::abs(x), 1e300)));
    }
    const control_problem& p = t.problem();
    const auto last = path.q.cols() - 1;
    const auto miss = [&](double value, double target, const std::string& name) {
        const double r = std::abs(value - target) / (1.0 + std::abs(target));
        if (!(r <= c.boundary)) { // NaN counts as a miss
            c.boundary = std::isnan(r) ? std::numeric_limits<double>::infinity() : r;
            c.boundary_entry = name;
        }
    };
    for (Eigen::Index i = 0; i < path.q.rows(); ++i) {
        const auto at = static_cast<std::size_t>(i);
        const std::string k = std::to_string(i + 1);
        miss(path.q(i, 0), p.q_start(i), "q" + k + "(0)");
        miss(path.v(i, 0), p.v_start(i), "v" + k + "(0)");
        if (p.free_end_position.empty() || !p.free_end_position[at])
            miss(path.q(i, last), p.q_end(i), "q" + k + "(T)");
        if (p.free_end_velocity.empty() || !p.free_end_velocity[at])
            miss(path.v(i, last), p.v_end(i), "v" + k + "(T)");
    }
    const auto on = [](double x, double lo, double hi) {
        const auto at = [x](double b) {
            return std::isfinite(b) && std::abs(x - b) <= 1e-9 * (1.0 + std::abs(b));
        };
        return at(lo) || at(hi);
    };
    const auto entry = [](const vector& b, Eigen::Index i) {
        return b.size() == 0 ? unbounded : b(b.size() == 1 ? 0 : i);
    };
    for (Eigen::Index j = 0; j < path.u.cols(); ++j)
        for (Eigen::Index i = 0; i < path.u.rows(); ++i)
            c.controls_at_bound +=
                on(path.u(i, j), entry(p.control_lower, i), entry(p.control_upper, i));
    for (Eigen::Index j = 0; j < path.q.cols(); ++j)
        for (Eigen::Index i = 0; i < path.q.rows(); ++i)
            c.positions_at_bound +=
                on(path.q(i, j), entry(p.position_lower, i), entry(p.position_upper, i));
    for (Eigen::Index j = 0; j < path.v.cols(); ++j)
        for (Eigen::Index i = 0; i < path.v.rows(); ++i) {
            const double v = path.v(i, j), hi = entry(p.velocity_upper, i),
                         lo = entry(p.velocity_lower, i); // +inf where there are none
            if (std::isfinite(hi) && v > hi)
                c.velocity_excess =
                    std::max(c.velocity_excess, (v - hi) / std::max(std::abs(hi), 1e-9));
            if (std::isfinite(lo) && v < lo)
                c.velocity_excess =
                    std::max(c.velocity_excess, (lo - v) / std::max(std::abs(lo), 1e-9));
        }
    c.closure = check_closure(t, path);
    return c;
}

} // namespace varsym::optimal
