// varsym/run/ensemble.hpp: many runs of one model from a grid of initial data or parameters —
// stability, MEGNO and Lyapunov maps, flip-time and escape-time maps. One member's run with its
// summary (final state, largest energy error, chaos indicators, first event), a rectangular
// grid numbered member by member, and a parallel loop over members. The numbering and each
// member's result do not depend on how many threads (or processes) share the members, so an
// ensemble written in member order is the same file for any split.
#pragma once

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <limits>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "varsym/diagnostics/chaos.hpp"
#include "varsym/run/cpus.hpp"

namespace varsym {

/// One axis of a grid: `count` ≥ 1 values evenly spaced from `first` to `last` (both included;
/// count 1: `first` alone).
struct grid_axis {
    std::string name;
    double first = 0.0, last = 0.0;
    std::size_t count = 1;
    [[nodiscard]] double value(std::size_t i) const {
        if (count == 1) return first;
        const double f = static_cast<double>(i) / static_cast<double>(count - 1);
        return i + 1 == count ? last : first + f * (last - first);
    }
};

/// The product of axes. Member m is numbered like nested loops with the last axis innermost:
/// the last axis varies fastest.
class grid {
  public:
    explicit grid(std::vector<grid_axis> axes) : axes_(std::move(axes)) {
        for (const auto& a : axes_)
            if (a.count == 0) throw std::invalid_argument("axis " + a.name + " has no points");
    }
    [[nodiscard]] const std::vector<grid_axis>& axes() const { return axes_; }
    /// The number of members: the product of the counts, saturated at the largest std::size_t
    /// (a product that does not fit is refused as too large, never wrapped around to a few).
    [[nodiscard]] std::size_t size() const {
        std::size_t n = 1;
        for (const auto& a : axes_)
            if (__builtin_mul_overflow(n, a.count, &n)) return SIZE_MAX;
        return n;
    }
    /// The values of member m along each axis.
    void point(std::size_t m, std::vector<double>& values) const {
        values.resize(axes_.size());
        for (std::size_t k = axes_.size(); k-- > 0;) {
            values[k] = axes_[k].value(m % axes_[k].count);
            m /= axes_[k].count;
        }
    }

  private:
    std::vector<grid_axis> axes_;
};

/// What one member's run found.
struct member_result {
    enum class outcome { completed, event, failed, stopped };
    outcome status = outcome::completed;
    long long steps = 0;          ///< steps taken
    double time = 0.0;            ///< time reached (t0 + steps · h)
    std::vector<double> q, p;     ///< the state at `time`
    double max_energy_error = 0.; ///< max |E − E0| / |E0| over the steps (|E − E0| if E0 = 0)
    double lyapunov = std::numeric_limits<double>::quiet_NaN();   ///< λ(time), 1/time units
    double mean_megno = std::numeric_limits<double>::quiet_NaN(); ///< ⟨Y⟩(time)
    double event_time = std::numeric_limits<double>::quiet_NaN(); ///< the first event, if any
    std::string cause; ///< why a failed member failed (Newton's residual, a non-finite value)
};

/// How a member runs: its number of steps, whether the tangent map is carried for λ and MEGNO
/// (about doubling the cost of a step), and the start time.
struct member_plan {
    long long steps = 0;
    bool indicators = true;
    double t0 = 0.0;
    /// When given and set (by another thread, or a signal handler), the member ends after its
    /// current step with outcome::stopped and the state reached: Ctrl-C within a step.
    const std::atomic<bool>* stop = nullptr;
    [[nodiscard]] bool stopped() const {
        return stop != nullptr && stop->load(std::memory_order_relaxed);
    }
};

/// What a member's loop watches after each step, for run_member and for the steppers of other
/// state spaces (the rigid bodies'): the largest relative energy error and the event, a change
/// of sign of a number g(t, x) from its first non-zero sign, located by linear interpolation of
/// g over the step (error O(h²) in time).
class member_watch {
  public:
    member_watch(double e0, double g0)
        : e0_(e0), scale_(e0 != 0.0 ? std::abs(e0) : 1.0), g_prev_(g0), sign_(g0) {}
    /// After a step of h ending at t with energy e and event value g: updates r's largest
    /// energy error, and returns true, with r's status and event time set, at the event.
    /// A value of g that is not finite (g = q1/0) ends r as failed, naming it: its sign would
    /// say nothing.
    bool after_step(member_result& r, double t, double h, double e, double g) {
        r.max_energy_error = std::max(r.max_energy_error, std::abs(e - e0_) / scale_);
        if (!std::isfinite(g) || !std::isfinite(g_prev_)) {
            r.status = member_result::outcome::failed;
            r.cause = "the event's value is not a finite number at t = " +
                      std::to_string(std::isfinite(g_prev_) ? t : t - h);
            return true;
        }
        if (sign_ == 0.0) {
            sign_ = g;
        } else if (g * sign_ <= 0.0 && g != g_prev_) {
            r.status = member_result::outcome::event;
            r.event_time = t - h * g / (g - g_prev_); // the zero of the line through both ends
            return true;
        }
        g_prev_ = g;
        return false;
    }
    /// Ends r as failed at a step that did not converge (or, converged, left a non-finite state).
    static void fail(member_result& r, const newton_report& rep) {
        r.status = member_result::outcome::failed;
        r.cause = rep.converged
                      ? "a non-finite state"
                      : "Newton did not converge (residual " + std::to_string(rep.residual) + ")";
    }

