// apps/varsym/optimize_memory.cpp: glibc's malloc thresholds for the program varsym-optimize
// alone (this file is linked into no library and not into the Python module; the robots'
// optimal control benchmark links it too, to time what `varsym optimize` does). MUMPS
// allocates its factorisation workspace afresh for every factorisation of IPOPT's KKT matrix.
// Above glibc's mmap threshold (dynamic, at most 32 MiB) such a block is a new mapping,
// released at its free, and the kernel zeroes every page of the next one on its first touch;
// below it, the heap's top is handed back once more than the trim threshold is free. With both
// at 1 GiB (glibc 2.36 takes it) the workspace stays mapped from one factorisation to the next.
// Measured on top of mumps_mem_percent 100 (ipopt_solve.cpp), `varsym optimize` whole, 3 rounds
// interleaved: the iiwa with gauss-2 at N = 50 from 0.40 s to 0.33 s (7 900 page faults to
// 2 900); large problems, whose workspace the smaller percentage already keeps, unchanged (a
// 10-link chain at N = 200: 1.49 s, 1.47 s). The price is a process that keeps its peak heap
// until it exits.
#include <cstdlib> // defines __GLIBC__ on glibc

#if defined(__GLIBC__)
#include <malloc.h>

namespace {

[[maybe_unused]] const int heap_kept = [] {
    constexpr int gib = 1 << 30;
    // Each on its own: an older glibc that refuses the first still takes the second.
    const int mapped = mallopt(M_MMAP_THRESHOLD, gib);
    const int trimmed = mallopt(M_TRIM_THRESHOLD, gib);
    return mapped + trimmed;
}();

} // namespace
#endif
