// apps/varsym/output/signals.hpp: SIGINT and SIGTERM. Outside a run's stepping loop a signal
// removes the temporary files the tool created (FILE.part, CK.tmp) and ends the process by that
// signal. Inside it (polling on), the first signal only sets a flag: the run finishes its step,
// writes a checkpoint and exits 130 or 143; a second signal acts at once, as outside, unless it is
// the same signal within a second of the first (one request delivered twice, as timeout(1) does).
#pragma once

#include <atomic>
#include <string>

namespace varsym::cli {

/// Installs the handlers (idempotent).
void install_signal_handlers();

/// Whether the first SIGINT/SIGTERM waits for the run to poll pending_signal(). A first
/// SIGINT then prints one line on standard error: what the command is doing before it stops
/// (`finishing`, e.g. "the members in flight finish their current step"; default: "the
/// current step finishes").
void set_signal_polling(bool on, const char* finishing = nullptr);

/// 0, or the number of the signal received while polling was on.
[[nodiscard]] int pending_signal();

/// Set with pending_signal(): for loops that watch a flag (member_plan::stop) rather than call.
[[nodiscard]] const std::atomic<bool>& stop_flag();

/// The tool run in-process (Python's varsym.call): install_signal_handlers() then leaves the
/// host's handlers alone, and the host calls request_stop() when it sees Ctrl-C, which acts as
/// a first signal with polling on. clear_pending_signal() before each in-process command.
void set_embedded(bool on);
void request_stop(int sig);
void clear_pending_signal();

/// A temporary file of ours to remove if a signal ends the process; forget_at_signal when it
/// was renamed, kept or removed. At most 16 at once (extra ones are not tracked).
void remove_at_signal(const std::string& path);
void forget_at_signal(const std::string& path);

} // namespace varsym::cli
