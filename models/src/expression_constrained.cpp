// models/src/expression_constrained.cpp: the constrained general engine for an expression
// Lagrangian with typed holonomic constraints g(q) = 0 (and a force), compiled here once for the
// Python package: a user's mechanism with closed loops, no compiler needed.
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "simulation_of.hpp"
#include "varsym/models/expression.hpp"
#include "varsym/schemes/constrained.hpp"
#include "varsym/schemes/constrained_sensitivity.hpp"

namespace varsym::models {

std::unique_ptr<simulation>
simulate_constrained_expression(const expression_lagrangian& l, const expression_constraint& c,
                                const expression_force& f, const phase_state<dynamic>& x0,
                                const step_options& o, double t0, bool project) {
    using stepper = general::constrained_stepper<expression_lagrangian, expression_constraint,
                                                 expression_force>;
    const int d = l.dimension();
    if (c.dimension() != d || f.dimension() != d)
        throw std::invalid_argument("the constraints and the force must be on the Lagrangian's " +
                                    std::to_string(d) + " coordinates");
    if (x0.q.size() != d || x0.p.size() != d)
        throw std::invalid_argument("q0 and p0 need " + std::to_string(d) +
                                    " entries each (one per coordinate)");
    if (!(std::isfinite(o.h) && o.h > 0.0))
        throw std::invalid_argument("the time step must be a finite positive number");
    detail::check_general(o);
    if (o.newton.iteration != iteration_kind::automatic &&
        o.newton.iteration != iteration_kind::newton)
        throw std::invalid_argument("a constrained system is solved by Newton: use the "
                                    "iteration newton (the default)");
    const lagrangian_system<expression_lagrangian> sys(l);
    stepper run(sys, c, f, o.h, o.spec, o.newton);
    run.set_time(t0);
    phase_state<dynamic> x = x0;
    if (project) x = run.project(x);
    // Refuses inconsistent data (naming the projection where it would help), and sets the
    // reference the diagnosis of a singular configuration compares with.
    try {
        run.check_initial(x);
    } catch (const std::invalid_argument& e) {
        const std::string what = e.what();
        const bool projectable = what.find("project it onto") != std::string::npos;
        throw std::invalid_argument(
            what + (projectable && !project ? " (project = 1: --project, or project=True in Python)"
                                            : ""));
    }
    const int m = c.size();
    std::vector<std::string> names{"energy", "work", "energy_balance", "constraint_residual",
                                   "hidden_residual"};
    for (int a = 1; a <= m; ++a)
        names.push_back("lambda_" + std::to_string(a));
    const double e0 = sys.energy(x, t0);
    return detail::simulate_general(
        std::move(run), x,
        detail::column_set{
            names,
            [e0, m](double t, const phase_state<dynamic>& y, const stepper& st, double* out) {
                out[0] = st.system().energy(y, t);
                out[1] = st.total_work();
                out[2] = out[0] - e0 - out[1];
                out[3] = st.residual(y.q);
                out[4] = st.hidden_residual(y);
                const vec<dynamic> lambda = st.mean_multiplier();
                for (int a = 0; a < m; ++a)
                    out[5 + a] = lambda(a);
            }},
        t0);
}

} // namespace varsym::models
