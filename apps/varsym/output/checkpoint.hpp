// apps/varsym/output/checkpoint.hpp: the checkpoint file of `varsym run --checkpoint FILE`: everything
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
/// The steppers' next step depends on (q, p), on the carries of the compensated summation
/// (solvers/compensated.hpp) and on the stepper's history (run_state::history: the previous
/// step's increments for --predictor previous, the kept Jacobian's point for --iteration
/// simplified; empty otherwise); every cached ∇V(q_j) and kept Jacobian is recomputed to the
/// same bits. So these and the run's options (its arguments) make a resumed run bit-for-bit the
/// run that never stopped.
struct checkpoint {
    std::string version = varsym_version;
    std::vector<std::string> args; ///< the arguments of `varsym run` (config file expanded)
    std::string output;            ///< absolute path of the CSV
    std::string scheme;            ///< e.g. "simpson", "gauss-3" (checked on resume)
    std::uint64_t step = 0;        ///< the last step taken
    std::uint64_t steps = 0;       ///< the run's total number of steps
    double h = 0.0;                ///< time step (checked bit for bit on resume)
    std::uint64_t csv_bytes = 0;   ///< length of the CSV holding the rows of steps 0 … step
    std::uint32_t csv_crc32 = 0;   ///< CRC-32 of those csv_bytes bytes (FILE.part is the run's)
    std::vector<double> q, p, carry_q, carry_p, history;
    std::int64_t newton_iterations = 0; ///< Newton statistics of steps 1 … step
    int newton_iterations_max = 0;
};

/// The largest dimension a checkpoint may hold (the tool's largest model, --model chain --n),
/// and so the longest valid checkpoint file: reads are bounded by it.
inline constexpr std::uint64_t max_checkpoint_dimension = 10'000'000;
inline constexpr std::uint64_t max_checkpoint_bytes = (1U << 20) + 100 * max_checkpoint_dimension;

/// Writes ck to path atomically through path + ".tmp" (files.hpp: write_exclusively): over the
/// previous checkpoint if `replace`, else only where no file is (a new run's first checkpoint,
/// the last good state of a failed run). Throws std::runtime_error on an I/O failure.
void write_checkpoint(const std::string& path, const checkpoint& ck, bool replace);

/// Whether `path` begins as a varsym checkpoint does, or with a part of that beginning, or is
/// empty: what a checkpoint write killed at any moment leaves in CK.tmp.
bool looks_like_checkpoint(const std::string& path);

/// Reads and verifies a checkpoint. Throws usage_error naming the file if it is not a regular
/// file, longer than max_checkpoint_bytes, not a varsym checkpoint, was written by another varsym
/// version, or fails its CRC-32 checksum (damaged).
checkpoint read_checkpoint(const std::string& path);

} // namespace varsym::cli
