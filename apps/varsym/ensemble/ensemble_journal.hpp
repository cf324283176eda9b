// apps/varsym/ensemble/ensemble_journal.hpp: the rows of an ensemble as they complete, kept on
// disk so that an ensemble killed at any instant and started again skips the members already
// done. Each process appends to its own journal, OUTPUT.journal (MPI rank R > 0:
// OUTPUT.journal.R), locked while it runs; OUTPUT.journal's lock is the ensemble's (held by the
// plain process or MPI rank 0 from before the journals are read until the output is
// committed), so that no two ensembles of one output run at once, whatever their launchers.
// A start reads every OUTPUT.journal* whose first line is this ensemble's (same model, members,
// scheme, steps...) and takes each complete row whose CRC-32 checks, once; a damaged or forged
// row is skipped (its member recomputed), and a row cut short by a kill is cut off. The output
// is written in member order from all journals when every member is done, and the journals are
// removed.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace varsym::cli {

class ensemble_journal {
  public:
    /// The journals of `output` for the ensemble described by `identity` (one line) with
    /// `members` members and rows of `fields` fields. Nothing is read yet.
    ensemble_journal(std::string output, const std::string& identity, std::size_t members,
                     std::size_t fields);
    ensemble_journal(const ensemble_journal&) = delete;
    ensemble_journal& operator=(const ensemble_journal&) = delete;
    ~ensemble_journal();

    /// Opens and locks this process's journal `output + suffix` (created if absent; nothing
    /// cut yet). Suffix ".journal" (the plain process, MPI rank 0) locks the whole ensemble:
    /// call it before any process reads. Throws usage_error if a running ensemble holds it.
    void lock(const std::string& suffix);
    /// Reads every journal of the output. Throws usage_error when one belongs to another
    /// ensemble (or to an older varsym), saying how to proceed.
    void read();
    /// Cuts this process's journal after its last complete row and writes its first line if
    /// it has none, after every process read the journals.
    void start();

    /// Whether member m's row was found in a journal by read().
    [[nodiscard]] bool done(std::size_t m) const { return !done_.empty() && done_[m]; }
    [[nodiscard]] std::size_t done_count() const { return done_count_; }
    /// Whether read() found a journal of this very ensemble (even one without rows).
    [[nodiscard]] bool found() const { return found_; }
    /// The rows read() skipped: damaged, forged or of a member out of range.
    [[nodiscard]] std::size_t rejected() const { return rejected_; }
    /// Appends rows (each ending in '\n'), each with its CRC-32; written through to the file at
    /// once (a SIGKILL after this returns loses none of them).
    void append(const std::string& rows);
    /// Calls emit(row) for each member in order, its row without checksum and '\n', merged
    /// from every journal of the output after a barrier where the other processes wrote theirs;
    /// memory independent of the members' count. Throws std::runtime_error if a member has no
    /// valid row.
    void merge(const std::function<void(std::string_view)>& emit) const;
    /// Removes every journal of the output (after the output was committed).
    void remove_all();

  private:
    void write_all(const std::string& text);
    std::string output_, path_, identity_;
    std::size_t members_, fields_;
    std::vector<bool> done_;
    std::size_t done_count_ = 0, rejected_ = 0;
    bool found_ = false;
    int fd_ = -1;
};

} // namespace varsym::cli
