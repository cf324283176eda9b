// varsym/solvers/newton.hpp: Newton's method for the small nonlinear systems of one time step.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "varsym/types.hpp"

namespace varsym {

/// How the family stepper (schemes/galerkin.hpp) and the general engine (schemes/variational.hpp)
/// iterate on a step's equations; every choice solves the same equations to round-off (the
/// other steppers always use Newton). In the general engine `fixed_point` is the simplified
/// iteration with the Jacobian's ∂²L/∂q̇² term alone.
enum class iteration_kind {
    automatic,   ///< the default: in the family stepper fixed_point; in the general engine
                 ///< newton, except simplified when L's
                 ///< derivatives are automatic (its Hessians cost (2d + 1)² per operation of L),
                 ///< and for a robot of about 10 joints and more (gauss-2, Simpson; the
                 ///< threshold depends on the degree) newton or articulated chosen step by
                 ///< step (schemes/variational_articulated.hpp)
    newton,      ///< exact Jacobian, evaluated and factorised at every iterate (in the general
                 ///< engine kept for chord updates once the updates are small: chord_start)
    simplified,  ///< Jacobian at one point, factorised once and kept across steps while the
                 ///< iterations contract fast (contraction_limit), refreshed at q_j when not
    fixed_point, ///< the free particle's Jacobian (1/h) A ⊗ M: no second derivatives at all
    articulated, ///< general engine, for an L that solves with its mass matrix (a robot):
                 ///< (1/h) A ⊗ M at the step's midpoint, applied by the articulated-body
                 ///< algorithm in O(n) per iterate; a step it does not converge goes to newton
};

/// Where the iteration starts.
enum class predictor_kind {
    taylor,   ///< second-order Taylor from (q_j, p_j): stateless (a robot's Newton steps in the
              ///< general engine add the jerk and the miss of the last step they continue)
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
    /// newton in the general engine (schemes/variational.hpp): once an update is below this
    /// fraction of the unknown, the next iterates keep that Jacobian (chord updates: first
    /// derivatives and a solve with the same factorisation) while they shrink at least
    /// 1/min(contraction_limit, chord_rate_limit) times. 0: a fresh Jacobian at every iterate.
    double chord_start = 1e-3;
};

/// What one Newton solve did. `iterations` counts the updates taken (one linear solve each).
struct newton_report {
    bool converged = false;
    int iterations = 0;
    double residual = 0.0; ///< max-norm residual at the last iterate that was evaluated
};

/// The largest observed rate ρ at which a chord update's linear model, ρ/(1 − ρ) |δ_k|, may stop a
/// Newton solve (newton_monitor), and so the least contraction a chord update must show to be
/// taken (the general engine's iterate, schemes/variational_solve.hpp).
inline constexpr double chord_rate_limit = 0.125;

/// Newton's stopping rule, shared by every Newton loop in varsym. After each update of
/// max-norm |δ_k| to an unknown of max-norm |x|, with scale = tol · max(|x|, typical), it
/// reports convergence when
///  - |δ_k| ≤ scale, or
///  - the quadratic model predicts the next update below scale (|δ_k|³/|δ_{k−1}|² ≤ scale; not
///    for a linearly converging iteration, `linear`, whose stop must not depend on a model;
///    for a chord update, Newton's Jacobian kept from an earlier iterate of the same solve, the
///    linear model ρ/(1 − ρ) |δ_k| ≤ scale with the observed rate ρ ≤ chord_rate_limit),
///  - or the updates stop decreasing once already tiny: the round-off floor, |δ_k| ≥ |δ_{k−1}|/2
///    with |δ_k| ≤ 64 ε max(|x|, typical, reference), whatever the tolerance asked for;
///    for Newton (not `linear`; chord updates included) also a second update in a row below
///    u = ε max(|x|, typical, reference), about an ulp of the value the unknown is an
///    increment of: the last update is below u/2, and what it leaves, ρ/(1 − ρ) |δ_k|, no more
///    at a contraction ρ ≤ ½. (A robot settled at rest has increments below an ulp of q, which
///    its residual sees through q̇ alone; Newton's updates then shrink only linearly, each to
///    0.1–0.5 of the last, down to 2ε of the increments: up to 20 iterations a step.)
class newton_monitor {
  public:
    explicit newton_monitor(const newton_options& opt, bool linear = false)
        : opt_(opt), linear_(linear) {}
    /// `chord`: the update came from a Jacobian kept from an earlier iterate (a linear
    /// iteration); its stop by model is then the linear one, ρ/(1 − ρ) |δ_k| ≤ scale with ρ the
    /// observed rate (rate(): updates at round-off do not change it; before one is measured,
    /// this update's own ratio |δ_k|/|δ_{k−1}|), taken only where ρ ≤ chord_rate_limit.
    bool converged(double step, double size, bool chord = false) {
        ++iterations_;
        const double magnitude = std::max(opt_.typical, size);
        // A ratio of updates near round-off measures the noise, not the iteration.
        if (step >
            1024.0 * std::numeric_limits<double>::epsilon() * std::max(magnitude, opt_.reference))
            rate_ = step / previous_;
        const double scale = opt_.tolerance * magnitude;
        const bool tiny = step <= scale;
        // A chord update at round-off before any rate was measured: its own ratio is all there is.
        const double rho = rate_ > 0.0 ? rate_ : step / previous_;
        const bool predicted =
            !linear_ && iterations_ > 1 &&
            (chord ? rho <= chord_rate_limit && rho * step <= (1.0 - chord_rate_limit) * scale
                   : step * step * step <= scale * previous_ * previous_);
        constexpr double eps = std::numeric_limits<double>::epsilon();
        const double ulp = eps * std::max(magnitude, opt_.reference);
        const bool floor = iterations_ > 1 && step <= 64.0 * ulp &&
                           (step >= 0.5 * previous_ || (!linear_ && previous_ <= ulp));
        previous_ = step;
        return tiny || predicted || floor;
    }
    [[nodiscard]] int iterations() const { return iterations_; }
    [[nodiscard]] bool exhausted() const { return iterations_ >= opt_.max_iterations; }
    /// |δ_k|/|δ_{k−1}| of the last update above round-off (1024 ε of the unknown's size): the
    /// observed contraction; 0 before there is one.
    [[nodiscard]] double rate() const { return iterations_ > 1 ? rate_ : 0.0; }
    /// |δ| of the last update converged() was given; infinity before the first.
    [[nodiscard]] double last_step() const { return previous_; }

