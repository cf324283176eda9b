// apps/varsym/ensemble/ensemble_processes.cpp: MPI where built in (VARSYM_HAVE_MPI) and launched by
// an MPI launcher; a group of one otherwise.
#include "ensemble/ensemble_processes.hpp"

#include <algorithm>
#include <cstdlib>

#include "varsym/run/cpus.hpp"

#ifdef VARSYM_HAVE_MPI
#include <mpi.h>
#endif

namespace varsym::cli {

unsigned process_group::default_threads() const {
    const unsigned cores = available_cpus();
    // The machine's CPUs (at most the quota) shared among its ranks, and no more than this
    // rank's own mask: a launcher may already have pinned each rank to its share.
    for (const char* v : {"OMPI_COMM_WORLD_LOCAL_SIZE", "MPI_LOCALNRANKS"})
        if (const char* s = std::getenv(v); s != nullptr && size_ > 1) {
            const long local = std::strtol(s, nullptr, 10);
            if (local > 0)
                return std::max(1U, std::min(cores, machine_cpus() / static_cast<unsigned>(local)));
        }
    return cores;
}

#ifdef VARSYM_HAVE_MPI
namespace {
/// Started by mpirun/mpiexec (Open MPI, MPICH, Slurm's PMI): then MPI_Init joins the job; a
/// plain `varsym` never initialises MPI (no singleton start, no daemon).
bool launched_by_mpi() {
    for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "MPI_LOCALNRANKS"})
        if (std::getenv(v) != nullptr) return true;
    return false;
}
} // namespace

process_group::process_group() {
    if (!launched_by_mpi()) return;
    int initialized = 0;
    MPI_Initialized(&initialized);
    if (initialized == 0) MPI_Init(nullptr, nullptr);
    mpi_ = true;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

process_group::~process_group() {
    if (mpi_) MPI_Finalize();
}

void process_group::barrier() const {
    if (mpi_) MPI_Barrier(MPI_COMM_WORLD);
}

long long process_group::max(long long v) const {
    long long r = v;
    if (mpi_) MPI_Allreduce(&v, &r, 1, MPI_LONG_LONG, MPI_MAX, MPI_COMM_WORLD);
    return r;
}

long long process_group::sum(long long v) const {
    long long r = v;
    if (mpi_) MPI_Allreduce(&v, &r, 1, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
    return r;
}

void process_group::abort(int code) const {
    if (mpi_ && size_ > 1) MPI_Abort(MPI_COMM_WORLD, code);
}

std::string mpi_version() {
    char v[MPI_MAX_LIBRARY_VERSION_STRING];
    int n = 0;
    MPI_Get_library_version(v, &n);
    std::string s(v, static_cast<std::size_t>(n));
    return s.substr(0, s.find('\n'));
}
#else
process_group::process_group() = default;
process_group::~process_group() = default;
void process_group::barrier() const {}
long long process_group::max(long long v) const {
    return v;
}
long long process_group::sum(long long v) const {
    return v;
}
void process_group::abort(int) const {}
std::string mpi_version() {
    return {};
}
#endif

} // namespace varsym::cli
