// apps/varsym/commands/bench_methods.cpp: the pendulum and Kepler problems of `varsym bench`, with
// varsym's schemes and Boost.Odeint's symplectic steppers on each.
#include "commands/bench_methods.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>

// Boost 1.74's m4 header is not self-contained: it needs the umbrella header first.
#include <boost/numeric/odeint.hpp>
#include <boost/numeric/odeint/stepper/symplectic_rkn_sb3a_m4_mclachlan.hpp>

#include "options/cli_common.hpp"
#include "varsym/integrate.hpp"
#include "varsym/problems/kepler.hpp"
#include "varsym/problems/pendulum.hpp"
#include "varsym/problems/solar_system.hpp"
#include "varsym/schemes/composition.hpp"
#include "varsym/schemes/scheme_kind.hpp"
#include "varsym/schemes/variational.hpp"
#include "varsym/solvers/solver_name.hpp"

namespace varsym::cli {

namespace {

using clock_type = std::chrono::steady_clock;
namespace odeint = boost::numeric::odeint;

double seconds_since(clock_type::time_point start) {
    return std::chrono::duration<double>(clock_type::now() - start).count();
}

scheme_spec parse_spec(const std::string& label) {
    const auto dash = label.find('-');
    const auto kind = parse_scheme(label.substr(0, dash));
    if (!kind) throw usage_error("unknown scheme '" + label + "' in --schemes");
    if (dash == std::string::npos) return *kind;
    const std::string degree = label.substr(dash + 1);
    int s = 0;
    const auto [end, ec] = std::from_chars(degree.data(), degree.data() + degree.size(), s);
    if (ec != std::errc() || end != degree.data() + degree.size() || s < 1)
        throw usage_error("--schemes: in " + shown(label) + ", the degree after '-' must be a " +
                          "whole number >= 1 (e.g. gauss-4, lobatto-3)");
    return {*kind, s};
}

/// A solver name (varsym/solvers/solver_name.hpp), as after the '/' in a --schemes entry
/// (gauss-4/fixed-point+forces) or in --solver.
newton_options solver_of(const std::string& solver, const std::string& where) {
    try {
        return parse_solver(solver);
    } catch (const std::invalid_argument& e) {
        throw usage_error(where + ": " + e.what());
    }
}

/// Runs a varsym stepper: timed loop without observer, or an observed run for the energy.
template <class Stepper, class Energy>
bench_run run_stepper(Stepper& stepper, phase_state<Stepper::dim> x, std::size_t n, bool observe,
                      const Energy& energy) {
    bench_run r;
    if (observe) {
        const double e0 = energy(x);
        const run_summary sum =
            integrate(stepper, x, 0.0, n, [&](std::size_t, double, const auto& y) {
                r.energy_error = std::max(r.energy_error, std::abs(energy(y) - e0) / std::abs(e0));
            });
        r.newton_mean = sum.mean_newton_iterations();
    } else {
        const auto start = clock_type::now();
        for (std::size_t j = 1; j <= n; ++j)
            if (!stepper.step(x).converged)
                throw numerical_error("Newton did not converge in step " + std::to_string(j) +
                                      " of the benchmark");
        r.seconds = seconds_since(start);
    }
    r.q = x.q;
    r.p = x.p;
    return r;
}

/// Runs an odeint symplectic stepper on q̈ = a(q) with unit mass, state as std::arrays.
template <class Stepper, std::size_t D, class Accel, class Energy>
bench_run run_odeint(std::array<double, D> q, std::array<double, D> p, double h, std::size_t n,
                     bool observe, const Accel& accel, const Energy& energy) {
    using state = std::array<double, D>;
    Stepper stepper;
    bench_run r;
    auto coordinate = [](const state& mom, state& dq) { dq = mom; };
    auto momentum = [&accel](const state& pos, state& dp) { accel(pos, dp); };
    const double e0 = energy(q, p);
    const auto start = clock_type::now();
    double t = 0.0;
    for (std::size_t j = 1; j <= n; ++j) {
        if constexpr (std::is_same_v<Stepper, odeint::velocity_verlet<state>>) {
            stepper.do_step(
                [&accel](const state& pos, const state&, state& a, double) { accel(pos, a); },
                std::make_pair(std::ref(q), std::ref(p)), t, h);
        } else {
            stepper.do_step(std::make_pair(coordinate, momentum),
                            std::make_pair(std::ref(q), std::ref(p)), t, h);
        }
        t += h;
        if (observe)
            r.energy_error = std::max(r.energy_error, std::abs(energy(q, p) - e0) / std::abs(e0));
    }
    if (!observe) r.seconds = seconds_since(start);
    r.q.resize(D); // element by element: a Map of a 1-element array trips GCC 12's -Warray-bounds
    r.p.resize(D);
    for (std::size_t i = 0; i < D; ++i) {
        r.q(static_cast<Eigen::Index>(i)) = q[i];
        r.p(static_cast<Eigen::Index>(i)) = p[i];
    }
    return r;
}

template <std::size_t D, class Accel, class Energy>
void add_odeint_methods(bench_problem& b, std::array<double, D> q0, std::array<double, D> p0,
                        Accel accel, Energy energy) {
    using state = std::array<double, D>;
    auto add = [&](const char* name, int order, auto tag) {
        using stepper_t = typename decltype(tag)::type;
        b.methods.push_back({name, order, true, [=](std::size_t n, double h, bool observe) {
                                 return run_odeint<stepper_t>(q0, p0, h, n, observe, accel, energy);
                             }});
    };
    add("odeint-velocity_verlet", 2, std::type_identity<odeint::velocity_verlet<state>>{});
    add("odeint-sb3a_mclachlan", 4,
        std::type_identity<odeint::symplectic_rkn_sb3a_mclachlan<state>>{});
    add("odeint-sb3a_m4_mclachlan", 4,
        std::type_identity<odeint::symplectic_rkn_sb3a_m4_mclachlan<state>>{});
}

struct composition_entry {
    std::string name;
    composition::method m;
    composition::form f;
};

/// Each composition of Störmer–Verlet in its drift–kick–drift form (the default: the more
/// accurate, tests/schemes/test_composition.cpp) and its kick–drift–kick form ("-kdk").
const std::vector<composition_entry>& compositions() {
    static const std::vector<composition_entry> list = [] {
        std::vector<composition_entry> v;
        for (const auto& [name, m] : {std::pair{"yoshida-6", composition::method::yoshida6},
                                      std::pair{"kahan-li-6", composition::method::kahan_li6},
                                      std::pair{"kahan-li-8", composition::method::kahan_li8}}) {
            v.push_back({name, m, composition::form::drift_kick_drift});
            v.push_back({std::string(name) + "-kdk", m, composition::form::kick_drift_kick});
        }
        return v;
    }();
    return list;
}

/// The selected varsym schemes and compositions on one separable system from x0.
template <class System, class Energy>
void add_varsym_methods(bench_problem& b, const bench_selection& selection, const System& sys,
                        const phase_state<System::dim>& x0, const Energy& energy) {
    for (const std::string& label : selection.schemes) {
        const auto slash = label.find('/');
        const scheme_spec spec = parse_spec(label.substr(0, slash));
        const newton_options opt =
            slash == std::string::npos
                ? solver_of(selection.solver, "--solver")
                : solver_of(label.substr(slash + 1), "--schemes: in " + shown(label));
        const std::string name =
            slash == std::string::npos ? spec.label() : spec.label() + label.substr(slash);
        b.methods.push_back({name, spec.order(), false, [=](std::size_t n, double h, bool observe) {
                                 return with_stepper(spec, sys, h, opt, [&](auto& st) {
                                     return run_stepper(st, x0, n, observe, energy);
                                 });
                             }});
    }
    for (const std::string& name : selection.compositions) {
        const auto it = std::find_if(compositions().begin(), compositions().end(),
                                     [&](const auto& c) { return c.name == name; });
        if (it == compositions().end())
            throw usage_error("unknown composition '" + name + "' in --compositions");
        const composition::method m = it->m;
        const composition::form f = it->f;
        b.methods.push_back(
            {name, composition::make(m).order, false, [=](std::size_t n, double h, bool observe) {
                 composition::stepper st(sys, h, m, f);
                 return run_stepper(st, x0, n, observe, energy);
             }});
    }
}

} // namespace

const std::vector<std::string>& composition_names() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> v;
        for (const auto& c : compositions())
            v.push_back(c.name);
        return v;
    }();
    return names;
}

