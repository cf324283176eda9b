// apps/varsym/models/model_run.hpp: what the tool's run loops share (simulation_run.cpp for the
// models layer, model_expression.cpp for `lagrangian`): the run log that streams the CSV rows,
// writes checkpoints and resumes from them, watches the energy, and turns a failed step into exit
// code 3 keeping the rows already written.
#pragma once

#include <chrono>
#include <iostream>
#include <numbers>
#include <string>

#include "models/models.hpp"
#include "output/files.hpp"
#include "output/progress.hpp"
#include "output/signals.hpp"
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
    /// Whether after_step(j, …) has nothing to do but look for a signal: no row, energy check,
    /// progress line or checkpoint is due at step j. The run loop's fast path (on the cheapest
    /// systems the full after_step costs about 12 % of a step).
    [[nodiscard]] bool idle(std::size_t j) const {
        return (j & 255U) != 0 && !checkpointing_ && !row_due(j);
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

/// Appends ",v" for each value.
inline void append_values(std::string& line, std::initializer_list<double> values) {
    for (double v : values) {
        line += ',';
        append_number(line, v);
    }
}

} // namespace varsym::cli
