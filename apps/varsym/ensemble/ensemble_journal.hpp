// apps/varsym/ensemble/ensemble_journal.hpp: the rows of an ensemble as they complete, kept on disk so that
// an ensemble killed at any instant and started again skips the members already done. Each
// process appends to its own journal, OUTPUT.journal (or OUTPUT.journal.R for MPI rank R),
// locked while it runs; a start reads every OUTPUT.journal* whose first line is this ensemble's
// (same model, members, scheme, steps...), takes each complete row once, and cuts its own file
// after its last complete row. The rows are the output's rows; the output is written in member
// order from all journals when every member is done, and the journals are removed.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace varsym::cli {

class ensemble_journal {
  public:
    /// Reads every journal of `output` for the ensemble described by `identity` (one line) with
    /// `members` members and rows of `fields` fields. Throws usage_error when a journal belongs
    /// to another ensemble, saying how to proceed.
    ensemble_journal(const std::string& output, const std::string& identity, std::size_t members,
                     std::size_t fields);
    /// Opens this process's journal `output + suffix` for appending (created, or cut after its
    /// last complete row), after every process read the journals. Throws usage_error if a
    /// running ensemble holds it.
    void open(const std::string& suffix);
    ensemble_journal(const ensemble_journal&) = delete;
    ensemble_journal& operator=(const ensemble_journal&) = delete;
    ~ensemble_journal();

    /// Whether member m's row was found in a journal at the start.
    [[nodiscard]] bool done(std::size_t m) const { return done_[m] != 0; }
    [[nodiscard]] std::size_t done_count() const { return done_count_; }
    /// Appends rows (each ending in '\n'); written through to the file at once (a SIGKILL after
    /// this returns loses none of them).
    void append(const std::string& rows);
    /// Every journal of the output, rows sorted by member (one per member), after a barrier
    /// where other processes wrote theirs: the output's body. Throws std::runtime_error if a
    /// member is missing.
    [[nodiscard]] std::string merged_rows() const;
    /// Removes every journal of the output (after the output was committed).
    void remove_all();

  private:
    std::string output_, path_, identity_;
    std::size_t members_, fields_;
    std::vector<char> done_;
    std::size_t done_count_ = 0;
    int fd_ = -1;
};

} // namespace varsym::cli