std::string pendulum_name(double q0) {
    if (q0 == std::numbers::pi / 2) return "pendulum";
    char name[40];
    std::snprintf(name, sizeof name, "pendulum-%g", q0);
    return name;
}

bench_problem pendulum_bench(const bench_selection& selection, double q0) {
    const double omega = 2.0 * std::numbers::pi;
    const auto sys = pendulum::make_system(1.0, omega);
    using LD = long double;
    const pendulum::basic_exact_solution<LD> exact(1, omega, q0, 0); // the system's own ω
    bench_problem b{pendulum_name(q0), static_cast<double>(exact.period()), {}, {}};
    b.error = [exact, omega](const bench_run& r, LD t) {
        const auto x = exact.state(t);
        return static_cast<double>(
            std::max(std::abs(r.q(0) - x.q), std::abs(r.p(0) - x.p) / omega));
    };
    add_varsym_methods(b, selection, sys, phase_state<1>{vec<1>{q0}, vec<1>{0.0}},
                       [sys](const phase_state<1>& y) { return sys.energy(y); });
    add_odeint_methods<1>(
        b, {q0}, {0.0},
        [omega](const std::array<double, 1>& q, std::array<double, 1>& a) {
            a[0] = -omega * omega * std::sin(q[0]);
        },
        [omega](const std::array<double, 1>& q, const std::array<double, 1>& p) {
            const double s = std::sin(0.5 * q[0]);
            return 0.5 * p[0] * p[0] + 2.0 * omega * omega * s * s;
        });
    return b;
}

