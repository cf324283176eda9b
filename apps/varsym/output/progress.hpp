// apps/varsym/output/progress.hpp: the progress line of long commands: "done/total UNIT (%), rate,
// time left" on standard error, redrawn at most twice a second, only when standard error is a
// terminal (and not --quiet); never on standard output.
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

#include <unistd.h>

namespace varsym::cli {

class progress_line {
  public:
    /// `what`: "varsym run"; `unit`: "steps"; `already`: done before this process started.
    progress_line(std::string what, std::string unit, std::size_t total, std::size_t already,
                  bool quiet = false)
        : what_(std::move(what)), unit_(std::move(unit)), total_(total), already_(already),
          shown_(!quiet && isatty(STDERR_FILENO) != 0), start_(clock::now()), last_(start_) {}
    [[nodiscard]] bool shown() const { return shown_; }
    void update(std::size_t done, bool final = false) {
        if (!shown_) return;
        const auto now = clock::now();
        if (!final && now - last_ < std::chrono::milliseconds(500)) return;
        last_ = now;
        const double secs = std::chrono::duration<double>(now - start_).count();
        const double rate = secs > 0 ? static_cast<double>(done - already_) / secs : 0.0;
        const double left = rate > 0 ? static_cast<double>(total_ - done) / rate : 0.0;
        std::fprintf(stderr, "\r%s: %zu/%zu %s (%.1f %%), %.3g %s/s, %.0f s left   %s",
                     what_.c_str(), done, total_, unit_.c_str(),
                     100.0 * static_cast<double>(done) / static_cast<double>(total_), rate,
                     unit_.c_str(), left, final ? "\n" : "");
        std::fflush(stderr);
    }
    /// Ends the line (a shown line that did not reach its final update).
    void close() {
        if (shown_ && last_ != start_) std::fputc('\n', stderr);
        shown_ = false;
    }

  private:
    using clock = std::chrono::steady_clock;
    std::string what_, unit_;
    std::size_t total_, already_;
    bool shown_;
    clock::time_point start_, last_;
};

} // namespace varsym::cli
