// apps/varsym/run_log.cpp: the output and checkpoints of `varsym run` (model_run.hpp): when a
// checkpoint is written, what it holds, how a resumed run checks it, and the exit-3 message.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "model_run.hpp"

namespace varsym::cli {

namespace {

std::string format(const char* fmt, double v) {
    char buf[160];
    std::snprintf(buf, sizeof buf, fmt, v);
    return buf;
}

/// Refuses a checkpoint that does not describe the run its own arguments set up.
void check_resume(const run_setup& s, const run_plan& plan, int d) {
    if (!s.resume) return;
    const checkpoint& ck = *s.resume;
    std::string what;
    if (ck.scheme != s.spec.label())
        what = "scheme " + ck.scheme + " vs " + s.spec.label();
    else if (ck.steps != plan.steps)
        what = "steps " + std::to_string(ck.steps) + " vs " + std::to_string(plan.steps);
    else if (ck.h != plan.h)
        what = "time step";
    else if (ck.q.size() != static_cast<std::size_t>(d))
        what = "dimension";
    if (!what.empty())
        throw usage_error("checkpoint '" + s.checkpoint +
                          "' does not match the run its options set up (" + what +
                          "); it was not written by this varsym build");
}

/// The CSV of a new run, or a resumed run's FILE.part cut to the checkpoint's rows once the
/// checkpoint is known to belong to this run.
output_file open_output(const run_setup& s, const run_plan& plan, int d) {
    if (!s.resume) return output_file(s.output);
    check_resume(s, plan, d);
    return output_file(s.output, s.resume->csv_bytes);
}

} // namespace

run_log::run_log(const run_setup& s, const run_plan& plan, int d, const std::string& header)
    : s_(s), plan_(plan), out_(open_output(s, plan, d)) {
    checkpointing_ = !s.checkpoint.empty();
    every_ = static_cast<std::size_t>(s.checkpoint_every);
    seconds_ = s.checkpoint_seconds;
    next_ = clock::now() +
            std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(seconds_));
    if (!s.resume) out_.write(header);
}

void run_log::write_checkpoint_to(const std::string& path, std::size_t j, const saved_state& x,
                                  const run_summary& sum) {
    out_.sync(); // the rows the checkpoint counts are on disk before it
    checkpoint ck;
    ck.args = s_.args;
    ck.output = std::filesystem::absolute(s_.output).string();
    ck.scheme = s_.spec.label();
    ck.step = j;
    ck.steps = plan_.steps;
    ck.h = plan_.h;
    ck.csv_bytes = out_.bytes();
    ck.q = x.q;
    ck.p = x.p;
    ck.carry_q = x.carry_q;
    ck.carry_p = x.carry_p;
    ck.newton_iterations = sum.newton_iterations;
    ck.newton_iterations_max = sum.newton_iterations_max;
    write_checkpoint(path, ck);
    out_.keep_partial(); // FILE.part now belongs to the checkpoint: never removed on failure
}

void run_log::save(std::size_t j, const saved_state& x, const run_summary& sum) {
    write_checkpoint_to(s_.checkpoint, j, x, sum);
    next_ = clock::now() +
            std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(seconds_));
}

void run_log::fail(const step_failure& e, const saved_state& x, const run_summary& sum,
                   double omega) {
    const double h = plan_.h;
    std::string msg = e.diagnosis();
    // A safer step: below the scheme's linear stability limit z* for the highest frequency ω
    // at the last good state (h ω < z*), with a margin of 2, and at most half the failed step.
    const double limit = linear_stability_limit(s_.spec);
    double safer = 0.5 * h;
    if (std::isfinite(omega) && omega > 0.0) {
        msg += format("; at the last good state omega_max = %.4g rad/s, h*omega = ", omega) +
               format("%.3g", h * omega);
        if (std::isfinite(limit)) {
            msg += " against " + s_.spec.label() + "'s linear stability limit " +
                   format("%.4g", limit);
            safer = std::min(safer, 0.5 * limit / omega);
        } else {
            msg += " (" + s_.spec.label() +
                   " is linearly stable at every h*omega; the nonlinearity "
                   "defeated Newton)";
        }
    }
    msg += format("; try h <= %.3g", safer) + format(" (now %.3g", h) + ", e.g. with more steps)";
    if (out_.is_stdout()) throw numerical_error(msg);
    // The last good state, as a checkpoint: --checkpoint FILE, else OUTPUT.ckpt (never over a
    // file the user already has).
    std::string path = s_.checkpoint;
    if (path.empty()) {
        path = s_.output + ".ckpt";
        if (std::filesystem::exists(path)) path.clear();
    }
    out_.keep_partial();
    if (!path.empty()) {
        write_checkpoint_to(path, e.step() - 1, x, sum);
        msg += "; the last good state (step " + std::to_string(e.step() - 1) + ") is in " + path;
    }
    throw numerical_error(msg + "; the rows before it are in " + out_.partial_path());
}

void run_log::finish(const saved_state& x, const run_summary& sum) {
    // The final checkpoint comes first: if the process dies between it and the rename, a
    // resume finds the run complete and only renames FILE.part.
    if (checkpointing_) write_checkpoint_to(s_.checkpoint, plan_.steps, x, sum);
    out_.commit();
    if (s_.stats)
        std::cerr << "varsym: " << s_.spec.label() << ", " << sum.steps
                  << " steps of h = " << plan_.h << ": Newton iterations per step mean "
                  << sum.mean_newton_iterations() << ", max " << sum.newton_iterations_max << '\n';
}

} // namespace varsym::cli
