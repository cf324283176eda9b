// varsym/models/checkpoint.hpp: the checkpoint format of a run: everything its next step depends
// on (the run state of run/state.hpp and the run's identity), as text with one "key value" line
// each, doubles as C99 hexadecimal floats (exact), and a CRC-32 of everything before the last
// line. `varsym run --checkpoint` writes it (atomically, through the tool's file safety) and
// `--resume` reads it; a program of its own can save and restore a simulation with it.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "varsym/run/state.hpp"
#include "varsym/version.hpp"

namespace varsym::models {

/// The version of varsym written into checkpoints; a checkpoint of another version is refused.
inline constexpr const char* checkpoint_version = VARSYM_VERSION_STRING;

/// The largest dimension a checkpoint may hold (the largest model, the chain's n), and so the
/// longest valid checkpoint: reads are bounded by it.
inline constexpr std::uint64_t max_checkpoint_dimension = 10'000'000;
inline constexpr std::uint64_t max_checkpoint_bytes = (1U << 20) + 100 * max_checkpoint_dimension;

/// The complete state of a run after step `step` of `steps`.
///
/// The steppers' next step depends on (q, p), on the carries of the compensated summation
/// (solvers/compensated.hpp) and on the stepper's history (run_state::history: the previous
/// step's increments for the predictor `previous`, the kept Jacobian's point for the simplified
/// iteration; empty otherwise); every cached ∇V(q_j) and kept Jacobian is recomputed to the
/// same bits. So these and the run's options (its arguments) make a resumed run bit-for-bit the
/// run that never stopped. A rigid body's q and p hold its R (9 values) and Π (3).
struct checkpoint {
    std::string version = checkpoint_version;
    std::vector<std::string> args; ///< the arguments of the run (`varsym run`'s, config expanded)
    /// A file the run's model was read from (a robot's URDF): its absolute path and its
    /// content_digest (input_file.hpp). A resume refuses a file that changed or moved.
    struct input_file {
        std::string path, digest;
    };
    std::vector<input_file> inputs;
    std::string output;          ///< absolute path of the CSV
    std::string scheme;          ///< e.g. "simpson", "gauss-3" (checked on resume)
    std::uint64_t step = 0;      ///< the last step taken
    std::uint64_t steps = 0;     ///< the run's total number of steps
    double h = 0.0;              ///< time step (checked bit for bit on resume)
    std::uint64_t csv_bytes = 0; ///< length of the CSV holding the rows of steps 0 … step
    std::uint32_t csv_crc32 = 0; ///< CRC-32 of those csv_bytes bytes
    std::vector<double> q, p, carry_q, carry_p, history;
    std::int64_t newton_iterations = 0; ///< Newton statistics of steps 1 … step
    int newton_iterations_max = 0;

    /// The run state it holds (d = the length of q and p); run_state::restore continues it.
    [[nodiscard]] run_state<dynamic> state() const;
    /// Sets q, p, the carries, the history, the step and the statistics from a run state.
    void set_state(const run_state<dynamic>& r);
};

/// A checkpoint that cannot be read: not one, another version's, or damaged (its CRC-32 fails,
/// it is cut short, its fields are inconsistent). The message names the file.
class checkpoint_error : public std::invalid_argument {
  public:
    using std::invalid_argument::invalid_argument;
};

/// The checkpoint as its file holds it, ending in its CRC-32 line.
std::string checkpoint_text(const checkpoint& ck);
/// Whether `head` is a prefix of a checkpoint's first line (or empty): what a write killed at
/// any moment leaves in a temporary file.
bool looks_like_checkpoint_start(const std::string& head);
/// The checkpoint in `text` (the contents of the file `name`, for messages), verified: its
/// magic line, its version (another version's is refused, naming both), its CRC-32 and its
/// fields' consistency. Throws checkpoint_error.
checkpoint parse_checkpoint(const std::string& text, const std::string& name);

} // namespace varsym::models
