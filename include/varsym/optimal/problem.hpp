// varsym/optimal/problem.hpp: an optimal control problem for a mechanical system with control
// inputs (the horizon, the scheme, the boundary states, the cost and the bounds), what a solver
// reports, and the optimal trajectory as the transcriptions return it. Eigen only.
// See docs/optimal_control.md.
#pragma once

#include <algorithm>
#include <cmath>
#include <concepts>
#include <functional>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "varsym/optimal/end_function.hpp"
#include "varsym/optimal/nlp.hpp"
#include "varsym/schemes/scheme_kind.hpp"
#include "varsym/systems/constraints.hpp"

namespace varsym::optimal {

/// The weights of the running cost's terms (costs.hpp): the effort ½ uᵀRu, the invariant
/// ½ τᵀM⁻¹τ and the smoothed absolute power Σ_i √((τ_i q̇_i)² + ε²), ε = power_smoothing.
struct cost_weights {
    double effort = 1.0;
    double invariant = 0.0;
    double power = 0.0;
    double power_smoothing = 1e-2; ///< ε [W]
    double time = 0.0;             ///< the weight of T itself, with a free final time
    /// The terminal cost ½ Σ_i a_i (q_i(T) − q_end,i)² + ½ Σ_i b_i (q̇_i(T) − v_end,i)², a =
    /// terminal_position, b = terminal_velocity (d each, ≥ 0; empty: 0), on the final
    /// coordinates left free (control_problem::free_end_position, free_end_velocity).
    vector terminal_position, terminal_velocity;
};

/// Take a mechanical system from (q_start, v_start) at t = 0 to (q_end, v_end) at t = time,
/// minimising the running cost ∫ c dt (by default the effort ½ uᵀ R u; cost_weights) over the
/// controls u(t) ∈ [control_lower, control_upper],
/// with the coordinates kept in [position_lower, position_upper]. Units: those of the model
/// (seconds, its coordinates' units, its inputs' units); v is q̇.
struct control_problem {
    double time = 1.0; ///< T > 0 [s] (the first guess if free_time)
    /// A free final time T ∈ [time_lower, time_upper] (minimum time: cost.time > 0); a lower
    /// bound of 0 means T/1000 of the first guess.
    bool free_time = false;
    double time_lower = 0.0, time_upper = unbounded;
    int steps = 50;                            ///< N ≥ 1 steps of h = T/N
    scheme_spec scheme = scheme_kind::simpson; ///< the discrete Lagrangian
    vector q_start, v_start, q_end, v_end;     ///< boundary states (d each)
    cost_weights cost;                         ///< the running cost's terms
    Eigen::MatrixXd effort;                    ///< R (m × m, s.p.d.); empty: identity
    vector control_lower, control_upper;       ///< (m each, or 1 for all); empty: unbounded
    vector position_lower, position_upper;     ///< (d each, or 1 for all); empty: unbounded
    /// Bounds on q̇ (d each, or 1 for all; empty: unbounded): on the velocities at the nodes
    /// (unknowns of the transcription) and on each step's polynomial at its interior quadrature
    /// points; with holonomic constraints on the polynomials at the steps' ends instead of the
    /// nodes. The boundary velocities must lie within them.
    vector velocity_lower, velocity_upper;
    /// Free final state: entry i true leaves q_i(T) (q̇_i(T)) free instead of fixing it to
    /// q_end(i) (v_end(i)), which is then the terminal cost's target (d each; empty: all fixed).
    std::vector<bool> free_end_position, free_end_velocity;
    /// A target at T for a function of the final position, φ(q(T)) = 0 (end_function.hpp: a
    /// robot frame's pose error, models::frame_target); it frees every final position (within
    /// the position bounds), and q_end is then only the first guess of q(T). Empty: none.
    std::shared_ptr<const end_function> end_target;
    /// 0: φ(q(T)) = 0 is a constraint; w > 0: the terminal cost ½ w |φ(q(T))|² instead.
    double end_target_weight = 0.0;
    [[nodiscard]] bool free_end() const {
        return std::ranges::find(free_end_position, true) != free_end_position.end() ||
               std::ranges::find(free_end_velocity, true) != free_end_velocity.end();
    }
};

/// A solver's verdict, by IPOPT's return codes in words.
enum class status {
    solved,          ///< converged to the tolerance
    acceptable,      ///< converged to IPOPT's looser "acceptable" tolerance
    infeasible,      ///< locally infeasible: no trajectory meets the constraints nearby
    iteration_limit, ///< stopped at the iteration limit
    interrupted,     ///< stopped by the caller (Ctrl-C, a progress callback)
    failed           ///< anything else (restoration failed, NaN, …): see message
};

inline const char* status_name(status s) {
    switch (s) {
    case status::solved:
        return "solved";
    case status::acceptable:
        return "acceptable";
    case status::infeasible:
        return "infeasible";
    case status::iteration_limit:
        return "iteration_limit";
    case status::interrupted:
        return "interrupted";
    case status::failed:
        return "failed";
    }
    return "failed";
}

/// What a solver returns: the last iterate x (the solution if converged), the multipliers λ of
/// the equations g(x) = 0 (sign: the Lagrangian is f + λᵀg), the cost and the iteration count.
struct nlp_result {
    status verdict = status::failed;
    std::string message;
    int iterations = 0;
    double cost = 0.0;
    double constraint_violation = 0.0;
    vector x, lambda;
    [[nodiscard]] bool converged() const {
        return verdict == status::solved || verdict == status::acceptable;
    }
};

/// The optimal motion: nodes t_n = n h (n = 0 … N) with positions, momenta p_n (the discrete
/// Legendre transform of the step's equations) and velocities; the control values of every
/// step at its quadrature points; the costates λ_p ≈ the continuous adjoint of the momenta at
/// the nodes; all control values of the steps' polynomials (dense output: position()).
struct trajectory {
    scheme_spec scheme;
    double h = 0.0;
    int degree = 1;
    vector node_times;                 ///< N + 1
    Eigen::MatrixXd q, p, v;           ///< d × (N + 1)
    Eigen::MatrixXd costate;           ///< d × (N + 1): λ_p at the nodes
    vector control_times;              ///< N r: (k + c_j) h
    Eigen::MatrixXd u;                 ///< m × N r
    Eigen::MatrixXd points;            ///< d × (N s + 1): control values Q at t = (k + d_i) h
    std::vector<double> control_nodes; ///< d_0 … d_s on [0, 1]
    double cost = 0.0;

