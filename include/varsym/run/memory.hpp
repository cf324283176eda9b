// varsym/run/memory.hpp: how much memory a run may plan to use: the machine's physical memory
// and the share of it (80 %) beyond which varsym refuses work up front, with a message saying
// what would fit, rather than let the system swap or kill it (a long chain's dense Jacobian, a
// typed Lagrangian's symbolic derivatives, an optimal control problem's KKT factors).
#pragma once

#include <unistd.h>

namespace varsym {

/// This machine's physical memory [bytes], or 0 where the system does not say.
inline double physical_memory() {
    const long pages = ::sysconf(_SC_PHYS_PAGES), size = ::sysconf(_SC_PAGE_SIZE);
    return pages > 0 && size > 0 ? static_cast<double>(pages) * static_cast<double>(size) : 0.0;
}

/// The share of physical memory a planned run may use.
inline constexpr double memory_share = 0.8;

/// Whether `bytes` exceeds that share of `have` (physical_memory(); unknown: never).
inline bool beyond_memory(double bytes, double have) {
    return have > 0.0 && bytes > memory_share * have;
}

} // namespace varsym
