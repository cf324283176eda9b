// optimal/src/solve_detail.hpp: one IPOPT run (ipopt_solve.cpp) under optimal::solve
// (solve.cpp), which holds the process's lock and chooses the Hessian.
#pragma once

#include "varsym/optimize/solve.hpp"

namespace varsym::optimal::detail {

/// Refuses a transcription whose memory_estimate exceeds 80 % of the machine's memory.
void check_solve_memory(const nlp& problem);
/// One IPOPT solve of `problem` with its exact Hessian or limited memory. The caller holds the
/// process's solve lock.
nlp_result run_ipopt(const nlp& problem, const solver_options& options, const vector* start,
                     bool exact);

} // namespace varsym::optimal::detail
