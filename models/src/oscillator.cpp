// models/src/oscillator.cpp: the d-dimensional harmonic oscillator L = q'ᵀMq'/2 − qᵀKq/2 with its
// exact solution by normal modes (problems/oscillator.hpp).
#include <numbers>
#include <string>

#include "simulation_of.hpp"
#include "varsym/models/parameters.hpp"
#include "varsym/problems/oscillator.hpp"

namespace varsym::models::defs {

namespace {

/// A d×d matrix from 1 value (times the identity), d values (diagonal) or d² (row by row).
Eigen::MatrixXd square_matrix(const std::vector<double>& entries, int d, const char* name) {
    const auto n = static_cast<int>(entries.size());
    if (n == 1) return entries.front() * Eigen::MatrixXd::Identity(d, d);
    if (n == d) return Eigen::Map<const Eigen::VectorXd>(entries.data(), d).asDiagonal();
    if (n == d * d)
        return Eigen::Map<
            const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
            entries.data(), d, d);
    throw std::invalid_argument(std::string(name) + " needs 1, " + std::to_string(d) + " or " +
                                std::to_string(d * d) + " values for dim " + std::to_string(d) +
                                ", got " + std::to_string(n));
}

/// "q_1_exact, …, p_d_exact" ("q_exact, p_exact" for d = 1).
std::vector<std::string> exact_columns(int d) {
    std::vector<std::string> names{"energy"};
    for (const char* v : {"q", "p"})
        for (int i = 1; i <= d; ++i)
            names.push_back(d == 1 ? std::string(v) + "_exact"
                                   : std::string(v) + "_" + std::to_string(i) + "_exact");
    return names;
}

struct oscillator_parameters {
    double dim;
    std::vector<double> mass_matrix, stiffness_matrix; ///< stiffness_matrix empty: the default
};

} // namespace

model oscillator() {
    model m;
    m.name = "oscillator";
    m.summary =
        "d-dimensional harmonic oscillator with mass matrix M and stiffness K, exact solution";
    m.description =
        "  L = (1/2) qdot^T M qdot - (1/2) q^T K q, M and K symmetric positive definite, each\n"
        "  given as 1 value (times the identity), d values (diagonal) or d*d values (row by\n"
        "  row). Defaults: M = I and K = (2 pi)^2 [[2, -1], [-1, 2]] for d = 2 (two unit masses\n"
        "  between three springs), else K = (2 pi)^2 I. Default start q = (1, 0, ...) at rest.\n"
        "  Conserved: energy. Exact solution: yes, by normal modes (q_i_exact, p_i_exact).\n"
        "  Period: the slowest mode's, 2 pi / omega_min.";
    m.dim = 2;
    m.coordinates = "q_1 ... q_d";
    const parameter_set<oscillator_parameters> set{
        {{&oscillator_parameters::dim,
          {.name = "dim",
           .value = 2,
           .doc = "dimension d",
           .lower = 1,
           .upper = 10000,
           .integer = true,
           .sets_dimension = true}}},
        {{&oscillator_parameters::mass_matrix,
          {.name = "mass_matrix",
           .value = {1.0},
           .doc = "mass matrix M: 1, d or d*d values",
           .option = "mass-matrix"}},
         {&oscillator_parameters::stiffness_matrix,
          {.name = "stiffness_matrix",
           .doc = "stiffness matrix K: 1, d or d*d values (default above)",
           .option = "stiffness-matrix"}}}};
    set.declare(m);
    m.dimension =
        set.dimension([](const oscillator_parameters& par) { return static_cast<int>(par.dim); });
    m.steps_per_period = 50;
    m.ensemble_time = 10.0;
    m.ensemble_steps = 500;
    m.ensemble_note = "Energy exchange between the coupled masses: --grid q0_2=-1:1:21.";
    m.make = set.make([](const oscillator_parameters& par, const start& s) {
        const int d = static_cast<int>(par.dim);
        const double w2 = 4.0 * std::numbers::pi * std::numbers::pi;
        const Eigen::MatrixXd mass = square_matrix(par.mass_matrix, d, "mass_matrix");
        Eigen::MatrixXd k = w2 * Eigen::MatrixXd::Identity(d, d);
        if (!par.stiffness_matrix.empty())
            k = square_matrix(par.stiffness_matrix, d, "stiffness_matrix");
        else if (d == 2)
            k << 2 * w2, -w2, -w2, 2 * w2;
        const oscillator::system sys = oscillator::make_system(mass, k);
        auto given = [d](const std::vector<double>& g) {
            return vec<dynamic>(Eigen::Map<const vec<dynamic>>(g.data(), d));
        };
        phase_state<dynamic> x0{vec<dynamic>::Unit(d, 0), vec<dynamic>::Zero(d)};
        if (!s.q0.empty()) x0.q = given(s.q0);
        if (!s.v0.empty()) x0.p = mass * given(s.v0);
        if (!s.p0.empty()) x0.p = given(s.p0);
        const oscillator::exact_solution exact(mass, k, x0);
        return detail::make_problem(x0, exact.period(), [=](const step_options& o) {
            return detail::simulate_family(
                sys, x0, o,
                detail::column_set{exact_columns(d),
                                   [sys, exact](double t, const phase_state<dynamic>& x,
                                                const auto&, double* out) {
                                       out[0] = sys.energy(x);
                                       const phase_state<dynamic> ref = exact.at(t);
                                       const Eigen::Index n = x.q.size();
                                       for (Eigen::Index i = 0; i < n; ++i) {
                                           out[1 + i] = ref.q(i);
                                           out[1 + n + i] = ref.p(i);
                                       }
                                   }});
        });
    });
    return m;
}

} // namespace varsym::models::defs
