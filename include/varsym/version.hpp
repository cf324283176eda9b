// varsym/version.hpp: the version of the varsym library. Kept in the source tree so that
// <varsym/varsym.hpp> compiles with -I include alone; CMake refuses to configure when it
// disagrees with project(varsym VERSION ...) in CMakeLists.txt.
#pragma once

#define VARSYM_VERSION_MAJOR 0
#define VARSYM_VERSION_MINOR 3
#define VARSYM_VERSION_PATCH 0
#define VARSYM_VERSION_STRING "0.3.0"

namespace varsym {
inline constexpr int version_major = VARSYM_VERSION_MAJOR;
inline constexpr int version_minor = VARSYM_VERSION_MINOR;
inline constexpr int version_patch = VARSYM_VERSION_PATCH;
inline constexpr const char* version_string = VARSYM_VERSION_STRING;
} // namespace varsym
