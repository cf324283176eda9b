// apps/varsym/model_pendulum.cpp: `--model pendulum`, the paper's nonlinear pendulum with its
// exact solution (columns step,t,q,p,energy,q_exact,p_exact, as in the foundation).
#include <memory>
#include <numbers>

#include "ensemble.hpp"
#include "model_run.hpp"
#include "shared_options.hpp"
#include "varsym/problems/pendulum.hpp"

namespace varsym::cli {

model make_pendulum_model() {
    auto par = std::make_shared<paper::pendulum_case>();
    model m;
    m.name = "pendulum";
    m.summary = "the paper's nonlinear pendulum, exact solution by elliptic functions";
    m.description =
        "  L = (m/2) qdot^2 - m omega^2 (1 - cos q); q [rad] from the downward vertical,\n"
        "  m the moment of inertia [kg m^2], omega the small-oscillation frequency [rad/s].\n"
        "  Parameters: --mass (1), --omega (2 pi); initial state --q0 (pi/2), --p0 (0) or --v0.\n"
        "  Conserved: energy. Exact solution: yes (q_exact, p_exact). Period: the nonlinear\n"
        "  period 4K(k^2)/omega (one revolution in rotation); default 50 steps per period.";
    m.options = {"--mass", "--omega"};
    m.add_options = [par](CLI::App& cmd) {
        cmd.add_option("--mass", par->mass, "pendulum: moment of inertia m [kg m^2]")
            ->transform(positive_number)
            ->capture_default_str();
        cmd.add_option("--omega", par->omega,
                       "pendulum: small-oscillation angular frequency omega [rad/s] (default 2 pi)")
            ->transform(positive_number);
    };
    m.run = [par](const run_setup& s) {
        paper::pendulum_case c = *par;
        c.q0 = initial_vector(s.q0, "--q0", 1, "the angle q", vec<dynamic>::Constant(1, c.q0))(0);
        if (!s.v0.empty()) c.p0 = c.mass * initial_vector(s.v0, "--v0", 1, "dq/dt", {})(0);
        c.p0 =
            initial_vector(s.p0, "--p0", 1, "the momentum p", vec<dynamic>::Constant(1, c.p0))(0);
        const pendulum::system sys = make_system(c);
        const pendulum::exact_solution exact = make_exact(c);
        const run_plan plan = plan_steps(s, "pendulum", exact.period(), 50, 0.0, 0);
        stream_trajectory<1>(
            s, plan, phase_state<1>{vec<1>{c.q0}, vec<1>{c.p0}}, ",energy,q_exact,p_exact",
            [&](auto&& f) { return with_stepper(s.spec, sys, plan.h, s.newton, f); },
            [&](double t, const phase_state<1>& x, std::string& line) {
                const auto ref = exact.at(t);
                append_values(line, {sys.energy(x), ref.q(0), ref.p(0)});
            });
    };
    return m;
}

ensemble_model make_pendulum_ensemble() {
    ensemble_model m;
    m.name = "pendulum";
    m.dim = 1;
    m.q0 = {std::numbers::pi / 2};
    m.p0 = {0.0};
    m.parameters = {{"mass", 1.0}, {"omega", 2.0 * std::numbers::pi}};
    m.help = "  L = (m/2) qdot^2 - m omega^2 (1 - cos q); q [rad] from the downward vertical.\n"
             "  Parameters: mass m [kg m^2] (1), omega [rad/s] (2 pi). Initial state q0_1\n"
             "  (pi/2), p0_1 (0). Default --time 10 --steps 500.";
    m.time = 10.0;
    m.steps = 500;
    m.run = [](const member_input& in, const ensemble_setup& e) {
        const pendulum::system sys = pendulum::make_system(in.parameters[0], in.parameters[1]);
        const phase_state<1> x0{vec<1>{in.q0[0]}, vec<1>{in.p0[0]}};
        return with_stepper(e.spec, sys, e.h, e.newton, [&](auto& s) {
            return run_ensemble_member(s, x0, e,
                                       [&](const phase_state<1>& x) { return sys.energy(x); });
        });
    };
    m.section = [](const member_input& in, const ensemble_setup& e, const section_plane& plane,
                   long long crossings) {
        const pendulum::system sys = pendulum::make_system(in.parameters[0], in.parameters[1]);
        const phase_state<1> x0{vec<1>{in.q0[0]}, vec<1>{in.p0[0]}};
        return with_stepper(e.spec, sys, e.h, e.newton,
                            [&](auto& s) { return section_rows(s, x0, e, plane, crossings); });
    };
    return m;
}

} // namespace varsym::cli