bench_problem kepler_bench(const bench_selection& selection) {
    const kepler::orbit orbit(0.6, 1.0);
    const auto sys = kepler::make_system();
    bench_problem b{"kepler", orbit.period(), {}, {}};
    b.error = [orbit](const bench_run& r, long double t) {
        const auto x = orbit.at(t);
        return std::max((r.q - x.q).lpNorm<Eigen::Infinity>(),
                        (r.p - x.p).lpNorm<Eigen::Infinity>());
    };
    add_varsym_methods(b, selection, sys, orbit.at(0.0),
                       [sys](const phase_state<2>& y) { return sys.energy(y); });
    const auto x0 = orbit.at(0.0);
    add_odeint_methods<2>(
        b, {x0.q(0), x0.q(1)}, {x0.p(0), x0.p(1)},
        [](const std::array<double, 2>& q, std::array<double, 2>& a) {
            const double r2 = q[0] * q[0] + q[1] * q[1], f = -1.0 / (r2 * std::sqrt(r2));
            a = {f * q[0], f * q[1]};
        },
        [](const std::array<double, 2>& q, const std::array<double, 2>& p) {
            return 0.5 * (p[0] * p[0] + p[1] * p[1]) - 1.0 / std::sqrt(q[0] * q[0] + q[1] * q[1]);
        });
    return b;
}

bench_problem solar_bench(const bench_selection& selection, double days) {
    constexpr int d = solar_system::dim;
    const auto sys = solar_system::make_system();
    const Eigen::VectorXd reference = solar_reference_positions(days);
    bench_problem b{"solar", solar_system::jupiter_period, {}, {}};
    b.total = days;
    b.error = [reference](const bench_run& r, long double) {
        return (r.q - reference).lpNorm<Eigen::Infinity>();
    };
    add_varsym_methods(b, selection, sys, solar_system::initial_state(),
                       [sys](const phase_state<d>& y) { return sys.energy(y); });
    // odeint's steppers take unit masses: their "momenta" are the velocities.
    std::array<double, d> q0{}, v0{}, m{};
    for (int i = 0; i < d; ++i) {
        const auto& body = solar_system::bodies[static_cast<std::size_t>(i / 3)];
        q0[static_cast<std::size_t>(i)] = body.q[static_cast<std::size_t>(i % 3)];
        v0[static_cast<std::size_t>(i)] = body.v[static_cast<std::size_t>(i % 3)];
        m[static_cast<std::size_t>(i)] = body.mass;
    }
    const nbody::gravity<d> v = sys.potential();
    add_odeint_methods<d>(
        b, q0, v0,
        [v, m](const std::array<double, d>& q, std::array<double, d>& a) {
            const vec<d> g = v.gradient(Eigen::Map<const vec<d>>(q.data()));
            for (std::size_t i = 0; i < a.size(); ++i)
                a[i] = -g(static_cast<Eigen::Index>(i)) / m[i];
        },
        [v, m](const std::array<double, d>& q, const std::array<double, d>& w) {
            double kinetic = 0.0;
            for (std::size_t i = 0; i < w.size(); ++i)
                kinetic += 0.5 * m[i] * w[i] * w[i];
            return kinetic + v.value(Eigen::Map<const vec<d>>(q.data()));
        });
    return b;
}

} // namespace varsym::cli
