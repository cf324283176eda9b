// varsym/optimize/model.hpp: the optimal control of a model of the models layer, as one service
// that the command line (`varsym optimize`) and Python (`varsym.optimize`) both call: the
// parameters checked, the model's own limits applied, its controlled system transcribed, solved
// by IPOPT (with mesh refinement if asked), the solution unpacked and checked by varsym's own
// check (solution_check.hpp), and a verdict with one line saying what it means. The front ends
// translate their options into a request and present the outcome. See docs/optimal_control.md.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "varsym/models/model.hpp"
#include "varsym/models/robot.hpp"
#include "varsym/optimal/problem.hpp"
#include "varsym/optimal/solution_check.hpp"
#include "varsym/optimize/solve.hpp"
#include "varsym/optimize/transcription.hpp"

namespace varsym::optimal {

/// The transcription of `problem` for model m at its parameters' values and lists (m.control;
/// the problem as given: the model's limits are not applied). Throws std::invalid_argument for
/// a model without inputs or data it refuses.
std::unique_ptr<transcription> transcribe(const models::model& m, std::span<const double> values,
                                          const models::lists& lists,
                                          const control_problem& problem);

/// The Hessian choice of a word: "automatic", "exact" or "limited-memory"; std::invalid_argument
/// for another.
hessian_kind hessian_of(std::string_view word);

/// A robot's link sent to a target pose at the end (models::frame_target).
struct reach_request {
    std::shared_ptr<const multibody::tree> robot;
    std::string frame;
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    std::optional<Eigen::Matrix3d> rotation;
    double weight = 0.0; ///< 0: a constraint; > 0: a terminal cost of this weight
};

struct model_request {
    control_problem problem;
    /// The model's own bounds (a URDF robot's joint and effort limits, model::limits) where the
    /// problem leaves them unbounded.
    bool limits = true;
    std::optional<reach_request> reach;
    /// Mesh refinement levels (solve_refined); 0: one solve at problem.steps.
    int refine = 0;
    /// Threads for the steps' derivatives (dmoc_transcription::set_threads; only a URDF robot's
    /// use more than one): 0 automatic (one per CPU this process may run on), 1 none.
    int threads = 0;
    solver_options solver;
    /// Called before each refinement level is solved, with its number of steps.
    std::function<void(int)> level;
    /// Called once the problem is transcribed, just before the solve: where a front end makes
    /// its output files (so that input refused leaves none) and starts deferring signals to the
    /// solver's iterations.
    std::function<void()> ready;
    /// Called as soon as the solver returns, before the solution is unpacked and checked.
    std::function<void()> solved;
};

/// What the outcome means.
enum class verdict {
    solved,      ///< converged and passed varsym's own check
    not_solved,  ///< IPOPT did not converge (infeasible, iteration limit): the last iterate
    not_trusted, ///< converged, but varsym's check failed (equations, bounds, replay)
    time_bound,  ///< a free horizon stopped at its lower bound: the guess was too long
    interrupted, ///< stopped by the progress callback or solver_options::stop: the last iterate
};

struct model_outcome {
    nlp_result result;
    trajectory path;
    solution_check check;    ///< done where the solver converged (else its defaults)
    control_problem problem; ///< as solved: the model's limits and the reach target in it
    enum verdict verdict = verdict::not_solved;
    /// One line for a verdict other than solved: what went wrong and what to do.
    std::string message;
    double seconds = 0.0; ///< wall time of the solve(s)
    int threads = 1;      ///< the threads the steps' derivatives ran on (model_request::threads)
    /// With a reach request: the link, and how far it ends from its target.
    std::string reach_frame;
    std::optional<models::frame_miss> reach_miss;
    /// max |g| of the answer: varsym's own re-evaluation where the solver converged, else the
    /// solver's.
    [[nodiscard]] double residual() const {
        return result.converged() ? check.residual : result.constraint_violation;
    }
};

/// Solves the optimal control problem of model m at its parameters' values and lists (empty:
/// defaults). Throws std::invalid_argument for input that cannot be solved: a model without
/// inputs, a parameter only a simulation uses set away from its default, a value out of range
/// or data the model or the transcription refuses (these three name the model), an exact
/// Hessian where there is none, a bad IPOPT options file.
model_outcome optimize(const models::model& m, std::span<const double> values,
                       const models::lists& lists, model_request request);

} // namespace varsym::optimal
