// apps/varsym/models/model_oscillator.cpp: `--model oscillator`, d-dimensional, exact by normal modes.
#include <cmath>
#include <memory>

#include "model_run.hpp"
#include "varsym/problems/oscillator.hpp"

namespace varsym::cli {

namespace {

/// A d×d matrix from 1 value (times the identity), d values (diagonal) or d² (row by row).
Eigen::MatrixXd square_matrix(const std::vector<double>& v, int d, const char* option) {
    const auto n = static_cast<int>(v.size());
    if (n == 1) return v[0] * Eigen::MatrixXd::Identity(d, d);
    if (n == d) return Eigen::Map<const Eigen::VectorXd>(v.data(), d).asDiagonal();
    if (n == d * d)
        return Eigen::Map<
            const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(v.data(),
                                                                                          d, d);
    throw usage_error(std::string(option) + " needs 1, " + std::to_string(d) + " or " +
                      std::to_string(d * d) + " values for --dim " + std::to_string(d) + ", got " +
                      std::to_string(n));
}

struct oscillator_parameters {
    int dim = 2;
    std::vector<double> mass{1.0};
    std::vector<double> stiffness{}; ///< empty: the default coupled pair below
};

} // namespace

model make_oscillator_model() {
    auto par = std::make_shared<oscillator_parameters>();
    model m;
    m.name = "oscillator";
    m.summary =
        "d-dimensional harmonic oscillator with mass matrix M and stiffness K, exact solution";
    m.description =
        "  L = (1/2) qdot^T M qdot - (1/2) q^T K q, M and K symmetric positive definite.\n"
        "  Parameters: --dim d (2); --mass-matrix and --stiffness-matrix as 1 value (times the\n"
        "  identity), d values (diagonal) or d*d values (row by row). Defaults: M = I and\n"
        "  K = (2 pi)^2 [[2, -1], [-1, 2]] for d = 2 (two unit masses between three springs),\n"
        "  else K = (2 pi)^2 I. Initial state --q0 (1, 0, ...), --p0 (0) or --v0.\n"
        "  Conserved: energy. Exact solution: yes, by normal modes. Period: the slowest mode's,\n"
        "  2 pi / omega_min; default 50 steps per period.";
    m.options = {"--dim", "--mass-matrix", "--stiffness-matrix"};
    m.add_options = [par](CLI::App& cmd) {
        cmd.add_option("--dim", par->dim, "oscillator: dimension d")
            ->transform(positive_integer)
            ->capture_default_str();
        cmd.add_option("--mass-matrix", par->mass, "oscillator: M (1, d or d*d values)")
            ->transform(finite_number)
            ->delimiter(',');
        cmd.add_option("--stiffness-matrix", par->stiffness, "oscillator: K (1, d or d*d values)")
            ->transform(finite_number)
            ->delimiter(',');
    };
    m.run = [par](const run_setup& s) {
        const int d = par->dim;
        if (d > 10000)
            throw usage_error("--dim " + std::to_string(d) +
                              " is too large for dense M and K (at most 10000)");
        const double w2 = 4.0 * std::numbers::pi * std::numbers::pi;
        const Eigen::MatrixXd mass = square_matrix(par->mass, d, "--mass-matrix");
        Eigen::MatrixXd k = w2 * Eigen::MatrixXd::Identity(d, d);
        if (!par->stiffness.empty())
            k = square_matrix(par->stiffness, d, "--stiffness-matrix");
        else if (d == 2)
            k << 2 * w2, -w2, -w2, 2 * w2;
        oscillator::system sys = [&] {
            try {
                return oscillator::make_system(mass, k);
            } catch (const std::invalid_argument& e) {
                throw usage_error(std::string("oscillator: ") + e.what());
            }
        }();
        phase_state<dynamic> x0;
        x0.q = initial_vector(s.q0, "--q0", d, "q_1 ... q_d", vec<dynamic>::Unit(d, 0));
        x0.p = vec<dynamic>::Zero(d);
        if (!s.v0.empty()) x0.p = mass * initial_vector(s.v0, "--v0", d, "dq_1/dt ... dq_d/dt", {});
        x0.p = initial_vector(s.p0, "--p0", d, "p_1 ... p_d", x0.p);
        const oscillator::exact_solution exact(mass, k, x0);
        const run_plan plan = plan_steps(s, "oscillator", exact.period(), 50, 0.0, 0);
        stream_trajectory<dynamic>(
            s, plan, x0, ",energy," + state_columns(d, "_exact"),
            [&](auto&& f) { return with_stepper(s.spec, sys, plan.h, s.newton, f); },
            [&](double t, const phase_state<dynamic>& x, std::string& line) {
                const auto ref = exact.at(t);
                append_values(line, {sys.energy(x)});
                for (auto* v : {&ref.q, &ref.p})
                    for (Eigen::Index i = 0; i < d; ++i)
                        append_values(line, {(*v)(i)});
            });
    };
    return m;
}

// Here, because this translation unit compiles every scheme's stepper for the oscillator already.
bool unit_oscillator_step(const scheme_spec& spec, double z, phase_state<1>& x) {
    static const oscillator::system sys =
        oscillator::make_system(Eigen::MatrixXd::Ones(1, 1), Eigen::MatrixXd::Ones(1, 1));
    return with_stepper(spec, sys, z, newton_options{}, [&](auto& stepper) {
        phase_state<dynamic> y{x.q, x.p};
        const bool ok = stepper.step(y).converged;
        x = phase_state<1>{vec<1>{y.q(0)}, vec<1>{y.p(0)}};
        return ok;
    });
}

} // namespace varsym::cli
