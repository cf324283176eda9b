// apps/varsym/models/model_run.hpp: the driver every model's run shares: steps a stepper, streams
// the CSV rows (state, energy, conserved quantities, exact values), writes checkpoints and resumes
// from them, and turns a failed step into exit code 3 keeping the rows already written.
#pragma once

#include <chrono>
#include <iostream>
#include <numbers>
#include <string>

#include "files.hpp"
#include "models.hpp"
#include "progress.hpp"
#include "signals.hpp"
#include "varsym/diagnostics/stability.hpp"
#include "varsym/integrate.hpp"
#include "varsym/run/energy.hpp"
#include "varsym/run/state.hpp"

namespace varsym::cli {

/// What a checkpoint keeps of a stepper and its state.
struct saved_state {
    std::vector<double> q, p, carry_q, carry_p, history;
};

/// The output and the checkpoints of one run (run_log.cpp): the template below calls it.
class run_log {
  public:
    /// Opens the CSV (or, resuming, the interrupted run's FILE.part cut to the checkpoint's rows)
    /// and writes the header of a new run. Refuses --checkpoint without --output, an existing
    /// checkpoint file, and a checkpoint whose scheme, step count, h or dimension differ. d is
    /// the length of the saved q, dp that of p (−1: d; a rigid body saves R and Π: 9 and 3).
    run_log(const run_setup& s, const run_plan& plan, int d, const std::string& header,
            int dp = -1);

    [[nodiscard]] const checkpoint* resumed() const { return s_.resume.get(); }
    void write(const std::string& row) { out_.write(row); }

    /// Whether a checkpoint is due after step j (every --checkpoint-every steps, or when
    /// --checkpoint-seconds have passed, looked at every 1024 steps).
    [[nodiscard]] bool due(std::size_t j) {
        if (!checkpointing_) return false;
        if (every_ != 0 && j % every_ == 0) return true;
        return seconds_ > 0.0 && (j & 1023U) == 0 && clock::now() >= next_;
    }
    /// Writes the checkpoint of the state after step j (CSV flushed and fsync'ed first).
    void save(std::size_t j, const saved_state& x, const run_summary& sum);
    /// A step failed: writes a checkpoint of the last good state (step e.step() − 1), and throws
    /// numerical_error naming the step, time, residual and a safer step size from the scheme's
    /// linear stability limit and the highest frequency omega at the last good state.
    [[noreturn]] void fail(const step_failure& e, const saved_state& x, const run_summary& sum,
                           double omega);
    /// The run completed: final checkpoint (if checkpointing), CSV renamed into place, --stats.
    void finish(const saved_state& x, const run_summary& sum);
    /// SIGINT or SIGTERM arrived: checkpoints the state after step j (to --checkpoint, else to
    /// OUTPUT.ckpt where no such file is) and throws `interrupted` saying how to resume.
    [[noreturn]] void stop_by_signal(int sig, std::size_t j, const saved_state& x,
                                     const run_summary& sum);

    /// The energy watch: the bound on |E − E0| / scale(E0) (0: off) and its check after step j,
    /// which throws energy_error (exit 4), keeping the rows, when the error passed the bound or
    /// the energy is not finite. omega: the highest frequency at the state, for the advice.
    /// omega0: the highest frequency at the start (or the orbit's, if higher), for advice.
    void set_energy_reference(double e0, double omega0, double bound);
    [[nodiscard]] bool energy_watched() const { return watch_.on(); }
    void check_energy(std::size_t j, double t, double energy) {
        if (watch_.exceeded(energy)) energy_out_of_bounds(j, t, watch_.error(energy));
    }

    /// Whether the row of step j is written: every --every steps and the last (--every 0: the
    /// last only).
    [[nodiscard]] bool row_due(std::size_t j) const {
        const auto every = static_cast<std::size_t>(s_.every);
        return every == 0 ? j == plan_.steps : (j % every == 0 || j == plan_.steps);
    }
    /// What every run does after step j: the energy watch at each written row and every 256
    /// steps (an energy costs about a step), the progress line, a checkpoint when one is due,
    /// and a stop on a pending signal. energy() and save() are called only when needed.
    template <class Energy, class Save>
    void after_step(std::size_t j, double t, bool written, Energy&& energy, Save&& save,
                    const run_summary& stats) {
        if (energy_watched() && (written || (j & 255U) == 0)) check_energy(j, t, energy());
        if ((j & 1023U) == 0) progress_.update(j);
        if (due(j)) this->save(j, save(), stats);
        if (const int sig = pending_signal(); sig != 0 && j < plan_.steps)
            stop_by_signal(sig, j, save(), stats);
    }

