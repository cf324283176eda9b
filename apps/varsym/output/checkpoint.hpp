// apps/varsym/output/checkpoint.hpp: the checkpoint file of `varsym run --checkpoint FILE`: the
// models layer's format (varsym/models/checkpoint.hpp), written atomically through the tool's
// file safety and read back with its version and checksum checks by `varsym run --resume FILE`.
#pragma once

#include <string>

#include "varsym/models/checkpoint.hpp"

namespace varsym::cli {

using checkpoint = models::checkpoint;
using models::max_checkpoint_bytes;
using models::max_checkpoint_dimension;
/// The version of varsym written into checkpoints; a checkpoint of another version is refused.
inline constexpr const char* varsym_version = models::checkpoint_version;

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
