// optimal/src/solve.cpp: optimal::solve, one solve at a time in the process with the Hessian
// chosen (solve.hpp), and mesh refinement over it (solve_refined).
#include <mutex>
#include <stdexcept>
#include <string>

#include "solve_detail.hpp"

namespace varsym::optimal {

namespace {

/// Whether the automatic choice solves again with limited memory: a free final time whose
/// exact-Hessian solve ended infeasible or failed, not stopped by the caller (its evaluations
/// then fail too). Not at the iteration limit: the caller's limit holds for the whole solve.
bool retry_with_limited_memory(const nlp& problem, const solver_options& options,
                               const nlp_result& out) {
    const auto* t = dynamic_cast<const transcription*>(&problem);
    return options.hessian == hessian_kind::automatic && t != nullptr && t->problem().free_time &&
           (out.verdict == status::infeasible || out.verdict == status::failed) &&
           !(options.stop && options.stop());
}

} // namespace

nlp_result solve(const nlp& problem, const solver_options& options, const vector* start) {
    if (options.hessian == hessian_kind::exact && !problem.has_hessian())
        throw std::invalid_argument("this transcription gives no exact Hessian: choose the "
                                    "limited-memory approximation");
    const bool exact = options.hessian != hessian_kind::limited_memory && problem.has_hessian();
    detail::check_solve_memory(problem);
    // One IPOPT solve at a time in the process: the sequential MUMPS that Debian's IPOPT links
    // keeps global state (its MPI stub, its load-balancing arrays), and two solves on two
    // threads at once crash the process ("PB allocation in DMUMPS_LOAD_INIT", SIGSEGV: 8 runs in
    // 8 from Python threads). Threads that optimise wait here for each other.
    static std::mutex one_solve;
    const std::lock_guard<std::mutex> only_this_one(one_solve);
    nlp_result out = detail::run_ipopt(problem, options, start, exact);
    // A free final time: its exact Hessian is 2-6 times faster where it converges (a robot's
    // and the cart-pole's minimum time), but the pendulum's pumping swing-up at N = 20 and 40
    // ended there at a point of local infeasibility (spurious roots of too coarse steps) where
    // limited memory's positive definite model solved it (docs/optimal_control.md, "Default by
    // measurement"). The automatic choice then solves again with limited memory from the same
    // start, its iterations numbered from 0 again in the progress callback.
    if (exact && retry_with_limited_memory(problem, options, out)) {
        const int first = out.iterations;
        const std::string why = std::string(status_name(out.verdict)) + " (" + out.message + ")";
        out = detail::run_ipopt(problem, options, start, false);
        out.iterations += first;
        out.message += "; by the limited-memory Hessian, after the exact one ended " + why +
                       " in " + std::to_string(first) + " iterations";
    }
    return out;
}

refined solve_refined(const std::function<std::unique_ptr<transcription>(int)>& make, int steps,
                      int levels, const solver_options& options) {
    std::vector<int> sizes{steps};
    while (static_cast<int>(sizes.size()) <= levels && sizes.back() / 2 >= 4)
        sizes.push_back(sizes.back() / 2);
    refined out;
    std::unique_ptr<trajectory> previous;
    for (auto n = sizes.rbegin(); n != sizes.rend(); ++n) {
        out.problem = make(*n);
        const vector x0 = previous ? out.problem->start_from(*previous) : out.problem->start();
        out.result = solve(*out.problem, options, &x0);
        out.steps.push_back(*n);
        out.iterations.push_back(out.result.iterations);
        if (!out.result.converged()) break;
        previous = std::make_unique<trajectory>(out.problem->unpack(out.result));
    }
    return out;
}

} // namespace varsym::optimal