  private:
    newton_options opt_;
    bool linear_ = false;
    double rate_ = 0.0;
    int iterations_ = 0;
    double previous_ = std::numeric_limits<double>::infinity();
};

/// When the general engine's Newton loops (schemes/variational_solve.hpp's iterate, the
/// constrained stepper's step, schemes/constrained.hpp) keep their Jacobian and its LU for the
/// next iterate (a chord update: first derivatives and a solve with the same factors): once an
/// update is below newton_options::chord_start of the unknown, while each chord update shrinks
/// at least 1/min(contraction_limit, chord_rate_limit) times (the rate newton_monitor's stop
/// by the linear model assumes). A chord update that does not is judged, not taken: the caller
/// drops the chord (the iterate is then Newton's, and so is the rest of the solve), or, below
/// the equations' noise, 1024 ε of the unknown or the value it is an increment of, may stop.
class chord_policy {
  public:
    /// `opt` with its typical and reference sizes set for this solve.
    explicit chord_policy(const newton_options& opt)
        : typical_(opt.typical), rate_limit_(std::min(opt.contraction_limit, chord_rate_limit)),
          noise_(1024.0 * std::numeric_limits<double>::epsilon() *
                 std::max(opt.typical, opt.reference)),
          enabled_(opt.chord_start > 0.0), fraction_(opt.chord_start) {}

