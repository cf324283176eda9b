// varsym/models/simulation.hpp: a simulation, the type-erased stepper of the models layer. It
// owns one model's system, a stepper of the chosen scheme and the run's state, and offers what
// every front end needs from any model: stepping with an observer that may stop the run, the
// state and the model's named columns at each step, the energy the watch follows, saving and
// restoring the run state bit for bit, the tangent map, one ensemble member and Poincaré
// crossings. The stepping loop runs inside the compiled model (one indirect call per step for
// the observer), so a simulation steps as fast as the template it erases.
#pragma once

#include <atomic>
#include <cstddef>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "varsym/integrate.hpp"
#include "varsym/run/ensemble.hpp"
#include "varsym/run/section.hpp"
#include "varsym/run/state.hpp"
#include "varsym/schemes/scheme_kind.hpp"

namespace varsym::models {

/// How a simulation steps: the scheme, Newton's options and the step size h.
struct step_options {
    scheme_spec spec;
    newton_options newton;
    double h = 0.0;
};

/// The integrator of a model that has its own rather than the scheme of step_options (the rigid
/// bodies' Lie group integrator of order 2, 4 or 6); an empty label: the scheme's.
struct own_integrator {
    std::string label;       ///< as messages and checkpoints name it: "lgvi-4"
    int order = 0;           ///< its order of accuracy
    double step_limit = 0.0; ///< the largest h·ω its steps are defined at (a guide, for advice)
};

/// The crossings of a Poincaré section by one orbit.
struct section_result {
    std::vector<double> time;   ///< the crossings' times
    std::vector<double> states; ///< their states, (q_1..q_d, p_1..p_d) one crossing after another
    bool failed = false;        ///< a step failed before the requested crossings were found
    bool stopped = false;       ///< the caller's stop flag ended it (the crossings so far)
};

/// How many crossings simulation::section holds before it hands them to its `drain`.
inline constexpr std::size_t section_drain_size = 4096;

/// A model's system stepped by one scheme from one initial state.
class simulation {
  public:
    virtual ~simulation() = default;

    /// The number of coordinates d.
    [[nodiscard]] virtual int dim() const = 0;
    [[nodiscard]] virtual double step_size() const = 0;
    /// The index j of the current state (0 at the start) and its time t_j = t0 + j h.
    [[nodiscard]] virtual std::size_t step() const = 0;
    [[nodiscard]] virtual double time() const = 0;
    /// The current state (q_j, p_j): d values each, in the coordinates the model's start takes
    /// (a rigid body: its z-x-z Euler angles θ, φ, ψ and its body angular momentum Π).
    [[nodiscard]] virtual std::span<const double> q() const = 0;
    [[nodiscard]] virtual std::span<const double> p() const = 0;
    /// The state as a row shows it: the names ("q_1".."q_d", "p_1".."p_d"; "q", "p" where
    /// d = 1; a rigid body: its attitude quaternion q_w..q_z and body angular velocity
    /// Omega_1..Omega_3) and the current values, written to `out` from its start.
    [[nodiscard]] virtual std::vector<std::string> state_columns() const;
    virtual void state_values(std::span<double> out) const;
    /// A robot in contact: the last step's pressing contacts, six numbers each in the world
    /// frame, the contact point [m] and the impulse on the robot [N s] (its force times h).
    /// Empty otherwise.
    [[nodiscard]] virtual std::span<const double> contact_impulses() const { return {}; }
    /// The model's own columns (energy, conserved quantities, exact solution) and their values at
    /// the current state: as many as columns() names, written to `out` from its start.
    [[nodiscard]] virtual const std::vector<std::string>& columns() const = 0;
    virtual void values(std::span<double> out) const = 0;
    /// The energy the watch follows at the current state: E, or E − W with forces (W the work of
    /// the forces since the start), constant up to the scheme's error when energy is conserved.
    [[nodiscard]] virtual double watched_energy() const = 0;
    /// Whether E (or E − W) is conserved: false for a Lagrangian that depends on time and does
    /// not give ∂L/∂t (a typed L does: W then holds −∫∂L/∂t dt).
    [[nodiscard]] virtual bool conserves_energy() const = 0;
    /// The highest frequency of the linearized motion at the current state [rad per time unit],
    /// or NaN where it cannot be estimated.
    [[nodiscard]] virtual double highest_frequency() const = 0;
    /// The statistics of Newton's method over the steps taken.
    [[nodiscard]] virtual const run_summary& stats() const = 0;

    /// Steps until step() == n, calling after_step() after each step; after_step may return
    /// true to stop the run early. Returns true when step n was reached. Throws step_failure if
    /// a step does not converge, the state then being the last good one.
    virtual bool advance(std::size_t n, const std::function<bool()>& after_step) = 0;
    /// Steps to n without an observer.
    bool advance(std::size_t n) {
        return advance(n, [] { return false; });
    }

    /// The run state (state, compensated-summation carries, history, step, statistics), to
    /// save; restore() puts a saved one back, after which the steps continue bit for bit.
    [[nodiscard]] virtual run_state<dynamic> save() const = 0;
    virtual void restore(const run_state<dynamic>& saved) = 0;

    /// Whether the stepper has a tangent map, which tangent_map() and the chaos indicators of
    /// run_member() need (the rigid bodies' Lie group integrator has none).
    [[nodiscard]] virtual bool has_tangent_map() const { return true; }
    /// The 2d × 2d tangent map ∂(q_{j+1}, p_{j+1})/∂(q_j, p_j) of the step from the current
    /// state (the state is not changed); throws std::logic_error where !has_tangent_map().
    virtual void tangent_map(Eigen::MatrixXd& jacobian) = 0;
    /// One ensemble member from the current state: `plan.steps` steps with the chaos
    /// indicators and the event `event(t, q, p)` (a change of its sign stops the member; null:
    /// none). Without a tangent map λ and MEGNO are NaN. The simulation's own state is not
    /// changed.
    [[nodiscard]] virtual member_result run_member(
        const member_plan& plan,
        const std::function<double(double, std::span<const double>, std::span<const double>)>&
            event) = 0;
    /// Whether the stepper has dense output, which section() needs.
    [[nodiscard]] virtual bool has_dense_output() const = 0;
    /// The crossings of `plane` over `steps` steps from the current state, at most `crossings`
    /// of them; throws std::logic_error where !has_dense_output(). The state is not changed.
    /// `stop`, when given and set (another thread, a signal handler), ends it after the
    /// current step (section_result::stopped). With `drain`, the crossings are handed to it
    /// every section_drain_size of them and the result keeps only the rest: memory stays
    /// bounded however many crossings there are (`varsym section` streams them to its file).
    [[nodiscard]] virtual section_result
    section(const section_plane& plane, long long steps, long long crossings,
            const std::atomic<bool>* stop,
            const std::function<void(const section_result&)>& drain = {}) = 0;
};

/// Runs f(), an evaluation of the model at the simulation's current state (its row's values,
/// its energy). An exception from it becomes the step_failure of the step after this state,
/// naming the cause, so that every front end handles it as a failed step: the rows so far
/// kept, and the current state (the last one the steps reached) saved as the last good one.
template <class F>
decltype(auto) evaluated(const simulation& sim, F&& f) {
    try {
        return f();
    } catch (const step_failure&) {
        throw;
    } catch (const std::exception& e) {
        const double t = sim.time();
        throw step_failure::other(sim.step() + 1, t, t + sim.step_size(),
                                  "the model cannot be evaluated at the state of step " +
                                      std::to_string(sim.step()) + ": " + e.what());
    }
}

} // namespace varsym::models
