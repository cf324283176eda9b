// apps/varsym/output/run_log.cpp: the output and checkpoints of `varsym run` (model_run.hpp): when
// a checkpoint is written, what it holds, how a resumed run checks it, and how a run stops: a
// failed step (exit 3), the energy watch (exit 4), SIGINT/SIGTERM (exit 130/143).
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "models/model_run.hpp"

namespace varsym::cli {

namespace {

std::string format(const char* fmt, double v) {
    char buf[160];
    std::snprintf(buf, sizeof buf, fmt, v);
    return buf;
}

/// Refuses a checkpoint that does not describe the run its own arguments set up.
void check_resume(const run_setup& s, const run_plan& plan, int d, int dp) {
    if (!s.resume) return;
    const checkpoint& ck = *s.resume;
    std::string what;
    if (ck.scheme != s.label())
        what = "scheme " + ck.scheme + " vs " + s.label();
    else if (ck.steps != plan.steps)
        what = "steps " + std::to_string(ck.steps) + " vs " + std::to_string(plan.steps);
    else if (ck.h != plan.h)
        what = "time step";
    else if (ck.q.size() != static_cast<std::size_t>(d) ||
             ck.p.size() != static_cast<std::size_t>(dp))
        what = "dimension";
    if (!what.empty())
        throw usage_error("checkpoint '" + s.checkpoint +
                          "' does not match the run its options set up (" + what +
                          "); it was not written by this varsym build");
}

/// The CSV of a new run, or a resumed run's FILE.part (locked, checked against the checkpoint's
/// CRC-32 and cut to its rows) once the checkpoint is known to belong to this run.
output_file open_output(const run_setup& s, const run_plan& plan, int d, int dp) {
    if (!s.resume) return output_file(s.output);
    check_resume(s, plan, d, dp);
    return output_file(s.output, s.resume->csv_bytes, s.resume->csv_crc32);
}

} // namespace

run_log::run_log(const run_setup& s, const run_plan& plan, int d, const std::string& header, int dp)
    : s_(s), plan_(plan), out_(open_output(s, plan, d, dp < 0 ? d : dp)),
      progress_("varsym run", "steps", plan.steps, s.resume ? s.resume->step : 0, s.quiet) {
    checkpointing_ = !s.checkpoint.empty();
    every_ = static_cast<std::size_t>(s.checkpoint_every);
    seconds_ = s.checkpoint_seconds;
    // More than 30 years is never (and would overflow the clock's nanoseconds).
    next_ = seconds_ > 1e9 ? clock::time_point::max()
                           : clock::now() + std::chrono::duration_cast<clock::duration>(
                                                std::chrono::duration<double>(seconds_));
    replace_ = static_cast<bool>(s.resume);
    if (s.resume) {
        // FILE.part is locked by us now: a CK.tmp left by this run's killed checkpoint write is
        // ours to remove; anything else there is not.
        const std::string tmp = s.checkpoint + ".tmp";
        if (std::filesystem::exists(tmp)) {
            if (!looks_like_checkpoint(tmp))
                throw usage_error("cannot resume: '" + tmp +
                                  "' exists and is not a checkpoint of this run; move it away");
            std::remove(tmp.c_str());
        }
    } else {
        out_.write(header);
    }
}

void run_log::set_energy_reference(double e0, double omega0, double bound) {
    watch_ = energy_watch(e0, bound);
    omega0_ = omega0;
}

void run_log::write_checkpoint_to(const std::string& path, std::size_t j, const saved_state& x,
                                  const run_summary& sum, bool replace) {
    out_.sync(); // the rows the checkpoint counts are on disk before it
    checkpoint ck;
    ck.args = s_.args;
    ck.inputs = s_.inputs;
    ck.output = std::filesystem::absolute(s_.output).string();
    ck.scheme = s_.label();
    ck.step = j;
    ck.steps = plan_.steps;
    ck.h = plan_.h;
    ck.csv_bytes = out_.bytes();
    ck.csv_crc32 = out_.crc();
    ck.q = x.q;
    ck.p = x.p;
    ck.carry_q = x.carry_q;
    ck.carry_p = x.carry_p;
    ck.history = x.history;
    ck.newton_iterations = sum.newton_iterations;
    ck.newton_iterations_max = sum.newton_iterations_max;
    write_checkpoint(path, ck, replace);
    out_.keep_partial(); // FILE.part now belongs to the checkpoint: never removed on failure
}

void run_log::save(std::size_t j, const saved_state& x, const run_summary& sum) {
    write_checkpoint_to(s_.checkpoint, j, x, sum, replace_);
    replace_ = true;
    if (seconds_ <= 1e9)
        next_ = clock::now() + std::chrono::duration_cast<clock::duration>(
                                   std::chrono::duration<double>(seconds_));
}

std::string run_log::save_last(std::size_t j, const saved_state& x, const run_summary& sum,
                               std::string& note) {
    if (out_.is_stdout() || out_.is_through()) return {};
    std::string path = s_.checkpoint;
    bool replace = replace_;
    if (path.empty()) { // OUTPUT.ckpt, never over a file the user already has
        path = s_.output + ".ckpt";
        replace = false;
        if (std::filesystem::exists(path) || std::filesystem::exists(path + ".tmp")) {
            note = "; no checkpoint written: '" + path + "' exists";
            return {};
        }
    }
    try {
        write_checkpoint_to(path, j, x, sum, replace);
        return path;
    } catch (const std::exception& e) {
        note = std::string("; the state could not be saved: ") + e.what();
        return {};
    }
}

std::string run_log::rows_place() const {
    return out_.is_through() ? s_.output : out_.partial_path();
}

std::string run_log::advice(double omega) const {
    const double h = plan_.h;
    if (!(std::isfinite(omega) && omega > 0.0))
        return format("; no frequency estimate at this state: try a much smaller h (now %.3g)", h);
    // Below the scheme's linear stability limit z* for ω (h ω < z*) with a margin of 2, and where
    // the expected energy error 100 (h ω)^r is within the bound; a tenth of h when these do not
    // call for a step below half the one that failed.
    // The family's linear stability limit, or the limit another method states (the rigid
    // bodies': the largest turn per step at which its step equation has a solution).
    const double limit = s_.method.empty() ? linear_stability_limit(s_.spec) : s_.method_limit;
    const std::string what = s_.method.empty() ? "'s linear stability limit " : "'s step limit ";
    const double bound = watch_.on() ? watch_.bound() : 0.01;
    double from_omega = std::pow(bound / 100.0, 1.0 / s_.order()) / omega;
    std::string msg =
        format("; at omega_max = %.4g rad/s (the start's or the state's), h*omega = ", omega) +
        format("%.3g", h * omega);
    if (std::isfinite(limit)) {
        msg += " against " + s_.label() + what + format("%.4g", limit);
        from_omega = std::min(from_omega, 0.5 * limit / omega);
    } else if (std::isinf(limit)) {
        msg += " (" + s_.label() + " is linearly stable at every h*omega)";
    }
    if (!(from_omega < 0.5 * h))
        return msg + "; that frequency does not explain it (the motion is faster elsewhere): " +
               format("try h <= %.3g", 0.1 * h) + format(" (now %.3g)", h);
    return msg + format("; try h <= %.3g", from_omega) + format(" (now %.3g", h) +
           ", e.g. with more steps)";
}

void run_log::fail(const step_failure& e, const saved_state& x, const run_summary& sum,
                   double omega) {
    progress_.close();
    // The last good state's frequency, or the start's if higher (a state may be near a turning
    // point, where the local frequency says little); no time-step advice when the stepper named
    // another cause.
    std::string msg = e.diagnosis();
    if (e.cause().empty()) msg += advice(std::isfinite(omega) ? std::max(omega, omega0_) : omega0_);
    if (out_.is_stdout()) throw numerical_error(msg);
    out_.keep_partial();
    std::string note;
    const std::string path = save_last(e.step() - 1, x, sum, note);
    if (!path.empty())
        msg += "; the last good state (step " + std::to_string(e.step() - 1) + ") is in " + path;
    throw numerical_error(msg + note + "; the rows before it are in " + rows_place());
}

void run_log::energy_out_of_bounds(std::size_t j, double t, double err) {
    progress_.close();
    std::string msg = "the relative energy error reached " + format("%.3g", err) + " at step " +
                      std::to_string(j) + format(" (t = %.6g)", t) + ", above --max-energy-error " +
                      format("%.3g", watch_.bound()) +
                      ": the trajectory is no longer meaningful (0 turns this check off)" +
                      advice(omega0_);
    if (!out_.is_stdout()) {
        out_.keep_partial();
        msg += "; the rows so far are in " + rows_place();
    }
    throw energy_error(msg);
}

void run_log::stop_by_signal(int sig, std::size_t j, const saved_state& x, const run_summary& sum) {
    set_signal_polling(false);
    progress_.close();
    const std::string name = sig == SIGINT ? "SIGINT" : "SIGTERM";
    std::string msg = "stopped by " + name + " after step " + std::to_string(j) + " of " +
                      std::to_string(plan_.steps);
    if (out_.is_stdout() || out_.is_through()) throw interrupted(sig, msg);
    out_.keep_partial();
    std::string note;
    const std::string path = save_last(j, x, sum, note);
    if (path.empty())
        throw interrupted(sig, msg + note + "; the rows so far are in " + rows_place());
    throw interrupted(sig, msg + "; continue with 'varsym run --resume " + path + "'");
}

void run_log::finish(const saved_state& x, const run_summary& sum) {
    progress_.update(plan_.steps, true);
    // The final checkpoint comes first: if the process dies between it and the rename, a
    // resume finds the run complete and only renames FILE.part.
    if (checkpointing_) write_checkpoint_to(s_.checkpoint, plan_.steps, x, sum, replace_);
    out_.commit();
    if (s_.stats)
        std::cerr << "varsym: " << s_.label() << ", " << sum.steps << " steps of h = " << plan_.h
                  << ": Newton iterations per step mean " << sum.mean_newton_iterations()
                  << ", max " << sum.newton_iterations_max << '\n';
}

} // namespace varsym::cli