  private:
    double e0_, scale_, g_prev_, sign_;
};

/// Runs one member of s from x. `energy(x)` gives E; `event(t, x)` a number whose change of sign
/// (from its first non-zero sign) is the event (member_watch); pass a function returning 1.0
/// for none. A step that fails (Newton, NaN) ends the member with outcome::failed and the state
/// before it.
template <tangent_stepper S, class Energy, class Event>
member_result run_member(S& s, phase_state<S::dim> x, const member_plan& plan, Energy&& energy,
                         Event&& event) {
    member_result r;
    const double h = s.step_size();
    member_watch watch(energy(x), event(plan.t0, x));
    std::optional<chaos_indicators> chaos;
    if (plan.indicators) chaos.emplace(static_cast<int>(x.q.size()), h);
    Eigen::MatrixXd j;
    phase_state<S::dim> from = x;
    long long k = 0;
    for (; k < plan.steps; ++k) {
        if (plan.stopped()) {
            r.status = member_result::outcome::stopped;
            break;
        }
        from = x;
        // A forced step depends on its start time: t0 + k h, as integrate() sets it (a time
        // accumulated step by step would drift from it by round-off).
        if constexpr (requires { s.set_time(plan.t0); })
            s.set_time(plan.t0 + static_cast<double>(k) * h);
        const newton_report rep = s.step(x);
        if (!rep.converged || !x.q.allFinite() || !x.p.allFinite()) {
            x = from;
            member_watch::fail(r, rep);
            break;
        }
        if (chaos) {
            s.step_jacobian(from, j);
            chaos->advance(j);
        }
        const double t = plan.t0 + static_cast<double>(k + 1) * h;
        if (watch.after_step(r, t, h, energy(x), event(t, x))) {
            ++k;
            break;
        }
    }
    r.steps = k;
    r.time = plan.t0 + static_cast<double>(k) * h;
    r.q.assign(x.q.data(), x.q.data() + x.q.size());
    r.p.assign(x.p.data(), x.p.data() + x.p.size());
    if (chaos && chaos->steps() > 0 && chaos->ok()) {
        r.lyapunov = chaos->lyapunov();
        r.mean_megno = chaos->mean_megno();
    }
    return r;
}

/// Calls f(m) once for each member m < count, from `threads` threads (0: available_cpus()),
/// each taking the next member not yet taken: members of unequal cost balance themselves. f must
/// be safe to call concurrently for different m. The first exception f throws stops the loop
/// (members already running finish) and is rethrown here.
template <class F>
void for_each_member(std::size_t count, unsigned threads, F&& f) {
    if (threads == 0) threads = available_cpus();
    threads =
        static_cast<unsigned>(std::min<std::size_t>(threads, std::max<std::size_t>(count, 1)));
    std::atomic<std::size_t> next{0};
    std::atomic<bool> stop{false};
    std::exception_ptr error;
    std::mutex error_mutex;
    auto work = [&] {
        for (std::size_t m; !stop.load(std::memory_order_relaxed) && (m = next++) < count;) {
            try {
                f(m);
            } catch (...) {
                const std::lock_guard lock(error_mutex);
                if (!error) error = std::current_exception();
                stop = true;
            }
        }
    };
    std::vector<std::jthread> pool;
    for (unsigned k = 1; k < threads; ++k)
        pool.emplace_back(work);
    work();
    pool.clear(); // joins
    if (error) std::rethrow_exception(error);
}

} // namespace varsym
