// apps/varsym/models/model_constrained.cpp: the constrained mechanisms, run by the general
// engine with forces (Lagrange–d'Alembert) and holonomic constraints: `four-bar`,
// `slider-crank` (closed loops) and `spherical-pendulum` (Cartesian, |x| = l).
#include <cmath>
#include <memory>
#include <numbers>

#include "model_run.hpp"
#include "varsym/problems/arm.hpp"
#include "varsym/problems/mechanisms.hpp"
#include "varsym/schemes/constrained.hpp"

namespace varsym::cli {

namespace {

const char* const constrained_columns =
    "  Columns: energy, work (of the forces since t = 0), energy_balance (energy - E0 - work:\n"
    "  the scheme's error), constraint_residual (max |g(q)|), hidden_residual (max |G(q) q'|),\n"
    "  lambda_1..m (the constraint forces' multipliers averaged over the last step).\n"
    "  Initial data must satisfy the constraints and be tangent to them (else exit 2);\n"
    "  --project moves them onto the constraints instead. Solved by Newton on the saddle-point\n"
    "  system (--iteration newton only).";

std::vector<double> or_default(const std::vector<double>& given, std::vector<double> fallback) {
    return given.empty() ? fallback : given;
}
void need(const std::vector<double>& v, std::size_t n, const char* option, const char* what) {
    if (v.size() != n)
        throw usage_error(std::string(option) + " needs " + std::to_string(n) + " values (" + what +
                          "), got " + std::to_string(v.size()));
}
void newton_only(const run_setup& s, const char* name) {
    if (s.newton.iteration != iteration_kind::automatic &&
        s.newton.iteration != iteration_kind::newton)
        throw usage_error(std::string(name) + " has constraints and is solved by Newton: use "
                                              "--iteration newton (the default)");
    if (s.newton.predictor != predictor_kind::taylor)
        throw usage_error(std::string(name) + " runs the general engine: use --predictor taylor");
}

/// The state from q0 and q̇0 with p = ∂L/∂q̇ (given --p0, that instead).
template <class L>
phase_state<L::dim> state_of(const lagrangian_system<L>& sys, const run_setup& s,
                             const vec<L::dim>& q, const vec<L::dim>& v) {
    if (!s.p0.empty()) {
        need(s.p0, static_cast<std::size_t>(q.size()), "--p0", "the momenta");
        return {q, vec<L::dim>(Eigen::Map<const vec<L::dim>>(s.p0.data(), q.size()))};
    }
    return {q, sys.momentum(q, v)};
}

/// Runs a constrained mechanism with force f from x0 (projected first with --project).
template <class L, class C, class F, class Extra>
void run_constrained(const run_setup& s, const run_plan& plan, const mechanism_options& o,
                     const lagrangian_system<L>& sys, const C& c, const F& f,
                     phase_state<L::dim> x0, const std::string& extra_header, Extra&& extra) {
    constexpr int D = L::dim;
    general::constrained_stepper<L, C, F> st(sys, c, f, plan.h, s.spec, s.newton);
    try {
        if (o.project) x0 = st.project(x0);
        st.check_initial(x0);
    } catch (const std::exception& e) {
        // Point to --project where the message suggests projecting (data off the constraints),
        // not where no projection helps (a singular configuration, dependent constraints).
        const std::string what = e.what();
        const bool projectable = what.find("project it onto") != std::string::npos;
        throw usage_error(what + (projectable && !o.project ? " (--project)" : ""));
    }
    const double e0 = sys.energy(x0);
    std::string header = ",energy,work,energy_balance,constraint_residual,hidden_residual";
    for (int a = 1; a <= C::count; ++a)
        header += ",lambda_" + std::to_string(a);
    stream_trajectory<D>(
        s, plan, x0, header + extra_header, [&st](auto&& fn) { return fn(st); },
        [&](double, const phase_state<D>& x, std::string& line) {
            const double e = sys.energy(x), w = st.total_work();
            append_values(line, {e, w, e - e0 - w, st.residual(x.q), st.hidden_residual(x)});
            const vec<C::count> lambda = st.mean_multiplier();
            for (int a = 0; a < C::count; ++a)
                append_values(line, {lambda(a)});
            extra(x, line);
        });
}

/// q0 and q̇0 of a loop: --q0 the crank angle alone (the loop closed by `close`) or all three
/// coordinates; --v0 the crank rate alone (the others from G q̇ = 0) or all three.
template <class C, class Close>
std::pair<vec<3>, vec<3>> loop_start(const run_setup& s, const C& c, Close&& close, double crank0,
                                     double rate0, const char* names) {
    vec<3> q;
    if (s.q0.size() <= 1) {
        try {
            q = close(s.q0.empty() ? crank0 : s.q0[0]);
        } catch (const std::invalid_argument& e) {
            throw usage_error(e.what());
        }
    } else {
        need(s.q0, 3, "--q0", names);
        q = vec<3>(s.q0[0], s.q0[1], s.q0[2]);
    }
    if (s.v0.size() > 1) {
        need(s.v0, 3, "--v0", names);
        return {q, vec<3>(s.v0[0], s.v0[1], s.v0[2])};
    }
    return {q, mechanisms::loop_rates(c, q, s.v0.empty() ? rate0 : s.v0[0])};
}

prescribed_force<3> crank_torque(double tau) {
    return prescribed_force<3>{[tau](double) { return vec<3>{tau, 0.0, 0.0}; }};
}

} // namespace

model make_four_bar_model(std::shared_ptr<mechanism_options> o) {
    model m;
    m.name = "four-bar";
    m.summary = "planar four-bar linkage, a closed loop of one degree of freedom";
    m.description =
        "  Crank AB (a, m1) turns about A = (0,0), rocker DC (c, m3) about D = (d,0), coupler BC\n"
        "  (b, m2) closes the loop; uniform bars, gravity g along -y. q = (th1, th2, th3) [rad],\n"
        "  the bars' angles from +x; constraints A + a e(th1) + b e(th2) = D + c e(th3).\n"
        "  --lengths a,b,c,d [m] (1,3,2.5,3: a crank-rocker), --masses m1,m2,m3 [kg] (1,3,2.5),\n"
        "  --gravity (9.81), --torque tau [N m] on the crank (0). --q0 th1 (pi/3; th2, th3 from\n"
        "  the loop) or all three; --v0 th1' (2 rad/s; the others from the loop) or all three.\n"
        "  Conserved: energy (with --torque 0), else energy - work. Default --time 10 --steps\n"
        "  10000.\n";
    m.description += constrained_columns;
    m.options = {"--masses", "--lengths", "--gravity", "--torque", "--project"};
    m.add_options = [](CLI::App&) {}; // shared: add_mechanism_options
    m.run = [o](const run_setup& s) {
        newton_only(s, "four-bar");
        mechanisms::four_bar p;
        const auto len = or_default(o->lengths, {p.a, p.b, p.c, p.ground});
        const auto mass = or_default(o->masses, {p.m1, p.m2, p.m3});
        need(len, 4, "--lengths", "crank, coupler, rocker, ground");
        need(mass, 3, "--masses", "crank, coupler, rocker");
        p.a = len[0], p.b = len[1], p.c = len[2], p.ground = len[3];
        p.m1 = mass[0], p.m2 = mass[1], p.m3 = mass[2], p.g = o->gravity;
        try {
            p.validate();
        } catch (const std::invalid_argument& e) {
            throw usage_error(std::string("four-bar: ") + e.what());
        }
        const mechanisms::four_bar_loop loop{p};
        const auto [q, v] = loop_start(
            s, loop, [&](double th) { return p.assemble(th); }, std::numbers::pi / 3, 2.0,
            "th1, th2, th3");
        const lagrangian_system<mechanisms::four_bar_lagrangian> sys({p});
        const run_plan plan = plan_steps(s, "four-bar", 0.0, 0, 10.0, 10000);
        run_constrained(s, plan, *o, sys, loop, crank_torque(o->torque), state_of(sys, s, q, v), "",
                        [](const auto&, std::string&) {});
    };
    return m;
}

model make_slider_crank_model(std::shared_ptr<mechanism_options> o) {
    model m;
    m.name = "slider-crank";
    m.summary = "slider-crank mechanism, a closed loop of one degree of freedom";
    m.description =
        "  Crank OA (r, moment of inertia J about O) at th, uniform rod AB (l, m_rod) at phi,\n"
        "  slider B (m_slider) at x on the x axis; gravity g along -y. q = (th, phi, x) [rad,\n"
        "  rad, m]; constraints r cos th + l cos phi = x, r sin th + l sin phi = 0.\n"
        "  --lengths r,l [m] (0.5,1.5), --masses m_rod,m_slider [kg] (1,2), --inertias J\n"
        "  [kg m^2] (0.1), --gravity (9.81), --torque tau [N m] on the crank (0). --q0 th (0.3;\n"
        "  phi, x from the loop) or all three; --v0 th' (10 rad/s) or all three. Conserved:\n"
        "  energy (with --torque 0), else energy - work. Default --time 5 --steps 10000.\n";
    m.description += constrained_columns;
    m.options = {"--masses", "--lengths", "--inertias", "--gravity", "--torque", "--project"};
    m.add_options = [](CLI::App&) {}; // shared: add_mechanism_options
    m.run = [o](const run_setup& s) {
        newton_only(s, "slider-crank");
        mechanisms::slider_crank p;
        const auto len = or_default(o->lengths, {p.r, p.l});
        const auto mass = or_default(o->masses, {p.m_rod, p.m_slider});
        const auto inertia = or_default(o->inertias, {p.j});
        need(len, 2, "--lengths", "crank, rod");
        need(mass, 2, "--masses", "rod, slider");
        need(inertia, 1, "--inertias", "the crank's about its pivot");
        p.r = len[0], p.l = len[1], p.m_rod = mass[0], p.m_slider = mass[1], p.j = inertia[0];
        p.g = o->gravity;
        try {
            p.validate();
        } catch (const std::invalid_argument& e) {
            throw usage_error(std::string("slider-crank: ") + e.what());
        }
        const mechanisms::slider_crank_loop loop{p};
        const auto [q, v] = loop_start(
            s, loop, [&](double th) { return p.assemble(th); }, 0.3, 10.0, "th, phi, x");
        const lagrangian_system<mechanisms::slider_crank_lagrangian> sys({p});
        const run_plan plan = plan_steps(s, "slider-crank", 0.0, 0, 5.0, 10000);
        run_constrained(s, plan, *o, sys, loop, crank_torque(o->torque), state_of(sys, s, q, v), "",
                        [](const auto&, std::string&) {});
    };
    return m;
}

model make_spherical_pendulum_model(std::shared_ptr<mechanism_options> o) {
    model m;
    m.name = "spherical-pendulum";
    m.summary = "spherical pendulum in Cartesian coordinates with the constraint |x| = l";
    m.description =
        "  L = m |x'|^2/2 - m g z, constraint (|x|^2 - l^2)/(2 l) = 0; q = (x, y, z) [m], z up.\n"
        "  --masses m [kg] (1), --lengths l [m] (1), --gravity g (9.81). --q0 x,y,z, or th,phi\n"
        "  [rad] (polar angle from the downward vertical, azimuth; default 1, 0); --v0 x',y',z'\n"
        "  or th',phi' (0, 1.2 sqrt(g/l)). Conserved: energy and spin = x p_y - y p_x (the\n"
        "  angular momentum about the vertical, to round-off). Default --time 10 --steps 2000.\n";
    m.description += constrained_columns;
    m.description += "\n  Last column: spin.";
    m.options = {"--masses", "--lengths", "--gravity", "--project"};
    m.add_options = [](CLI::App&) {}; // shared: add_mechanism_options
    m.run = [o](const run_setup& s) {
        newton_only(s, "spherical-pendulum");
        mechanisms::spherical_pendulum p;
        const auto mass = or_default(o->masses, {p.m});
        const auto len = or_default(o->lengths, {p.length});
        need(mass, 1, "--masses", "the bob's");
        need(len, 1, "--lengths", "the rod's");
        p.m = mass[0], p.length = len[0], p.g = o->gravity;
        try {
            p.validate();
        } catch (const std::invalid_argument& e) {
            throw usage_error(std::string("spherical-pendulum: ") + e.what());
        }
        const auto angles = or_default(s.q0.size() == 3 ? std::vector<double>{} : s.q0, {1.0, 0.0});
        const auto rates = or_default(s.v0.size() == 3 ? std::vector<double>{} : s.v0,
                                      {0.0, 1.2 * std::sqrt(p.g / p.length)});
        need(angles, 2, "--q0", "x,y,z or th,phi");
        need(rates, 2, "--v0", "x',y',z' or th',phi'");
        auto [q, v] = p.state(angles[0], angles[1], rates[0], rates[1]);
        if (s.q0.size() == 3) q = vec<3>(s.q0[0], s.q0[1], s.q0[2]);
        if (s.v0.size() == 3) v = vec<3>(s.v0[0], s.v0[1], s.v0[2]);
        const lagrangian_system<mechanisms::spherical_lagrangian> sys({p});
        const run_plan plan = plan_steps(s, "spherical-pendulum", 0.0, 0, 10.0, 2000);
        run_constrained(s, plan, *o, sys, mechanisms::spherical_rod{p}, unforced{},
                        state_of(sys, s, q, v), ",spin",
                        [](const phase_state<3>& x, std::string& line) {
                            append_values(line, {mechanisms::spherical_pendulum::spin(x)});
                        });
    };
    return m;
}

} // namespace varsym::cli
