// varsym/models/input_file.hpp: the identity of a file a model was read from (a robot's URDF):
// its content digest, which a checkpoint or an ensemble journal records beside its absolute path
// so that a resumed run refuses a changed input. Reading: varsym/run/input_file.hpp.
#pragma once

#include <string>
#include <string_view>

#include "varsym/run/input_file.hpp"

namespace varsym::models {

using varsym::input_error;
using varsym::read_input_file;

/// The digest of a file's content as checkpoints record it: its CRC-32 and its length,
/// "crc32:1a2b3c4d,bytes:5120".
[[nodiscard]] std::string content_digest(std::string_view content);

} // namespace varsym::models
