// apps/varsym/checkpoint.hpp: the checkpoint file of `varsym run --checkpoint FILE`: everything
// the next step of a run depends on, written atomically, read back with version and checksum
// checks by `varsym run --resume FILE`.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "varsym/version.hpp"

namespace varsym::cli {

/// The version of varsym written into checkpoints; a checkpoint of another version is refused.
inline constexpr const char* varsym_version = VARSYM_VERSION_STRING;

/// The complete state of a run after step `step` of `steps`.
///
/// The steppers' next step depends on (q, p) and on the carries of the compensated summation
/// (solvers/compensated.hpp) only: every predictor starts from (q_j, p_j) alone and every cached
/// ∇V(q_j) is recomputed from q_j to the same bits. So (q, p, carries) and the run's options
/// (its arguments) make a resumed run bit-for-bit the run that never stopped.
struct checkpoint {
    std::string version = varsym_version;
    std::vector<std::string> args; ///< the arguments of `varsym run` (config file expanded)
    std::string output;            ///< absolute path of the CSV
    std::string scheme;            ///< e.g. "simpson", "gauss-3" (checked on resume)
    std::uint64_t step = 0;        ///< the last step taken
    std::uint64_t steps = 0;       ///< the run's total number of steps
    double h = 0.0;                ///< time step (checked bit for bit on resume)
    std::uint64_t csv_bytes = 0;   ///< length of the CSV holding the rows of steps 0 … step
    std::vector<double> q, p, carry_q, carry_p;
    std::int64_t newton_iterations = 0; ///< Newton statistics of steps 1 … step
    int newton_iterations_max = 0;
};

/// Writes ck to path atomically: to path + ".tmp", flushed and fsync'ed, then renamed over path
/// (and the directory fsync'ed), so a crash at any instant leaves the old or the new file.
/// Throws std::runtime_error on an I/O failure.
void write_checkpoint(const std::string& path, const checkpoint& ck);

/// Reads and verifies a checkpoint. Throws usage_error naming the file if it is not a varsym
/// checkpoint, was written by another varsym version, or fails its CRC-32 checksum (damaged).
checkpoint read_checkpoint(const std::string& path);

} // namespace varsym::cli
