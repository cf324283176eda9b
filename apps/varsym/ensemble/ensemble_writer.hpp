// apps/varsym/ensemble/ensemble_writer.hpp: one process's rows on their way to its journal, in
// member order. Threads finish members out of order; a row waits here until every member
// before it has finished, so that the journal holds long runs of rows in increasing member
// order and the final merge (ensemble_journal::merge) streams them with little memory.
#pragma once

#include <chrono>
#include <cstddef>
#include <map>
#include <mutex>
#include <set>
#include <string>

#include "ensemble_journal.hpp"

namespace varsym::cli {

class ordered_writer {
  public:
    explicit ordered_writer(ensemble_journal& journal) : journal_(journal) {}
    /// This process's k-th member (counting from 0, in increasing member order) is done, with
    /// its row (ending in '\n'; empty for a member skipped because a journal has it). Rows in
    /// order go to the journal every 0.25 s or 64 KiB; more than `max_waiting` rows waiting
    /// behind a slow member are written at once (a new run of the journal begins).
    void done(std::size_t k, std::string row);
    /// Writes every row done, in member order (at the end, or when the work stops).
    void flush_all();

    static constexpr std::size_t max_waiting = 4096;

  private:
    void write(); // under the lock: buffer_ to the journal
    ensemble_journal& journal_;
    std::mutex mutex_;
    std::size_t next_ = 0;                       ///< the first member not yet written
    std::map<std::size_t, std::string> waiting_; ///< rows after next_, done early
    std::set<std::size_t> ahead_;                ///< rows after next_ written early
    std::string buffer_;
    std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

} // namespace varsym::cli
