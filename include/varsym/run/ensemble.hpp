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
#include <exception>
#include <limits>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "varsym/diagnostics/chaos.hpp"

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
    [[nodiscard]] std::size_t size() const {
        std::size_t n = 1;
        for (const auto& a : axes_)
            n *= a.count;
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
    enum class outcome { completed, event, failed };
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
};

/// Runs one member of s from x. `energy(x)` gives E; `event(t, x)` a number whose change of sign
/// (from its first non-zero sign) is the event: the run stops there, with the event's time
/// located by linear interpolation of that number over the step (error O(h²) in time); pass
/// a function returning 1.0 for none. A step that fails (Newton, NaN) ends the member with
/// outcome::failed and the state before it.
template <tangent_stepper S, class Energy, class Event>
member_result run_member(S& s, phase_state<S::dim> x, const member_plan& plan, Energy&& energy,
                         Event&& event) {
    member_result r;
    const double h = s.step_size(), e0 = energy(x);
    const double scale = e0 != 0.0 ? std::abs(e0) : 1.0;
    std::optional<chaos_indicators> chaos;
    if (plan.indicators) chaos.emplace(static_cast<int>(x.q.size()), h);
    Eigen::MatrixXd j;
    double g_prev = event(plan.t0, x), sign = g_prev;
    phase_state<S::dim> from = x;
    long long k = 0;
    for (; k < plan.steps; ++k) {
        from = x;
        // A forced step depends on its start time: t0 + k h, as integrate() sets it (a time
        // accumulated step by step would drift from it by round-off).
        if constexpr (requires { s.set_time(plan.t0); })
            s.set_time(plan.t0 + static_cast<double>(k) * h);
        const newton_report rep = s.step(x);
        if (!rep.converged || !x.q.allFinite() || !x.p.allFinite()) {
            x = from;
            r.status = member_result::outcome::failed;
            r.cause = rep.converged ? "a non-finite state"
                                    : "Newton did not converge (residual " +
                                          std::to_string(rep.residual) + ")";
            break;
        }
        if (chaos) {
            s.step_jacobian(from, j);
            chaos->advance(j);
        }
        const double t = plan.t0 + static_cast<double>(k + 1) * h;
        r.max_energy_error = std::max(r.max_energy_error, std::abs(energy(x) - e0) / scale);
        const double g = event(t, x);
        if (sign == 0.0) {
            sign = g;
        } else if (g * sign <= 0.0 && g != g_prev) {
            r.status = member_result::outcome::event;
            r.event_time = t - h * g / (g - g_prev); // the zero of the line through both ends
            ++k;
            break;
        }
        g_prev = g;
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

/// Calls f(m) once for each member m < count, from `threads` threads (0: all the hardware's),
/// each taking the next member not yet taken: members of unequal cost balance themselves. f must
/// be safe to call concurrently for different m. The first exception f throws stops the loop
/// (members already running finish) and is rethrown here.
template <class F>
void for_each_member(std::size_t count, unsigned threads, F&& f) {
    if (threads == 0) threads = std::max(1U, std::thread::hardware_concurrency());
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
