// varsym/integrate.hpp: the driver that runs a stepper for n steps, calls an observer after
// each, keeps Newton statistics, and turns a failed step into an error that says where.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <exception>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include "varsym/solvers/newton.hpp"
#include "varsym/stepper.hpp"
#include "varsym/systems/separable_failure.hpp"
#include "varsym/types.hpp"

namespace varsym {

/// Thrown when a step fails: its Newton iteration does not converge, or (other()) anything else
/// goes wrong in it, such as an exception from the model (a singular mass matrix, a force that
/// cannot be evaluated). The state passed to integrate() is left at the last good step (index
/// step − 1, time t_from). `cause`, where the stepper could name one (its diagnose(): NaN from
/// the Lagrangian, a force or a constraint, a singular mass matrix or constraint Jacobian; for
/// the separable steppers, NaN from the potential: systems/separable_failure.hpp), follows the
/// residual in the message.
class step_failure : public std::runtime_error {
  public:
    step_failure(std::size_t step, double t_from, double t_to, const newton_report& rep,
                 std::string cause = {})
        : std::runtime_error(describe(step, t_from, t_to, rep, cause) +
                             (cause.empty() ? "; use a smaller time step" : "")),
          step_(step), time_(t_from), time_to_(t_to), report_(rep), cause_(std::move(cause)) {}
    /// A step that failed for another reason than Newton's: `cause` says what.
    static step_failure other(std::size_t step, double t_from, double t_to, std::string cause) {
        newton_report rep;
        rep.residual = std::numeric_limits<double>::quiet_NaN();
        return step_failure(step, t_from, t_to, rep, std::move(cause), false);
    }
    [[nodiscard]] std::size_t step() const { return step_; }
    [[nodiscard]] double time() const { return time_; }
    [[nodiscard]] const newton_report& report() const { return report_; }
    /// The named cause, or empty when the step was merely too large for the motion (or no
    /// cause could be found).
    [[nodiscard]] const std::string& cause() const { return cause_; }
    /// what() without its closing advice, for a caller that has better advice to append.
    [[nodiscard]] std::string diagnosis() const {
        return newton_ ? describe(step_, time_, time_to_, report_, cause_) : what();
    }

  private:
    step_failure(std::size_t step, double t_from, double t_to, const newton_report& rep,
                 std::string cause, bool)
        : std::runtime_error(describe_other(step, t_from, t_to, cause)), step_(step),
          time_(t_from), time_to_(t_to), report_(rep), cause_(std::move(cause)), newton_(false) {}
    static std::string describe_other(std::size_t step, double t0, double t1,
                                      const std::string& cause) {
        char buf[120];
        std::snprintf(buf, sizeof buf, "step %zu (t = %.9g -> %.9g) failed: ", step, t0, t1);
        return buf + cause;
    }
    static std::string describe(std::size_t step, double t0, double t1, const newton_report& r,
                                const std::string& cause) {
        char buf[320];
        std::snprintf(buf, sizeof buf,
                      "Newton's method did not converge in step %zu (t = %.9g -> %.9g): residual "
                      "%.3e after %d iterations%s",
                      step, t0, t1, r.residual, r.iterations,
                      std::isfinite(r.residual) ? "" : " (NaN or infinity)");
        return cause.empty() ? std::string(buf) : std::string(buf) + ": " + cause;
    }
    std::size_t step_;
    double time_;
    double time_to_;
    newton_report report_;
    std::string cause_;
    bool newton_ = true;
};

/// Newton statistics of a run.
struct run_summary {
    std::size_t steps = 0;
    long long newton_iterations = 0;
    int newton_iterations_max = 0;
    [[nodiscard]] double mean_newton_iterations() const {
        return steps == 0 ? 0.0
                          : static_cast<double>(newton_iterations) / static_cast<double>(steps);
    }
};

/// Step j of a run: advances x from t_{j−1} to t_j = t0 + j h and returns t_j, adding the
/// step's Newton statistics to `sum`. Throws step_failure if Newton does not converge; x is then
/// left at the last good state, and the stepper's diagnose(x), if it has one, names the cause.
/// An exception from inside the step (the model's: a singular mass matrix, …) becomes a
/// step_failure too, naming it: the steppers write x only once a step has converged, so x is
/// still the step's start. The one step of both integrate and integrate_from.
template <stepper Stepper>
double advance(Stepper& stepper, phase_state<Stepper::dim>& x, double t0, std::size_t j,
               run_summary& sum) {
    const double h = stepper.step_size();
    if constexpr (requires { stepper.set_time(t0); }) // a forced step depends on t_{j−1}
        stepper.set_time(t0 + static_cast<double>(j - 1) * h);
    const double t = t0 + static_cast<double>(j) * h;
    newton_report rep;
    try {
        rep = stepper.step(x);
    } catch (const std::exception& e) {
        throw step_failure::other(j, t - h, t, e.what());
    }
    if (!rep.converged) {
        std::string cause; // x is still the step's start
        if constexpr (requires { stepper.diagnose(x); })
            cause = stepper.diagnose(x);
        else if constexpr (requires {
                               requires separable<std::remove_cvref_t<decltype(stepper.system())>>;
                           })
            cause = separable_failure(stepper.system(), x, t - h, h);
        throw step_failure(j, t - h, t, rep, std::move(cause));
    }
    ++sum.steps;
    sum.newton_iterations += rep.iterations;
    sum.newton_iterations_max = std::max(sum.newton_iterations_max, rep.iterations);
    return t;
}

/// Runs n steps from x at time t0 with t_j = t0 + j h. Calls observe(j, t_j, x) for j = 0 … n
/// (j = 0 is the initial state). Throws step_failure if a step does not converge.
/// For runs that stop early, checkpoint or resume, see run/state.hpp (run_state, integrate_from)
/// and run/observers.hpp.
template <stepper Stepper, class Observer>
run_summary integrate(Stepper& stepper, phase_state<Stepper::dim>& x, double t0, std::size_t n,
                      Observer&& observe) {
    observe(std::size_t{0}, t0, static_cast<const phase_state<Stepper::dim>&>(x));
    run_summary sum;
    for (std::size_t j = 1; j <= n; ++j) {
        const double t = varsym::advance(stepper, x, t0, j, sum);
        observe(j, t, static_cast<const phase_state<Stepper::dim>&>(x));
    }
    return sum;
}

} // namespace varsym
