// apps/varsym/models/model_chain.cpp: `--model chain`, n coupled nonlinear oscillators (FPU-beta) with
// fixed ends; Newton's linear solve is tridiagonal, so a step costs O(n).
#include <unistd.h>

#include <memory>

#include "model_run.hpp"
#include "varsym/problems/chain.hpp"
#include "varsym/schemes/scheme_kind.hpp"

namespace varsym::cli {

namespace {
struct chain_parameters {
    int n = 64;
    double beta = 1.0;
    double amplitude = 1.0;
};
} // namespace

model make_chain_model() {
    auto par = std::make_shared<chain_parameters>();
    model m;
    m.name = "chain";
    m.summary = "n coupled nonlinear oscillators (FPU-beta, fixed ends), O(n) per step";
    m.description =
        "  L = sum_i qdot_i^2/2 - sum_{i=0..n} (r_i^2/2 + beta r_i^4/4), r_i = q_{i+1} - q_i,\n"
        "  q_0 = q_{n+1} = 0 (fixed ends), unit masses and springs. Parameters: --n (64),\n"
        "  --beta (1), --amplitude A (1): the default start is the lowest linear mode\n"
        "  q_i = A sin(pi i/(n+1)) at rest; --q0/--p0/--v0 (n values each) override it.\n"
        "  Schemes: every one. Simpson and Newmark cost O(n) a step (their Newton system is\n"
        "  tridiagonal); the other Lobatto and Gauss members solve a dense (s n) x (s n) system,\n"
        "  O((s n)^3) a step: keep n small with them. Conserved: energy.\n"
        "  No exact solution, no period: default --time 100 --steps 1000.";
    m.options = {"--n", "--beta", "--amplitude"};
    m.add_options = [par](CLI::App& cmd) {
        cmd.add_option("--n", par->n, "chain: number of moving masses")
            ->transform(positive_integer)
            ->capture_default_str();
        cmd.add_option("--beta", par->beta, "chain: quartic coupling beta")
            ->transform(non_negative_number)
            ->capture_default_str();
        cmd.add_option("--amplitude", par->amplitude, "chain: amplitude of the initial lowest mode")
            ->transform(finite_number)
            ->capture_default_str();
    };
    m.run = [par](const run_setup& s) {
        if (par->n > static_cast<int>(max_checkpoint_dimension))
            throw usage_error("--n is at most 1e7");
        // Memory: about 300 bytes per mass (measured: 243 MB at n = 1e6 with Simpson), and a
        // dense member's Jacobian and its LU factors, 3 (s n)^2 doubles.
        const double sn = static_cast<double>(s.spec.degree) * par->n;
        const bool dense =
            s.spec.kind != scheme_kind::simpson && s.spec.kind != scheme_kind::newmark;
        const double need = 300.0 * par->n + (dense ? 24.0 * sn * sn : 0.0);
        const double have = static_cast<double>(::sysconf(_SC_PHYS_PAGES)) *
                            static_cast<double>(::sysconf(_SC_PAGE_SIZE));
        if (have > 0.0 && need > 0.8 * have)
            throw usage_error("--model chain --n " + std::to_string(par->n) + " with " +
                              s.spec.label() + " needs about " +
                              std::to_string(static_cast<long long>(need / 1e9)) +
                              " GB, more than 80 % of this machine's " +
                              std::to_string(static_cast<long long>(have / 1e9)) +
                              " GB: use a smaller --n" + (dense ? " or simpson/newmark" : ""));
        const chain::system sys(par->n, par->beta);
        const int d = par->n;
        const auto mode = sys.lowest_mode(par->amplitude);
        phase_state<dynamic> x0;
        x0.q = initial_vector(s.q0, "--q0", d, "q_1 ... q_n", mode.q);
        x0.p = initial_vector(s.v0, "--v0", d, "dq_1/dt ... dq_n/dt", mode.p);
        x0.p = initial_vector(s.p0, "--p0", d, "p_1 ... p_n", x0.p);
        const run_plan plan = plan_steps(s, "chain", 0.0, 0, 100.0, 1000);
        if (s.spec.kind != scheme_kind::simpson && s.spec.kind != scheme_kind::newmark &&
            par->n > 2000)
            throw usage_error("--model chain with " + s.spec.label() +
                              " solves a dense system of " + std::to_string(s.spec.degree) +
                              " n unknowns a step; use n <= 2000 with it, or simpson/newmark");
        stream_trajectory<dynamic>(
            s, plan, x0, ",energy",
            [&](auto&& f) { return with_stepper(s.spec, sys, plan.h, s.newton, f); },
            [&](double, const phase_state<dynamic>& x, std::string& line) {
                append_values(line, {sys.energy(x)});
            });
    };
    return m;
}

} // namespace varsym::cli
