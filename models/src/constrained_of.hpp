// models/src/constrained_of.hpp: the problem of a constrained mechanism (four-bar, slider-crank,
// spherical-pendulum): the general engine with forces and holonomic constraints
// (schemes/constrained.hpp), its initial data checked or projected onto the constraints, and the
// columns every constrained model has. Private to the models layer.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "simulation_of.hpp"
#include "varsym/problems/mechanisms.hpp"
#include "varsym/schemes/constrained.hpp"
#include "varsym/schemes/constrained_sensitivity.hpp"

namespace varsym::models::detail {

/// What the constrained models' descriptions share.
inline const char* const constrained_columns =
    "  Columns: energy, work (of the forces since t = 0), energy_balance (energy - E0 - work:\n"
    "  the scheme's error), constraint_residual (max |g(q)|), hidden_residual (max |G(q) q'|),\n"
    "  lambda_1..m (the constraint forces' multipliers averaged over the last step).\n"
    "  Initial data must satisfy the constraints and be tangent to them (else it is refused);\n"
    "  project = 1 (--project) moves them onto the constraints instead. Solved by Newton on the\n"
    "  saddle-point system (iteration newton only).";

/// A positive length or mass given as value `index` of the list option `option` (`--lengths`).
inline parameter positive_value(const char* name, double v, const char* unit, const char* doc,
                                const char* option, int index) {
    return {.name = name,
            .value = v,
            .unit = unit,
            .doc = doc,
            .lower = 0.0,
            .lower_open = true,
            .option = option,
            .option_index = index};
}

/// Gravity g, and a constant torque on the crank: what the loop mechanisms share.
inline parameter gravity_parameter(double g) {
    return {.name = "gravity", .value = g, .unit = "m/s^2", .doc = "gravity g", .lower = 0.0};
}
inline parameter crank_torque_parameter() {
    return {
        .name = "torque", .value = 0.0, .unit = "N m", .doc = "constant torque tau on the crank"};
}

/// The state from q and q' with p = dL/dq' (or the given p0 instead).
template <class L>
phase_state<L::dim> state_of(const lagrangian_system<L>& sys, const start& s, const vec<L::dim>& q,
                             const vec<L::dim>& v) {
    if (!s.p0.empty())
        return {q, vec<L::dim>(Eigen::Map<const vec<L::dim>>(s.p0.data(), q.size()))};
    return {q, sys.momentum(q, v)};
}

/// The problem of L with constraints c and force f from x0 (projected first where `project`):
/// columns energy, work, energy_balance, constraint_residual, hidden_residual, lambda_1..m, then
/// `extra`'s names, filled by extra.fill(x, out).
template <class L, class C, class F, class Fill>
problem constrained_problem(const lagrangian_system<L>& sys, const C& c, const F& f,
                            phase_state<L::dim> x0, bool project, column_set<Fill> extra) {
    using stepper = general::constrained_stepper<L, C, F>;
    {
        const stepper probe(sys, c, f, 1.0, scheme_spec(scheme_kind::simpson));
        try {
            if (project) x0 = probe.project(x0);
            probe.check_initial(x0);
        } catch (const std::invalid_argument& e) {
            // Point to the projection where it helps (data off the constraints), not where it
            // cannot (a singular configuration, dependent constraints).
            const std::string what = e.what();
            const bool projectable = what.find("project it onto") != std::string::npos;
            throw std::invalid_argument(
                what + (projectable && !project ? " (project = 1: --project)" : ""));
        }
    }
    std::vector<std::string> names{"energy", "work", "energy_balance", "constraint_residual",
                                   "hidden_residual"};
    const int m = constraint_count(c);
    for (int a = 1; a <= m; ++a)
        names.push_back("lambda_" + std::to_string(a));
    names.insert(names.end(), extra.names.begin(), extra.names.end());
    const double e0 = sys.energy(x0);
    return make_problem(x0, 0.0, [=](const step_options& o) {
        check_general(o);
        refuse_non_newton(o, "a constrained model is solved by Newton");
        stepper run(sys, c, f, o.h, o.spec, o.newton);
        run.check_initial(x0); // passes (checked above), and sets the reference for diagnoses
        return simulate_general(
            std::move(run), x0,
            column_set{names, [sys, e0, m, fill = extra.fill](double, const phase_state<L::dim>& x,
                                                              const stepper& st, double* out) {
                           const double e = sys.energy(x), w = st.total_work();
                           out[0] = e;
                           out[1] = w;
                           out[2] = e - e0 - w;
                           out[3] = st.residual(x.q);
                           out[4] = st.hidden_residual(x);
                           const vec<C::count> lambda = st.mean_multiplier();
                           for (int a = 0; a < m; ++a)
                               out[5 + a] = lambda(a);
                           fill(x, out + 5 + m);
                       }});
    });
}

/// q0 and q0' of a loop of three coordinates: q0 the crank angle alone (the loop closed by
/// `close`) or all three; v0 the crank rate alone (the others from G q' = 0) or all three.
template <class C, class Close>
std::pair<vec<3>, vec<3>> loop_start(const start& s, const C& c, Close&& close, double crank0,
                                     double rate0) {
    const vec<3> q = s.q0.size() == 3 ? vec<3>(s.q0[0], s.q0[1], s.q0[2])
                                      : close(s.q0.empty() ? crank0 : s.q0[0]);
    if (s.v0.size() == 3) return {q, vec<3>(s.v0[0], s.v0[1], s.v0[2])};
    return {q, mechanisms::loop_rates(c, q, s.v0.empty() ? rate0 : s.v0[0])};
}

/// A constant torque tau on the crank, the first coordinate.
inline prescribed_force<3> crank_torque(double tau) {
    return prescribed_force<3>{[tau](double) { return vec<3>{tau, 0.0, 0.0}; }};
}

/// No extra columns.
inline auto no_columns() {
    return column_set{std::vector<std::string>{}, [](const auto&, double*) {}};
}

} // namespace varsym::models::detail
