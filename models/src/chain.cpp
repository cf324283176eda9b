// models/src/chain.cpp: n coupled nonlinear oscillators with fixed ends (the FPU-beta chain,
// problems/chain.hpp). Simpson's and Newmark's Newton systems are tridiagonal, so a step costs
// O(n); the other members of the family solve a dense (s n) x (s n) system.

#include <cmath>
#include <string>

#include "simulation_of.hpp"
#include "varsym/models/parameters.hpp"
#include "varsym/problems/chain.hpp"
#include "varsym/run/memory.hpp"

namespace varsym::models::defs {

namespace {

/// Refuses a chain whose steps would need more memory than the machine has, or a dense system
/// too large to solve in reasonable time (the family members other than simpson and newmark).
void check_size(int n, const scheme_spec& spec) {
    const bool dense = spec.kind != scheme_kind::simpson && spec.kind != scheme_kind::newmark;
    // About 300 bytes per mass (measured: 243 MB at n = 1e6 with Simpson), and a dense member's
    // Jacobian and its LU factors, 3 (s n)^2 doubles.
    const double sn = static_cast<double>(spec.degree) * n;
    const double need = 300.0 * n + (dense ? 24.0 * sn * sn : 0.0);
    const double have = physical_memory();
    if (beyond_memory(need, have))
        throw std::invalid_argument("n = " + std::to_string(n) + " with " + spec.label() +
                                    " needs about " +
                                    std::to_string(static_cast<long long>(need / 1e9)) +
                                    " GB, more than 80 % of this "
                                    "machine's " +
                                    std::to_string(static_cast<long long>(have / 1e9)) +
                                    " GB: use a smaller n" + (dense ? " or simpson/newmark" : ""));
    if (dense && n > 2000)
        throw std::invalid_argument(spec.label() + " solves a dense system of " +
                                    std::to_string(spec.degree) +
                                    " n unknowns a step; use n <= "
                                    "2000 with it, or simpson/newmark");
}

struct chain_parameters {
    double amplitude, beta, n;
};

} // namespace

model chain() {
    model m;
    m.name = "chain";
    m.summary = "n coupled nonlinear oscillators (FPU-beta, fixed ends), O(n) per step";
    m.description =
        "  L = sum_i qdot_i^2/2 - sum_{i=0..n} (r_i^2/2 + beta r_i^4/4), r_i = q_{i+1} - q_i,\n"
        "  q_0 = q_{n+1} = 0 (fixed ends), unit masses and springs. The default start is the\n"
        "  lowest linear mode q_i = A sin(pi i/(n+1)) at rest; q0/p0/v0 (n values) override it.\n"
        "  Schemes: every one. Simpson and Newmark cost O(n) a step (their Newton system is\n"
        "  tridiagonal); the other Lobatto and Gauss members solve a dense (s n) x (s n) system,\n"
        "  O((s n)^3) a step: keep n small with them (at most 2000). Conserved: energy.\n"
        "  No exact solution, no period.";
    m.dim = 64;
    m.coordinates = "q_1 ... q_n";
    const parameter_set<chain_parameters> set{
        {{&chain_parameters::amplitude,
          {.name = "amplitude", .value = 1.0, .doc = "amplitude A of the initial lowest mode"}},
         {&chain_parameters::beta,
          {.name = "beta", .value = 1.0, .doc = "quartic coupling beta", .lower = 0.0}},
         {&chain_parameters::n,
          {.name = "n",
           .value = 64,
           .doc = "number of moving masses (the dimension d)",
           .lower = 1,
           .upper = 1e7,
           .integer = true,
           .sets_dimension = true}}}};
    set.declare(m);
    m.dimension =
        set.dimension([](const chain_parameters& par) { return static_cast<int>(par.n); });
    m.time = 100.0;
    m.steps = 1000;
    m.ensemble_time = 100.0;
    m.ensemble_steps = 1000;
    m.ensemble_note = "Energy sharing between modes: --grid amplitude=0.5:2:16; n for all\n"
                      "  members: --set n=16.";
    m.make = set.make([](const chain_parameters& par, const start& s) {
        const int n = static_cast<int>(par.n);
        const chain::system sys(n, par.beta);
        phase_state<dynamic> x0 = sys.lowest_mode(par.amplitude);
        auto given = [n](const std::vector<double>& g) {
            return vec<dynamic>(Eigen::Map<const vec<dynamic>>(g.data(), n));
        };
        if (!s.q0.empty()) x0.q = given(s.q0);
        if (!s.v0.empty()) x0.p = given(s.v0); // unit masses: p = qdot
        if (!s.p0.empty()) x0.p = given(s.p0);
        return detail::make_problem(x0, 0.0, [sys, x0](const step_options& o) {
            check_size(sys.dimension(), o.spec);
            return detail::simulate_family(
                sys, x0, o,
                detail::column_set{{"energy"},
                                   [sys](double, const phase_state<dynamic>& x, const auto&,
                                         double* out) { out[0] = sys.energy(x); }});
        });
    });
    return m;
}

} // namespace varsym::models::defs
