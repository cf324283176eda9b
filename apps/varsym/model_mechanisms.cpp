// apps/varsym/model_mechanisms.cpp: models with a configuration-dependent mass matrix, run by
// the general engine with automatic derivatives: `--model double-pendulum` and `--model
// heavy-top`.
#include <cmath>
#include <memory>
#include <numbers>

#include "ensemble.hpp"
#include "model_run.hpp"
#include "varsym/problems/double_pendulum.hpp"
#include "varsym/problems/heavy_top.hpp"
#include "varsym/schemes/variational.hpp"

namespace varsym::cli {

namespace {

/// The initial state of a general Lagrangian system: q from --q0, p from --p0, or from --v0
/// through p = dL/dqdot; refuses a singular mass matrix there.
template <class L>
phase_state<L::dim> initial_state(const lagrangian_system<L>& sys, const run_setup& s,
                                  const std::string& names, const vec<L::dim>& q0,
                                  const vec<L::dim>& v0) {
    constexpr int d = L::dim;
    if (!s.p0.empty() && !s.v0.empty()) throw usage_error("give --p0 or --v0, not both");
    const vec<d> q = initial_vector(s.q0, "--q0", d, names, q0);
    const vec<d> v = initial_vector(s.v0, "--v0", d, "the velocities of " + names, v0);
    try {
        sys.check_regular(q, v);
        const vec<d> p =
            s.p0.empty() ? sys.momentum(q, v)
                         : vec<d>(initial_vector(s.p0, "--p0", d, "the momenta of " + names, {}));
        sys.check_regular(q, sys.velocity(q, p));
        return {q, p};
    } catch (const std::exception& e) {
        throw usage_error(e.what());
    }
}

template <class L>
auto general_runner(const run_setup& s, const lagrangian_system<L>& sys, double h) {
    if (s.newton.predictor != predictor_kind::taylor)
        throw usage_error("--predictor previous is for the separable models (the family "
                          "stepper); this model runs the general engine: use --predictor taylor");
    return [&s, &sys, h](auto&& f) {
        general::stepper<L> stepper(sys, h, s.spec, s.newton);
        return f(stepper);
    };
}

} // namespace

model make_double_pendulum_model(std::shared_ptr<mechanism_options> o) {
    auto par = std::make_shared<double_pendulum::lagrangian>();
    model m;
    m.name = "double-pendulum";
    m.summary = "two-link arm (double pendulum) with optional joint springs; M depends on q";
    m.description =
        "  L = (m1+m2) l1^2 th1'^2/2 + m2 l2^2 th2'^2/2 + m2 l1 l2 th1' th2' cos(th1 - th2)\n"
        "      + (m1+m2) g l1 cos th1 + m2 g l2 cos th2 - k (th1^2 + (th2 - th1)^2)/2\n"
        "  q = (th1, th2) [rad] from the downward vertical. Parameters: --masses m1,m2 [kg]\n"
        "  (1,1), --lengths l1,l2 [m] (1,1), --gravity g [m/s^2] (9.81), --joint-stiffness k\n"
        "  [N m/rad] (0). Initial state --q0 (pi/2, pi/2: both links horizontal, a chaotic\n"
        "  energy), --v0 (0, 0) or --p0. Conserved: energy. No exact solution, no period:\n"
        "  default --time 10 --steps 10000.";
    m.options = {"--masses", "--lengths", "--gravity", "--joint-stiffness"};
    m.add_options = [par, o](CLI::App& cmd) {
        add_mechanism_options(cmd, *o); // once, for every mechanism
        cmd.add_option("--joint-stiffness", par->k,
                       "double-pendulum: joint spring stiffness k [N m/rad]")
            ->transform(non_negative_number)
            ->capture_default_str();
    };
    m.run = [par, o](const run_setup& s) {
        double_pendulum::lagrangian l = *par;
        l.g = o->gravity;
        for (auto [list, option] : {std::pair{&o->masses, "--masses"}, {&o->lengths, "--lengths"}})
            if (!list->empty() && list->size() != 2)
                throw usage_error(std::string("double-pendulum: ") + option +
                                  " needs 2 values, got " + std::to_string(list->size()));
        if (!o->masses.empty()) l.m1 = o->masses[0], l.m2 = o->masses[1];
        if (!o->lengths.empty()) l.l1 = o->lengths[0], l.l2 = o->lengths[1];
        const auto sys = double_pendulum::make_system(l);
        const double half_pi = std::numbers::pi / 2;
        const auto x0 = initial_state(sys, s, "th1, th2", vec<2>{half_pi, half_pi}, vec<2>::Zero());
        const run_plan plan = plan_steps(s, "double-pendulum", 0.0, 0, 10.0, 10000);
        stream_trajectory<2>(s, plan, x0, ",energy", general_runner(s, sys, plan.h),
                             [&](double, const phase_state<2>& x, std::string& line) {
                                 append_values(line, {sys.energy(x)});
                             });
    };
    return m;
}

ensemble_model make_double_pendulum_ensemble() {
    ensemble_model m;
    m.name = "double-pendulum";
    m.dim = 2;
    m.q0 = {std::numbers::pi / 2, std::numbers::pi / 2};
    m.p0 = {0.0, 0.0};
    const double_pendulum::lagrangian l0;
    m.parameters = {{"m1", l0.m1}, {"m2", l0.m2}, {"l1", l0.l1},
                    {"l2", l0.l2}, {"g", l0.g},   {"k", l0.k}};
    m.help = "  The double pendulum of `varsym models` (q = th1, th2 [rad] from the downward\n"
             "  vertical; p the momenta dL/dqdot). Parameters: m1, m2 [kg] (1), l1, l2 [m] (1),\n"
             "  g [m/s^2] (9.81), k [N m/rad] (0). Initial state q0 (pi/2, pi/2), p0 (0, 0).\n"
             "  Default --time 20 --steps 10000. A flip of the second link: --event\n"
             "  'q2^2 - pi^2' (|th2| reaches pi).";
    m.time = 20.0;
    m.steps = 10000;
    m.run = [](const member_input& in, const ensemble_setup& e) {
        const auto& v = in.parameters;
        const auto sys = double_pendulum::make_system({v[0], v[1], v[2], v[3], v[4], v[5]});
        const phase_state<2> x0{vec<2>(in.q0[0], in.q0[1]), vec<2>(in.p0[0], in.p0[1])};
        sys.check_regular(x0.q, sys.velocity(x0.q, x0.p));
        general::stepper<double_pendulum::lagrangian> s(sys, e.h, e.spec, e.newton);
        return run_ensemble_member(s, x0, e,
                                   [&](const phase_state<2>& x) { return sys.energy(x); });
    };
    return m;
}

model make_heavy_top_model() {
    auto par = std::make_shared<heavy_top::lagrangian>();
    model m;
    m.name = "heavy-top";
    m.summary = "symmetric heavy (Lagrange) top in Euler angles, closed-form nutation";
    m.description =
        "  L = I1 (th'^2 + phi'^2 sin^2 th)/2 + I3 (psi' + phi' cos th)^2/2 - mgl cos th\n"
        "  q = (th, phi, psi) [rad]: tilt from the upward vertical, precession, spin.\n"
        "  Parameters: --I1 (1), --I3 (0.5) [kg m^2], --mgl (1) [J]. Initial state --q0\n"
        "  (1, 0, 0), --v0 (0, 0.5, 8) [rad/s] or --p0. The Euler angles are singular at\n"
        "  th = 0 and pi. Conserved: energy, p_phi, p_psi (exactly: phi and psi are cyclic).\n"
        "  Exact: th(t) in closed form (q_1_exact). Period: the nutation period; default 100\n"
        "  steps per period.";
    m.options = {"--I1", "--I3", "--mgl"};
    m.add_options = [par](CLI::App& cmd) {
        cmd.add_option("--I1", par->i1,
                       "heavy-top: moment of inertia about a transverse axis [kg m^2]")
            ->transform(positive_number)
            ->capture_default_str();
        cmd.add_option("--I3", par->i3,
                       "heavy-top: moment of inertia about the symmetry axis [kg m^2]")
            ->transform(positive_number)
            ->capture_default_str();
        cmd.add_option("--mgl", par->mgl,
                       "heavy-top: weight times distance to the centre of mass [J]")
            ->transform(positive_number)
            ->capture_default_str();
    };
    m.run = [par](const run_setup& s) {
        const auto sys = heavy_top::make_system(*par);
        const auto x0 =
            initial_state(sys, s, "th, phi, psi", vec<3>{1.0, 0.0, 0.0}, vec<3>{0.0, 0.5, 8.0});
        const heavy_top::nutation nutation = [&] {
            try {
                return heavy_top::nutation(*par, x0);
            } catch (const std::invalid_argument& e) {
                throw usage_error(std::string("heavy-top: ") + e.what());
            }
        }();
        const run_plan plan = plan_steps(s, "heavy-top", nutation.period(), 100, 10.0, 1000);
        stream_trajectory<3>(
            s, plan, x0, ",energy,p_phi,p_psi,q_1_exact", general_runner(s, sys, plan.h),
            [&](double t, const phase_state<3>& x, std::string& line) {
                append_values(line, {sys.energy(x), x.p(1), x.p(2), nutation.theta(t)});
            });
    };
    return m;
}

} // namespace varsym::cli
