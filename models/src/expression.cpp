// models/src/expression.cpp: expression Lagrangians, without and with a force, on the general
// engine, on the separable steppers (a separable L) and on the constrained engine (typed
// holonomic constraints), compiled here once for the tool (`varsym run --lagrangian`) and the
// Python package.
#include "varsym/models/expression.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "simulation_of.hpp"
#include "varsym/run/memory.hpp"
#include "varsym/schemes/constrained.hpp"
#include "varsym/schemes/constrained_sensitivity.hpp"
#include "varsym/systems/expression_separable.hpp"

namespace varsym::models {

namespace {
using expression_system = lagrangian_system<expression_lagrangian>;

/// What a run of L with force f from x0 needs: the same dimensions, a finite positive step, and
/// (`general`: off the separable steppers) the general engine's predictor. Throws
/// std::invalid_argument.
void check_run(const expression_lagrangian& l, const expression_force& f,
               const phase_state<dynamic>& x0, const step_options& o, bool general) {
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
    if (general) detail::check_general(o);
}
} // namespace

std::unique_ptr<simulation> simulate_expression(const expression_lagrangian& l,
                                                const expression_force& f,
                                                const phase_state<dynamic>& x0,
                                                const step_options& o, double t0) {
    // ½ q̇ᵀ M q̇ − V(q) without a force runs on the separable steppers (their predictors too).
    const bool separable = f.zero() && !l.depends_on_time() && l.separable();
    check_run(l, f, x0, o, !separable);
    const expression_system sys(l);
    // E − E0 − W, W the energy put in by the force and by L's time dependence (−∫∂L/∂t dt):
    // what is conserved up to the scheme's error.
    const double e0 = sys.energy(x0, t0);
    auto balance = [e0](double t, const auto& x, const auto& st, double* out) {
        out[0] = st.system().energy(x, t);
        out[1] = st.total_work();
        out[2] = out[0] - e0 - out[1];
    };
    const std::vector<std::string> balanced{"energy", "work", "energy_balance"};
    if (f.zero() && l.depends_on_time())
        return detail::simulate_general(
            general::stepper<expression_lagrangian>(sys, o.h, o.spec, o.newton), x0,
            detail::column_set{balanced, balance}, t0);
    if (separable) { // ½ q̇ᵀ M q̇ − V(q): the paper's steppers and the family's
        // Fixed-size vectors for one to three coordinates (one angle, a particle in a plane or
        // in space), as a built-in model has them; sizes known only at run time above three.
        auto family = [&]<int D>() {
            return detail::simulate_family(
                separable_system_of<D>(l), x0, o,
                detail::column_set{{"energy"},
                                   [](double, const auto& x, const auto& st, double* out) {
                                       out[0] = st.system().energy(x);
                                   }},
                t0);
        };
        switch (l.dimension()) {
        case 1:
            return family.template operator()<1>();
        case 2:
            return family.template operator()<2>();
        case 3:
            return family.template operator()<3>();
        default:
            return family.template operator()<dynamic>();
        }
    }
    if (f.zero())
        return detail::simulate_general(
            general::stepper<expression_lagrangian>(sys, o.h, o.spec, o.newton), x0,
            detail::column_set{{"energy"},
                               [](double t, const auto& x, const auto& st, double* out) {
                                   out[0] = st.system().energy(x, t);
                               }},
            t0);
    return detail::simulate_general(
        general::stepper<expression_lagrangian, expression_force>(sys, f, o.h, o.spec, o.newton),
        x0, detail::column_set{balanced, balance}, t0);
}

std::unique_ptr<simulation>
simulate_constrained_expression(const expression_lagrangian& l, const expression_constraint& c,
                                const expression_force& f, const phase_state<dynamic>& x0,
                                const step_options& o, double t0, bool project) {
    using stepper = general::constrained_stepper<expression_lagrangian, expression_constraint,
                                                 expression_force>;
    check_run(l, f, x0, o, true);
    if (c.dimension() != l.dimension())
        throw std::invalid_argument("the constraints must be on the Lagrangian's " +
                                    std::to_string(l.dimension()) + " coordinates");
    detail::refuse_non_newton(o, "a constrained system is solved by Newton");
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

vec<dynamic> expression_momentum(const expression_lagrangian& l, const vec<dynamic>& q,
                                 const vec<dynamic>& v, double t) {
    const expression_system sys(l);
    sys.check_regular(q, v, t);
    return sys.momentum(q, v, t);
}

void check_expression_size(int d, std::size_t length) {
    const double d2 = static_cast<double>(d) * d;
    const double seconds = 6.6e-10 * d2 * static_cast<double>(length);
    const double bytes = 1000.0 * d2;
    const double have = physical_memory();
    if (seconds <= 60.0 && !beyond_memory(bytes, have)) return;
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "a Lagrangian of %d coordinates typed in %zu characters would take about %.0f s "
                  "and %.1f GB to differentiate (the limits: 60 s, 80 %% of this machine's "
                  "%.0f GB): write it as a C++ system for the general engine "
                  "(docs/library.md), or use fewer coordinates",
                  d, length, seconds, bytes / 1e9, have / 1e9);
    throw std::invalid_argument(buf);
}

namespace {

/// The expression's parameters at `values`, given in their order (the model's first values).
std::vector<expression_parameter> at_values(std::vector<expression_parameter> parameters,
                                            std::span<const double> values) {
    for (std::size_t i = 0; i < parameters.size(); ++i)
        parameters[i].value = values[i];
    return parameters;
}

/// expression_model, with L at the defaults already built where `built` is given.
model make_expression_model(const std::string& text, const std::vector<std::string>& coordinates,
                            const std::vector<expression_parameter>& parameters,
                            const std::vector<std::string>& force,
                            const std::vector<std::string>& constraints,
                            const expression_lagrangian* built) {
    // L and the force at the parameters' values `par` (each member of an ensemble may have
    // its own: the expressions are parsed again, a matter of microseconds).
    check_expression_size(static_cast<int>(coordinates.size()), text.size());
    // The force at parameters `given`, beside an L of `d` coordinates.
    auto force_at = [=](const std::vector<expression_parameter>& given, int d) {
        return force.empty() ? expression_force(d) : expression_force(force, coordinates, given);
    };
    // The constraints at parameters `given` (checked once here, at the defaults).
    auto constraints_at = [=](const std::vector<expression_parameter>& given) {
        return constraints.empty() ? std::optional<expression_constraint>()
                                   : std::optional<expression_constraint>(
                                         std::in_place, constraints, coordinates, given);
    };
    (void)constraints_at(parameters);
    auto build = [=](std::span<const double> par) {
        const std::vector<expression_parameter> given = at_values(parameters, par);
        expression_lagrangian l(text, coordinates, given);
        expression_force f = force_at(given, l.dimension());
        return std::pair{std::move(l), std::move(f)};
    };
    model m;
    m.name = "lagrangian";
    m.summary = "your own L(q, qdot, t) given as an expression, no compiling";
    std::vector<double> defaults;
    for (const auto& p : parameters) {
        m.parameters.push_back({.name = p.name, .value = p.value, .doc = "parameter of L"});
        defaults.push_back(p.value);
    }
    // L and the force at the defaults, built once (refusing what does not parse, before any
    // run) and copied for every problem at these values: differentiating a large L is costly.
    const auto at_defaults =
        built == nullptr
            ? std::make_shared<const std::pair<expression_lagrangian, expression_force>>(
                  build(defaults))
            : std::make_shared<const std::pair<expression_lagrangian, expression_force>>(
                  *built, force_at(parameters, built->dimension()));
    m.dim = at_defaults->first.dimension();
    for (const auto& c : coordinates)
        m.coordinates += (m.coordinates.empty() ? "" : ", ") + c;
    m.description = "  L = " + text + " over " + m.coordinates +
                    (force.empty() ? "" : "; a generalized force") +
                    (constraints.empty() ? "" : "; holonomic constraints") + ".";
    // With constraints, the constrained models' flag `project` follows L's parameters.
    const std::size_t n_par = parameters.size();
    if (!constraints.empty()) {
        m.parameters.push_back(detail::project_parameter());
        defaults.push_back(0.0);
    }
    m.time = 10.0;
    m.steps = 10000;
    m.ensemble_time = 10.0;
    m.ensemble_steps = 1000;
    const vec<dynamic> zero = vec<dynamic>::Zero(m.dim);
    m.make = [build, zero, at_defaults, defaults, constraints_at, parameters,
              n_par](std::span<const double> par, const start& s, const lists&) {
        auto [l, f] =
            std::equal(par.begin(), par.begin() + static_cast<std::ptrdiff_t>(n_par),
                       defaults.begin(), defaults.begin() + static_cast<std::ptrdiff_t>(n_par))
                ? *at_defaults
                : build(par.first(n_par));
        const expression_system sys(l);
        phase_state<dynamic> x0;
        auto vector = [&](const std::vector<double>& v) {
            return v.empty() ? zero
                             : vec<dynamic>(Eigen::Map<const vec<dynamic>>(v.data(), zero.size()));
        };
        x0.q = vector(s.q0);
        const vec<dynamic> v = vector(s.v0);
        sys.check_regular(x0.q, v, 0.0);
        x0.p = s.p0.empty() ? sys.momentum(x0.q, v, 0.0) : vector(s.p0);
        sys.check_regular(x0.q, sys.velocity(x0.q, x0.p, 0.0), 0.0);
        problem pr;
        if (par.size() > n_par) { // constrained: checked (or projected) here, before any run
            expression_constraint c = *constraints_at(at_values(parameters, par));
            const bool project = par[n_par] != 0.0; // the flag after L's parameters
            const auto probe = simulate_constrained_expression(
                l, c, f, x0, {scheme_spec(scheme_kind::simpson), {}, 1.0}, 0.0, project);
            x0 = probe->save().x;
            pr.simulate = [l = std::move(l), c = std::move(c), f = std::move(f),
                           x0](const step_options& o) {
                return simulate_constrained_expression(l, c, f, x0, o);
            };
        } else {
            pr.simulate = [l = std::move(l), f = std::move(f), x0](const step_options& o) {
                return simulate_expression(l, f, x0, o);
            };
        }
        pr.q0.assign(x0.q.data(), x0.q.data() + x0.q.size());
        pr.p0.assign(x0.p.data(), x0.p.data() + x0.p.size());
        return pr;
    };
    // The default start, q = 0 and q̇ = 0, as far as L allows it there (1/sqrt(q) does not:
    // then a run must give its own start, and p0 is shown as 0).
    m.q0.assign(static_cast<std::size_t>(m.dim), 0.0);
    m.p0 = m.q0;
    try {
        m.p0 = m.make(defaults, {}, {}).p0;
    } catch (const std::exception&) {
    }
    return m;
}

} // namespace

model expression_model(const std::string& text, const std::vector<std::string>& coordinates,
                       const std::vector<expression_parameter>& parameters,
                       const std::vector<std::string>& force,
                       const std::vector<std::string>& constraints) {
    return make_expression_model(text, coordinates, parameters, force, constraints, nullptr);
}

model expression_model(const expression_lagrangian& l, const std::vector<std::string>& force,
                       const std::vector<std::string>& constraints) {
    return make_expression_model(l.text(), l.coordinates(), l.parameters(), force, constraints, &l);
}

} // namespace varsym::models