    /// Whether this iterate keeps the last Jacobian.
    [[nodiscard]] bool chord() const { return chord_; }
    /// A chord update of max-norm `update`: whether it contracted as a chord update must.
    [[nodiscard]] bool contracts(double update) const { return update <= rate_limit_ * last_; }
    /// Whether `update` is below the equations' noise.
    [[nodiscard]] bool at_noise(double update) const { return update <= noise_; }
    /// No more chord updates in this solve: this iterate and the next are Newton's.
    void drop() { chord_ = enabled_ = stale_ = false; }
    /// The first iterate keeps a Jacobian taken before the solve, near a start moved from where
    /// it was taken by `last` (max-norm), the unknown then of max-norm `size`: as if that move had
    /// been an update (taken()).
    void keep(double last, double size) {
        chord_ = enabled_ && last <= fraction_ * std::max(size, typical_);
        last_ = last;
    }
    /// The first iterate keeps a Jacobian factorised before the solve at another point (an
    /// earlier step's): its update is taken where it is below chord_start of `size` (the
    /// caller's scale: of the unknown, or of what it is an increment of) or of the unknown's
    /// typical size, else the caller drops the chord (Newton's from there); it is not
    /// linearised (how far that Jacobian is off is not known); the next must contract.
    void keep_stale(double size) {
        chord_ = stale_ = enabled_;
        last_ = fraction_ * std::max(size, typical_) / rate_limit_;
    }
    /// After an update of max-norm `update` was taken and the unknown has max-norm `size`: the
    /// next iterate keeps this Jacobian once an update is below chord_start of the unknown.
    void taken(double update, double size) {
        chord_ = enabled_ && (chord_ || update <= fraction_ * std::max(size, typical_));
        stale_ = false;
        last_ = update;
    }
    /// Where the solve stops after `update` (the unknown then of size `size`): whether the
    /// momentum may come from the last iterate corrected to first order for it, what that
    /// leaves being about ρ |δ| ≤ ε of the unknown, ρ the relative error of the second
    /// derivatives used: |δ|/|X| fresh, the chord's rate |δ_k|/|δ_{k−1}| kept.
    [[nodiscard]] bool linearisable(double update, double size) const {
        if (stale_) return false; // a stale Jacobian's first update
        const double magnitude = std::max(size, typical_);
        const double rho = chord_ ? update / last_ : update / magnitude;
        return rho * update <= std::numeric_limits<double>::epsilon() * magnitude;
    }

  private:
    double typical_, rate_limit_, noise_;
    bool enabled_;
    double fraction_;
    bool chord_ = false;
    bool stale_ = false; // keep_stale()'s Jacobian, before its first update is taken
    double last_ = 0.0;  // the last update taken
};

/// The residual, Jacobian, update and LU factorisation of newton_solve's iterations: held by a
/// caller that solves again and again (a stepper), so that at a run-time size the iterations
/// allocate nothing once the first solve has sized them.
template <int N>
struct newton_workspace {
    vec<N> residual, update;
    mat<N> jacobian;
    Eigen::PartialPivLU<mat<N>> lu; ///< unused at N = 1 (a division)

    void resize(Eigen::Index n) {
        residual.resize(n);
        update.resize(n);
        jacobian.resize(n, n);
    }
    /// update = jacobian⁻¹ residual: the values of solve_dense<N>(jacobian, residual).
    void solve() {
        if constexpr (N == 1) {
            update(0) = residual(0) / jacobian(0, 0);
        } else {
            lu.compute(jacobian);
            update.noalias() = lu.solve(residual);
        }
    }
};

/// Solves F(x) = 0 from the starting guess in `x`. `f(x, r, J)` writes F(x) into r and the
/// Jacobian dF(x) into J. Stops by newton_monitor's rule; fails (converged = false) on NaN or
/// infinity, or after `max_iterations` linear solves. Its vectors and matrices are `ws`'s.
template <int N, class Function>
newton_report newton_solve(vec<N>& x, Function&& f, const newton_options& opt,
                           newton_workspace<N>& ws) {
    ws.resize(x.size());
    newton_report rep;
    newton_monitor monitor(opt);
    while (!monitor.exhausted()) {
        f(x, ws.residual, ws.jacobian);
        rep.residual = ws.residual.template lpNorm<Eigen::Infinity>();
        ws.solve();
        const double step = ws.update.template lpNorm<Eigen::Infinity>();
        rep.iterations = monitor.iterations() + 1;
        if (!std::isfinite(step) || !std::isfinite(rep.residual)) return rep;
        x -= ws.update;
        if (monitor.converged(step, x.template lpNorm<Eigen::Infinity>())) {
            rep.converged = true;
            return rep;
        }
    }
    f(x, ws.residual, ws.jacobian);
    rep.residual = ws.residual.template lpNorm<Eigen::Infinity>();
    return rep;
}

/// newton_solve with a workspace of its own (a one-off solve).
template <int N, class Function>
newton_report newton_solve(vec<N>& x, Function&& f, const newton_options& opt = {}) {
    newton_workspace<N> ws;
    return newton_solve<N>(x, std::forward<Function>(f), opt, ws);
}

} // namespace varsym