    /// q(t) on the step's polynomial of degree s through its control values.
    [[nodiscard]] vector position(double t) const {
        const auto steps = static_cast<double>(node_times.size() - 1);
        const double x = std::clamp(t / h, 0.0, steps);
        const int k = std::min(static_cast<int>(x), static_cast<int>(steps) - 1);
        const double tau = x - k;
        vector out = vector::Zero(points.rows());
        for (int i = 0; i <= degree; ++i) {
            double value = 1.0;
            for (int m = 0; m <= degree; ++m)
                if (m != i)
                    value *= (tau - control_nodes[static_cast<std::size_t>(m)]) /
                             (control_nodes[static_cast<std::size_t>(i)] -
                              control_nodes[static_cast<std::size_t>(m)]);
            out += value * points.col(k * degree + i);
        }
        return out;
    }
};

/// No holonomic constraints (a transcription's default).
struct unconstrained {};
template <class C>
inline constexpr int constraint_rows = 0;
template <class C>
requires(!std::same_as<C, unconstrained>) inline constexpr int constraint_rows<C> = C::count;
/// C is `unconstrained`, or holonomic constraints on d coordinates.
template <class C, int D>
inline constexpr bool constraints_on = std::same_as<C, unconstrained>;
template <class C, int D>
requires(!std::same_as<C, unconstrained>) inline constexpr bool constraints_on<C, D> =
    holonomic_constraint<C> && C::dim == D;

/// A transcription whose system is known at run time only (the models layer's): the NLP, the
/// trajectory of a result and its closure check.
class transcription : public nlp {
  public:
    [[nodiscard]] virtual const control_problem& problem() const = 0;
    [[nodiscard]] virtual trajectory unpack(const nlp_result& result) const = 0;
    /// A starting point from another trajectory (a coarser solution: mesh refinement).
    [[nodiscard]] virtual vector start_from(const trajectory& guess) const = 0;
    /// A starting point along a guessed path q(t), t ∈ [0, T], the controls zero.
    [[nodiscard]] virtual vector start_along(const std::function<vector(double)>& q) const = 0;
    /// The general engine's nodes under the trajectory's controls (replay.hpp): 2d × (N + 1).
    [[nodiscard]] virtual Eigen::MatrixXd replay(const trajectory& path) const = 0;
    /// Whether the system is a multibody model (controlled_system::multibody).
    [[nodiscard]] virtual bool multibody() const { return false; }
};

/// The closure check of a solution: the largest difference in q between its nodes and the
/// general engine's replay of its controls (transcription::replay), or why the replay failed.
/// Measured on sound solutions: 1e-15 to 2e-10. A larger one means the optimum rides on a root
/// of some step's equations that the simulator, from its own predictor, does not reach: steps
/// too coarse for the motion (h |q̇| of order 1), where the discrete equations have spurious
/// roots an optimizer can exploit (an acrobot swing-up at N = 40 refined from N = 20 "costs"
/// 4.35 instead of 35.2 that way, and the replay ends 4.75 rad away). Take more steps.
inline constexpr double closure_tolerance = 1e-6;
struct closure_check {
    double error = std::numeric_limits<double>::quiet_NaN();
    std::string failure; ///< why the replay failed, or empty
    [[nodiscard]] bool ok() const { return failure.empty() && error <= closure_tolerance; }
    /// One line for a message: what was found and what to do.
    [[nodiscard]] std::string advice() const {
        return (failure.empty()
                    ? "the simulator's replay of the optimal controls ends " +
                          std::to_string(error) + " away from the optimal motion"
                    : "the simulator could not replay the optimal controls (" + failure + ")") +
               ": the steps are too coarse for this motion; take more --steps";
    }
};
inline closure_check check_closure(const transcription& t, const trajectory& path) {
    closure_check c;
    try {
        c.error = (t.replay(path).topRows(path.q.rows()) - path.q).cwiseAbs().maxCoeff();
    } catch (const std::exception& e) {
        c.failure = e.what();
    }
    return c;
}

namespace detail {

inline void require(bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument(what);
}

inline bool finite(const Eigen::MatrixXd& m) {
    return m.allFinite();
}

/// Checks p against a system of dimension d with m inputs; fills the defaults (R = I, no
/// bounds). Every message names the field and what to do.
inline control_problem checked(control_problem p, int d, int m) {
    require(std::isfinite(p.time) && p.time > 0.0,
            "the time horizon must be positive and finite, got " + std::to_string(p.time));
    require(p.steps >= 1, "the number of steps must be at least 1, got " + std::to_string(p.steps));
    const auto dim = [&](const vector& x, const char* name) {
        require(x.size() == d, std::string(name) + " has " + std::to_string(x.size()) +
                                   " entries; the model has " + std::to_string(d) + " coordinates");
        require(x.allFinite(), std::string(name) + " must be finite (NaN or inf given)");
    };
    dim(p.q_start, "the start position");
    dim(p.v_start, "the start velocity");
    dim(p.q_end, "the end position");
    dim(p.v_end, "the end velocity");
    require(m >= 1, "the model has no control input: nothing to optimise");
    const auto flags = [&](std::vector<bool>& f, const char* name) {
        if (f.empty()) f.assign(static_cast<std::size_t>(d), false);
        require(f.size() == static_cast<std::size_t>(d),
                std::string(name) + " has " + std::to_string(f.size()) + " flags; the model has " +
                    std::to_string(d) + " coordinates");
    };
    flags(p.free_end_position, "the free final positions");
    if (p.end_target) {
        require(p.end_target->dimension() == d && p.end_target->rows() >= 1,
                "the end target takes " + std::to_string(p.end_target->dimension()) +
                    " coordinates; the model has " + std::to_string(d));
        require(std::isfinite(p.end_target_weight) && p.end_target_weight >= 0.0,
                "the end target's weight must be finite and >= 0 (0: a constraint)");
        p.free_end_position.assign(static_cast<std::size_t>(d), true);
    }
    flags(p.free_end_velocity, "the free final velocities");
    cost_weights& w = p.cost;
    const auto terminal = [&](vector& a, const char* name) {
        if (a.size() == 0) a = vector::Zero(d);
        require(a.size() == d, std::string(name) + " weights need " + std::to_string(d) +
                                   " entries, one per coordinate");
        require(a.allFinite() && (a.array() >= 0.0).all(),
                std::string(name) + " weights must be finite and >= 0");
    };
    terminal(w.terminal_position, "the terminal position");
    terminal(w.terminal_velocity, "the terminal velocity");
    for (std::size_t i = 0; i < static_cast<std::size_t>(d); ++i) {
        const auto at = static_cast<Eigen::Index>(i);
        require((w.terminal_position(at) == 0.0 || p.free_end_position[i]) &&
                    (w.terminal_velocity(at) == 0.0 || p.free_end_velocity[i]),
                "a terminal cost on a fixed final coordinate: free it (free_end_position, "
                "free_end_velocity) or drop its weight");
    }
    for (const double x : {w.effort, w.invariant, w.power, w.time})
        require(std::isfinite(x) && x >= 0.0, "the cost weights must be finite and >= 0");
    require(w.effort + w.invariant + w.power + w.time + w.terminal_position.sum() +
                    w.terminal_velocity.sum() + (p.end_target ? p.end_target_weight : 0.0) >
                0.0,
            "the cost is zero: give the effort, invariant, power, time or terminal term a "
            "positive weight");
    require(w.time == 0.0 || p.free_time, "a cost on the time needs a free final time");
    if (p.free_time) {
        if (p.time_lower <= 0.0) p.time_lower = 1e-3 * p.time;
        require(!std::isnan(p.time_upper) && p.time_lower < p.time_upper &&
                    p.time >= p.time_lower && p.time <= p.time_upper,
                "the free final time's bounds must hold its first guess: time_lower <= time <= "
                "time_upper");
    }
    require(std::isfinite(w.power_smoothing) && w.power_smoothing > 0.0,
            "the power's smoothing must be positive");
    if (p.effort.size() == 0) p.effort = Eigen::MatrixXd::Identity(m, m);
    require(p.effort.rows() == m && p.effort.cols() == m,
            "the effort weight R must be " + std::to_string(m) + " x " + std::to_string(m));
    require(finite(p.effort) && p.effort.isApprox(p.effort.transpose()) &&
                p.effort.llt().info() == Eigen::Success,
            "the effort weight R must be symmetric positive definite");
    const auto box = [&](vector& lo, vector& hi, Eigen::Index n, const char* name) {
        if (lo.size() == 0) lo = vector::Constant(n, -unbounded);
        if (hi.size() == 0) hi = vector::Constant(n, unbounded);
        if (lo.size() == 1) lo = vector::Constant(n, lo(0)); // one bound for every entry
        if (hi.size() == 1) hi = vector::Constant(n, hi(0));
        require(lo.size() == n && hi.size() == n,
                std::string(name) + " bounds need " + std::to_string(n) + " entries each");
        for (Eigen::Index i = 0; i < n; ++i)
            require(!std::isnan(lo(i)) && !std::isnan(hi(i)) && lo(i) <= hi(i),
                    std::string(name) + " bounds are empty or NaN at entry " + std::to_string(i) +
                        ": lower must not exceed upper");
    };
    box(p.control_lower, p.control_upper, m, "control");
    box(p.position_lower, p.position_upper, d, "position");
    box(p.velocity_lower, p.velocity_upper, d, "velocity");
    for (Eigen::Index i = 0; i < d; ++i)
        for (const vector* v : {&p.v_start, &p.v_end})
            require((v == &p.v_end && p.free_end_velocity[static_cast<std::size_t>(i)]) ||
                        ((*v)(i) >= p.velocity_lower(i) && (*v)(i) <= p.velocity_upper(i)),
                    "a boundary velocity lies outside the velocity bounds");
    for (Eigen::Index i = 0; i < d; ++i)
        for (const vector* q : {&p.q_start, &p.q_end})
            require((q == &p.q_end && p.free_end_position[static_cast<std::size_t>(i)]) ||
                        ((*q)(i) >= p.position_lower(i) && (*q)(i) <= p.position_upper(i)),
                    "a boundary position lies outside the position bounds");
    return p;
}

} // namespace detail

} // namespace varsym::optimal
