// models/src/expression.cpp: the general engine for expression Lagrangians, without and with a
// force, compiled here once for the tool (`varsym run --lagrangian`) and the Python package.
#include "varsym/models/expression.hpp"

#include <cmath>

#include "simulation_of.hpp"

namespace varsym::models {

namespace {
using expression_system = lagrangian_system<expression_lagrangian>;
} // namespace

std::unique_ptr<simulation> simulate_expression(const expression_lagrangian& l,
                                                const expression_force& f,
                                                const phase_state<dynamic>& x0,
                                                const step_options& o, double t0) {
    const int d = l.dimension();
    if (f.dimension() != d)
        throw std::invalid_argument("the force has " + std::to_string(f.dimension()) +
                                    " components; the Lagrangian " + std::to_string(d) +
                                    " coordinates");
    if (x0.q.size() != d || x0.p.size() != d)
        throw std::invalid_argument("q0 and p0 need " + std::to_string(d) +
                                    " entries each (one per coordinate)");
    if (!(std::isfinite(o.h) && o.h > 0.0))
        throw std::invalid_argument("the time step must be a finite positive number");
    detail::check_general(o);
    const expression_system sys(l);
    if (f.zero())
        return detail::simulate_general(
            general::stepper<expression_lagrangian>(sys, o.h, o.spec, o.newton), x0,
            detail::column_set{{"energy"},
                               [](double t, const auto& x, const auto& st, double* out) {
                                   out[0] = st.system().energy(x, t);
                               }},
            t0);
    const double e0 = sys.energy(x0, t0);
    return detail::simulate_general(
        general::stepper<expression_lagrangian, expression_force>(sys, f, o.h, o.spec, o.newton),
        x0,
        detail::column_set{{"energy", "work", "energy_balance"},
                           [e0](double t, const auto& x, const auto& st, double* out) {
                               out[0] = st.system().energy(x, t);
                               out[1] = st.total_work();
                               out[2] = out[0] - e0 - out[1];
                           }},
        t0);
}

vec<dynamic> expression_momentum(const expression_lagrangian& l, const vec<dynamic>& q,
                                 const vec<dynamic>& v, double t) {
    const expression_system sys(l);
    sys.check_regular(q, v, t);
    return sys.momentum(q, v, t);
}

} // namespace varsym::models
