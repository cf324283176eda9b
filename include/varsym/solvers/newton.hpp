// varsym/solvers/newton.hpp: Newton's method for the small nonlinear systems of one time step.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "varsym/types.hpp"

namespace varsym {

/// How the family stepper (schemes/galerkin.hpp) and the general engine (schemes/variational.hpp)
/// iterate on a step's equations; every choice solves the same equations to round-off (the
/// other steppers always use Newton). In the general engine `fixed_point` is the simplified
/// iteration with the Jacobian's ∂²L/∂q̇² term alone.
enum class iteration_kind {
    automatic,   ///< the default: in the family stepper fixed_point; in the general engine
                 ///< newton, except simplified when L's
                 ///< derivatives are automatic (its Hessians cost (2d + 1)² per operation of L)
    newton,      ///< exact Jacobian, evaluated and factorised at every iterate
    simplified,  ///< Jacobian at one point, factorised once and kept across steps while the
                 ///< iterations contract fast (contraction_limit), refreshed at q_j when not
    fixed_point, ///< the free particle's Jacobian (1/h) A ⊗ M: no second derivatives at all
};

/// Where the iteration starts.
enum class predictor_kind {
    taylor,   ///< second-order Taylor from (q_j, p_j): stateless
    previous, ///< the previous step's polynomial extrapolated: O(h^(s+1)), but state a resumed
              ///< run must restore (run_state::history); family stepper only
    forces,   ///< the previous step's forces at its quadrature points extrapolated to this
              ///< step's (HLW §VIII.6.1), then the step's equations in closed form: two orders
              ///< beyond `previous` at no extra evaluation; state as `previous`; family only
};

/// When Newton stops. The default asks for machine precision: the update must fall below
/// `tolerance` relative to max(|x|, typical) in the max norm. `typical` is the size the unknown
/// is expected to have (solvers set it from their starting guess when they solve for small
/// increments, so that those are resolved to their own relative precision).
struct newton_options {
    double tolerance = 2.0 * std::numeric_limits<double>::epsilon();
    int max_iterations = 25;
    double typical = 1.0;
    /// Size of the value the unknown is an increment of (|q_j| when solving for q − q_j), or 0.
    /// Updates that stall below round-off of that value cannot matter once it is added.
    double reference = 0.0;
    iteration_kind iteration = iteration_kind::automatic;
    predictor_kind predictor = predictor_kind::taylor;
    /// simplified: the kept Jacobian is refreshed when an iteration's update shrinks by less
    /// than this factor (the observed contraction rate).
    double contraction_limit = 0.125;
};

/// What one Newton solve did. `iterations` counts linear solves (one per Jacobian).
struct newton_report {
    bool converged = false;
    int iterations = 0;
    double residual = 0.0; ///< max-norm residual at the last iterate that was evaluated
};

/// Newton's stopping rule, shared by every Newton loop in varsym. After each update of
/// max-norm |δ_k| to an unknown of max-norm |x|, with scale = tol · max(|x|, typical), it
/// reports convergence when
///  - |δ_k| ≤ scale, or
///  - the quadratic model predicts the next update below scale (|δ_k|³/|δ_{k−1}|² ≤ scale; not
///    for a linearly converging iteration, `linear`, whose stop must not depend on a model),
///  - or the updates stop decreasing once already tiny: the round-off floor, |δ_k| ≥ |δ_{k−1}|/2
///    with |δ_k| ≤ 64 ε max(|x|, typical, reference), whatever the tolerance asked for.
class newton_monitor {
  public:
    explicit newton_monitor(const newton_options& opt, bool linear = false)
        : opt_(opt), linear_(linear) {}
    bool converged(double step, double size) {
        ++iterations_;
        const double magnitude = std::max(opt_.typical, size);
        // A ratio of updates near round-off measures the noise, not the iteration.
        if (step >
            1024.0 * std::numeric_limits<double>::epsilon() * std::max(magnitude, opt_.reference))
            rate_ = step / previous_;
        const double scale = opt_.tolerance * magnitude;
        const bool tiny = step <= scale;
        const bool predicted =
            !linear_ && iterations_ > 1 && step * step * step <= scale * previous_ * previous_;
        const bool floor = iterations_ > 1 && step >= 0.5 * previous_ &&
                           step <= 64.0 * std::numeric_limits<double>::epsilon() *
                                       std::max(magnitude, opt_.reference);
        previous_ = step;
        return tiny || predicted || floor;
    }
    [[nodiscard]] int iterations() const { return iterations_; }
    [[nodiscard]] bool exhausted() const { return iterations_ >= opt_.max_iterations; }
    /// |δ_k|/|δ_{k−1}| of the last update above round-off (1024 ε of the unknown's size): the
    /// observed contraction; 0 before there is one.
    [[nodiscard]] double rate() const { return iterations_ > 1 ? rate_ : 0.0; }

  private:
    newton_options opt_;
    bool linear_ = false;
    double rate_ = 0.0;
    int iterations_ = 0;
    double previous_ = std::numeric_limits<double>::infinity();
};

/// Solves F(x) = 0 from the starting guess in `x`. `f(x, r, J)` writes F(x) into r and the
/// Jacobian dF(x) into J. Stops by newton_monitor's rule; fails (converged = false) on NaN or
/// infinity, or after `max_iterations` linear solves.
template <int N, class Function>
newton_report newton_solve(vec<N>& x, Function&& f, const newton_options& opt = {}) {
    vec<N> r(x.size());
    mat<N> jac(x.size(), x.size());
    newton_report rep;
    newton_monitor monitor(opt);
    while (!monitor.exhausted()) {
        f(x, r, jac);
        rep.residual = r.template lpNorm<Eigen::Infinity>();
        const vec<N> delta = solve_dense<N>(jac, r);
        const double step = delta.template lpNorm<Eigen::Infinity>();
        rep.iterations = monitor.iterations() + 1;
        if (!std::isfinite(step) || !std::isfinite(rep.residual)) return rep;
        x -= delta;
        if (monitor.converged(step, x.template lpNorm<Eigen::Infinity>())) {
            rep.converged = true;
            return rep;
        }
    }
    f(x, r, jac);
    rep.residual = r.template lpNorm<Eigen::Infinity>();
    return rep;
}

} // namespace varsym
