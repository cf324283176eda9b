// varsym/optimize/solve.hpp: solving a transcription (optimal/nlp.hpp) with IPOPT (Wächter &
// Biegler 2006; Debian's coinor-libipopt-dev, its sparse linear solver MUMPS). The compiled part
// of varsym::optimal: link varsym::optimal. See docs/optimal_control.md.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "varsym/optimal/problem.hpp"

namespace varsym::optimal {

/// One IPOPT iteration as the progress callback sees it.
struct iteration {
    int number = 0;
    double cost = 0.0;
    double primal_infeasibility = 0.0; ///< max |g(x)|
    double dual_infeasibility = 0.0;
    bool restoration = false; ///< in IPOPT's feasibility restoration phase
};

/// How the Hessian of the Lagrangian is had: exact (the transcription's, where it has one),
/// limited-memory BFGS, or whichever of the two the transcription supports (exact first).
enum class hessian_kind { automatic, exact, limited_memory };

struct solver_options {
    double tolerance = 1e-10;            ///< IPOPT's tol (scaled KKT error)
    double constraint_tolerance = 1e-12; ///< IPOPT's constr_viol_tol (max |g(x)|)
    int max_iterations = 3000;
    hessian_kind hessian = hessian_kind::automatic;
    int print_level = 0; ///< IPOPT's own output on standard error (0: none; 5: its table)
    /// Called after every iteration; return false to stop (status::interrupted), keeping the
    /// iterate reached.
    std::function<bool(const iteration&)> progress;
    /// Polled at every evaluation and iteration: true stops the solve (status::interrupted)
    /// as soon as IPOPT returns, also during its derivative test, which reports no iterations.
    /// Must be cheap and thread-safe (a signal flag).
    std::function<bool()> stop;
    /// Checks the first derivatives against finite differences before solving (IPOPT's
    /// derivative_test), printing what it finds to standard error.
    bool derivative_test = false;
    /// An IPOPT options file ("name value" lines, IPOPT's ipopt.opt format) read after the
    /// options above, which it overrides; empty: none. IPOPT reads no other file (not even
    /// ./ipopt.opt). Throws std::invalid_argument if it cannot be read or IPOPT rejects it.
    /// What it loosens is not trusted blindly: check the answer (solution_check.hpp).
    std::string options_file;
};

/// The longest IPOPT options file read (a few lines are the norm).
inline constexpr std::uint64_t max_ipopt_options_bytes = std::uint64_t{1} << 20;

/// One entry of an IPOPT options file.
struct ipopt_option {
    std::string name, value;
    int line = 0;
};
/// The entries of an IPOPT options file's text ("name value" a line, '#' comments; `file`
/// names it in messages), each name checked against IPOPT's options: std::invalid_argument
/// "FILE:LINE: 'NAME' is not an IPOPT option". solve() reads solver_options::options_file
/// through it; a front end may call it first, before it creates any file.
std::vector<ipopt_option> parse_ipopt_options(const std::string& text, const std::string& file);

/// An upper estimate of a transcription's peak memory in a solve [bytes]: 300 (x/N)² N + 32 MB,
/// x/N the unknowns per step (IPOPT's and MUMPS's sparse factors dominate). Measured at N =
/// 8000: 4.7 KB a step for the pendulum (Simpson), 10.8 the acrobot, 16.3 Gauss 3, 39.7
/// Lobatto 5; the estimate is 1.3 to 2 times those.
std::uint64_t memory_estimate(const transcription& problem);

/// Solves `problem` from its start(), or from `start` when given (same size as start()).
/// With hessian_kind::automatic and a free final time, an exact-Hessian solve that ends
/// infeasible or failed (not stopped) is solved again with limited memory from the same start;
/// the result's message says so and its iterations are both solves'.
/// A transcription whose memory_estimate exceeds 80 % of the machine's memory is refused
/// before anything is sized (std::invalid_argument, saying how many steps fit).
nlp_result solve(const nlp& problem, const solver_options& options = {},
                 const vector* start = nullptr);

/// Mesh refinement: solves with N/2^levels steps first (at least 4), then each doubled N from
/// the previous solution (transcription::start_from), up to N. `make(n)` makes the
/// transcription of n steps. A far better start for the fine problem than the interpolated
/// boundary states, and cheaper: the coarse problems take most of the iterations. Stops at
/// the first level that does not converge (its result is returned). `iterations` per level.
struct refined {
    nlp_result result;
    std::unique_ptr<transcription> problem; ///< the finest solved (or the failed level's)
    std::vector<int> steps, iterations;
};
refined solve_refined(const std::function<std::unique_ptr<transcription>(int)>& make, int steps,
                      int levels, const solver_options& options = {});

} // namespace varsym::optimal
