// apps/varsym/ensemble/ensemble_processes.hpp: the processes that share an ensemble. Under mpirun
// (in a build with MPI, VARSYM_MPI), every rank takes the members m with m mod size = rank and
// keeps its own journal; rank 0 writes the output once all are done. Otherwise one process does
// all.
#pragma once

#include <string>

namespace varsym::cli {

class process_group {
  public:
    /// Joins MPI when the process was started by an MPI launcher (and MPI is built in).
    process_group();
    process_group(const process_group&) = delete;
    process_group& operator=(const process_group&) = delete;
    ~process_group();

    [[nodiscard]] int rank() const { return rank_; }
    [[nodiscard]] int size() const { return size_; }
    /// The threads each process runs by default: the CPUs it may use (varsym/run/cpus.hpp), or
    /// with ranks the machine's CPUs shared among its ranks (Open MPI's
    /// OMPI_COMM_WORLD_LOCAL_SIZE, MPICH's MPI_LOCALNRANKS), at most the rank's own mask.
    [[nodiscard]] unsigned default_threads() const;
    /// Waits for every process.
    void barrier() const;
    /// The largest of every process's value (a failure anywhere stops all alike).
    [[nodiscard]] long long max(long long v) const;
    /// Sums every process's value.
    [[nodiscard]] long long sum(long long v) const;
    /// Ends every process at once after a failure on one (MPI_Abort); returns otherwise.
    void abort(int code) const;

  private:
    int rank_ = 0, size_ = 1;
    [[maybe_unused]] bool mpi_ = false; // unused in a build without MPI
};

/// Whether this build has MPI ("" if not, else the library's version line).
std::string mpi_version();

} // namespace varsym::cli
