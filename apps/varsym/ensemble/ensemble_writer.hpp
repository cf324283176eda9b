// apps/varsym/ensemble/ensemble_writer.hpp: rows of members on their way to a file, in member
// order. Threads finish members out of order; a row waits here until every member before it
// has finished. An ensemble's journal so holds long runs of rows in increasing member order,
// which the final merge (ensemble_journal::merge) streams with little memory; a section's
// output is written as its members finish, not held to the end.
#pragma once

#include <chrono>
#include <cstddef>
#include <functional>
#include <map>
#include <mutex>
#include <set>
#include <string>

namespace varsym::cli {

class ordered_writer {
  public:
    /// Rows go to `sink` every 0.25 s or 64 KiB. More than `max_waiting` rows waiting behind a
    /// slow member are written at once, out of order (a journal: a new run begins); 0: rows
    /// always wait (a section's output, which has no merge after it).
    ordered_writer(std::function<void(const std::string&)> sink, std::size_t max_waiting)
        : sink_(std::move(sink)), max_waiting_(max_waiting) {}
    /// The k-th member (counting from 0, in increasing member order) is done, with its rows
    /// (each ending in '\n'; empty for a member skipped or without rows).
    void done(std::size_t k, std::string row);
    /// Some rows of the k-th member, more to come (done() ends it): written at once when every
    /// member before it is done, so that a member with many rows streams through (a section's
    /// millions of crossings), else kept until then.
    void partial(std::size_t k, std::string rows);
    /// Writes every row done, in member order (at the end, or when the work stops).
    void flush_all();

  private:
    void write(); // under the lock: buffer_ to the sink
    std::function<void(const std::string&)> sink_;
    std::size_t max_waiting_;
    std::mutex mutex_;
    std::size_t next_ = 0;                       ///< the first member not yet written
    std::map<std::size_t, std::string> waiting_; ///< rows after next_, done early
    std::map<std::size_t, std::string> started_; ///< partial rows of members after next_
    std::set<std::size_t> ahead_;                ///< rows after next_ written early
    std::string buffer_;
    std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

} // namespace varsym::cli