  private:
    using clock = std::chrono::steady_clock;
    [[noreturn]] void energy_out_of_bounds(std::size_t j, double t, double err);
    /// Where the rows written so far are: FILE.part, or the special file written through.
    [[nodiscard]] std::string rows_place() const;
    /// A safer step for the message: stable at omega and within the energy bound.
    [[nodiscard]] std::string advice(double omega) const;
    /// The checkpoint after a stop (--checkpoint, else OUTPUT.ckpt if absent): "" if none.
    std::string save_last(std::size_t j, const saved_state& x, const run_summary& sum,
                          std::string& note);
    void write_checkpoint_to(const std::string& path, std::size_t j, const saved_state& x,
                             const run_summary& sum, bool replace);
    const run_setup& s_;
    run_plan plan_;
    output_file out_;
    bool checkpointing_ = false;
    std::size_t every_ = 0;
    double seconds_ = 0.0;
    clock::time_point next_;
    bool replace_ = false; ///< a checkpoint of this run exists: later ones replace it
    progress_line progress_;
    energy_watch watch_;
    double omega0_ = 0.0;
};

/// The run state a checkpoint saved, for d coordinates.
template <int D>
run_state<D> resumed_state(const checkpoint& ck, int d) {
    auto as_vec = [d](const std::vector<double>& v) {
        return vec<D>(Eigen::Map<const vec<D>>(v.data(), d));
    };
    run_state<D> r;
    r.x = phase_state<D>{as_vec(ck.q), as_vec(ck.p)};
    r.carry_q = as_vec(ck.carry_q);
    r.carry_p = as_vec(ck.carry_p);
    r.history = ck.history;
    r.step = ck.step;
    r.stats.steps = ck.step;
    r.stats.newton_iterations = ck.newton_iterations;
    r.stats.newton_iterations_max = ck.newton_iterations_max;
    return r;
}

/// The frequency a run's step must resolve: omega, the highest at the start (NaN: none known),
/// or the orbit's 2 pi / period if higher.
inline double resolved_frequency(double omega, double period) {
    if (!(omega >= 0.0)) omega = 0.0;
    return period > 0.0 ? std::max(omega, 2.0 * std::numbers::pi / period) : omega;
}

/// The energy watch's bound: none where the energy is not conserved (an L that depends on
/// time), else --max-energy-error or the default from the scheme's order, h and omega0.
inline double energy_watch_bound(const run_setup& s, bool conserved, double h, double omega0) {
    return !conserved                  ? 0.0
           : s.max_energy_error >= 0.0 ? s.max_energy_error
                                       : default_energy_bound(s.order(), h, omega0);
}

/// A run_state as the checkpoint file stores it (plain vectors).
template <int D>
saved_state save_state(const run_state<D>& r) {
    auto list = [](const auto& v) { return std::vector<double>(v.data(), v.data() + v.size()); };
    return {list(r.x.q), list(r.x.p), list(r.carry_q), list(r.carry_p), r.history};
}

/// Streams `step,t,<state columns><extra header>` rows for plan.steps steps from x, written every
/// s.every steps and at the end. `with_stepper(f)` calls f(stepper); `extras(t, x, line)` appends
/// the model's columns (each preceded by a comma) to a row. A resumed run (s.resume) starts from
/// its checkpoint's state, carries and step instead of x.
template <int D, class WithStepper, class Extras>
void stream_trajectory(const run_setup& s, const run_plan& plan, phase_state<D> x,
                       const std::string& extra_header, WithStepper&& with_stepper,
                       Extras&& extras) {
    const int d = static_cast<int>(x.q.size());
    run_log log(s, plan, d, "step,t," + state_columns(d) + extra_header + "\n");
    const std::size_t n = plan.steps;
    std::string line;
    /// Writes the row of step j if it is one to write; says whether it did.
    auto row = [&](std::size_t j, double t, const phase_state<D>& y) {
        if (!log.row_due(j)) return false;
        line = std::to_string(j);
        line += ',';
        append_number(line, t);
        for (Eigen::Index i = 0; i < d; ++i) {
            line += ',';
            append_number(line, y.q(i));
        }
        for (Eigen::Index i = 0; i < d; ++i) {
            line += ',';
            append_number(line, y.p(i));
        }
        extras(t, y, line);
        line += '\n';
        log.write(line);
        return true;
    };
    with_stepper([&](auto& stepper) {
        auto r = run_state<D>::start(x);
        const double h = stepper.step_size();
        auto omega_at = [&](const phase_state<D>& y, double t) {
            try {
                if constexpr (timed_system<std::remove_cvref_t<decltype(stepper.system())>>)
                    return highest_frequency(stepper.system(), y, t);
                else
                    return highest_frequency(stepper.system(), y);
            } catch (const std::exception&) { // no estimate: the messages say so
                return std::numeric_limits<double>::quiet_NaN();
            }
        };
        const double omega0 = resolved_frequency(omega_at(x, 0.0), plan.period);
        const double bound = energy_watch_bound(s, conserves_energy(stepper.system()), h, omega0);
        log.set_energy_reference(energy_at(stepper.system(), x, 0.0), omega0, bound);
        if (const checkpoint* ck = log.resumed()) {
            r = resumed_state<D>(*ck, d);
            restore(stepper, r);
        } else {
            row(0, 0.0, x);
        }
        set_signal_polling(true);
        try {
            integrate_from(stepper, r, n, [&](const run_state<D>& y) {
                const std::size_t j = y.step;
                log.after_step(
                    j, y.time(h), row(j, y.time(h), y.x),
                    [&] { return watched_energy(stepper, y.x, y.time(h)); },
                    [&] { return save_state(y); }, y.stats);
            });
        } catch (const step_failure& e) {
            set_signal_polling(false);
            log.fail(e, save_state(r), r.stats, omega_at(r.x, r.time(h)));
        }
        set_signal_polling(false);
        log.finish(save_state(r), r.stats);
    });
}

/// Appends ",v" for each value.
inline void append_values(std::string& line, std::initializer_list<double> values) {
    for (double v : values) {
        line += ',';
        append_number(line, v);
    }
}

} // namespace varsym::cli
