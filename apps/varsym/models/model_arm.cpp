// apps/varsym/models/model_arm.cpp: `--model arm`, an n-link planar robot arm under joint PD control
// (problems/arm.hpp), run by the general engine with forces; and the options every mechanism
// shares.
#include <cmath>
#include <memory>

#include "model_run.hpp"
#include "varsym/problems/arm.hpp"
#include "varsym/schemes/variational.hpp"

namespace varsym::cli {

void add_mechanism_options(CLI::App& cmd, mechanism_options& o) {
    auto list = [&cmd](const char* name, std::vector<double>& v, const char* help,
                       const CLI::Validator& check) {
        cmd.add_option(name, v, help)->transform(check)->delimiter(',');
    };
    list("--masses", o.masses,
         "mechanisms: masses [kg] (double-pendulum m1,m2; arm one per link; four-bar crank,"
         "coupler,rocker; slider-crank rod,slider; spherical-pendulum m)",
         positive_number);
    list("--lengths", o.lengths,
         "mechanisms: lengths [m] (double-pendulum l1,l2; arm one per link; four-bar a,b,c,d; "
         "slider-crank r,l; spherical-pendulum l)",
         positive_number);
    list("--inertias", o.inertias,
         "arm: each link's rotational inertia [kg m^2]; slider-crank: the crank's J",
         non_negative_number);
    cmd.add_option("--gravity", o.gravity, "mechanisms: g [m/s^2]")
        ->transform(non_negative_number)
        ->capture_default_str();
    list("--damping", o.damping, "arm: viscous damping per joint [N m s/rad]", non_negative_number);
    list("--kp", o.kp, "arm: proportional gain per joint [N m/rad]", non_negative_number);
    list("--kd", o.kd, "arm: derivative gain per joint [N m s/rad]", non_negative_number);
    cmd.add_option("--target", o.target, "arm: target joint angles [rad]")->delimiter(',');
    cmd.add_option("--move-time", o.move_time,
                   "arm: duration of the minimum-jerk move to --target [s]")
        ->transform(positive_number)
        ->capture_default_str();
    cmd.add_flag("--no-gravity-compensation", o.no_compensation,
                 "arm: leave gravity out of the controller");
    cmd.add_option("--torque", o.torque,
                   "four-bar, slider-crank: constant torque on the crank "
                   "[N m]")
        ->capture_default_str();
    cmd.add_flag("--project", o.project,
                 "constrained mechanisms: move initial data onto the constraints (else "
                 "inconsistent data is refused)");
}

model make_arm_model(std::shared_ptr<mechanism_options> o) {
    model m;
    m.name = "arm";
    m.summary = "n-link planar robot arm, joint PD control to a target, joint damping";
    m.description =
        "  Link i (from the base) has a point mass m_i at its end, length l_i and an optional\n"
        "  rotational inertia J_i; th_i [rad] is its absolute angle from the downward vertical\n"
        "  (q = th), joint angles phi_1 = th_1, phi_i = th_i - th_(i-1). Each joint's torque\n"
        "  tau = Kp (r - phi) + Kd (r' - phi') - c phi' (+ gravity compensation) tracks a\n"
        "  minimum-jerk move r(t) from the initial joint angles to --target over --move-time.\n"
        "  --masses (1,1,1; their count is n), --lengths (1,0.8,0.6), --inertias (0), --gravity\n"
        "  (9.81), --damping (0.5 each) [N m s/rad], --kp (100 each) [N m/rad], --kd (40 each)\n"
        "  [N m s/rad], --target (0.8, 0.5, 0.3 for n = 3; else 0.5 each) [rad], --move-time (2)\n"
        "  [s], --no-gravity-compensation. --q0 th (0 each: hanging), --v0 (0) or --p0.\n"
        "  Columns: energy, work (of damping and controller since t = 0), energy_balance\n"
        "  (energy - E0 - work: the scheme's error), tracking_error (max |phi - r(t)|) [rad].\n"
        "  Not conserved: energy; balanced: energy - work. Default --time 5 --steps 5000.";
    m.options = {"--masses", "--lengths", "--inertias", "--gravity",   "--damping",
                 "--kp",     "--kd",      "--target",   "--move-time", "--no-gravity-compensation"};
    m.add_options = [o](CLI::App& cmd) { add_mechanism_options(cmd, *o); }; // once, for all
    m.run = [o](const run_setup& s) {
        const std::vector<double> masses =
            o->masses.empty() ? std::vector<double>{1, 1, 1} : o->masses;
        const auto n = masses.size();
        std::vector<double> lengths = o->lengths;
        if (lengths.empty()) {
            if (n != 3)
                throw usage_error("arm: give --lengths for the " + std::to_string(n) + " links");
            lengths = {1.0, 0.8, 0.6};
        }
        auto each = [n](const std::vector<double>& v, double fallback) {
            return v.empty() ? std::vector<double>(n, fallback) : v;
        };
        arm::control c;
        c.kp = each(o->kp, 100.0);
        c.kd = each(o->kd, 40.0);
        c.damping = each(o->damping, 0.5);
        c.gravity_compensation = !o->no_compensation;
        const std::vector<double> target =
            !o->target.empty() ? o->target
                               : (n == 3 ? std::vector<double>{0.8, 0.5, 0.3} : each({}, 0.5));
        const int d = static_cast<int>(n);
        try {
            const arm::lagrangian l(masses, lengths, o->gravity, o->inertias);
            const lagrangian_system<arm::lagrangian> sys(l);
            const vec<dynamic> q0 =
                initial_vector(s.q0, "--q0", d, "the link angles", vec<dynamic>::Zero(d));
            const vec<dynamic> v0 =
                initial_vector(s.v0, "--v0", d, "the link rates", vec<dynamic>::Zero(d));
            if (!s.p0.empty() && !s.v0.empty()) throw usage_error("give --p0 or --v0, not both");
            const vec<dynamic> p0 = s.p0.empty() ? sys.momentum(q0, v0)
                                                 : initial_vector(s.p0, "--p0", d, "momenta", {});
            if (static_cast<int>(target.size()) != d)
                throw usage_error("arm: --target needs " + std::to_string(d) + " joint angles");
            const mat<dynamic> b = arm::joint_map(d);
            c.reference.from = b * q0;
            c.reference.to = Eigen::Map<const vec<dynamic>>(target.data(), d);
            c.reference.duration = o->move_time;
            const arm::force f = arm::make_force(l, c);
            if (s.newton.predictor != predictor_kind::taylor)
                throw usage_error("arm runs the general engine: use --predictor taylor");
            const run_plan plan = plan_steps(s, "arm", 0.0, 0, 5.0, 5000);
            general::stepper<arm::lagrangian, arm::force> st(sys, f, plan.h, s.spec, s.newton);
            const phase_state<dynamic> x0{q0, p0};
            sys.check_regular(q0, sys.velocity(q0, p0));
            const double e0 = sys.energy(x0);
            stream_trajectory<dynamic>(
                s, plan, x0, ",energy,work,energy_balance,tracking_error",
                [&st](auto&& fn) { return fn(st); },
                [&](double t, const phase_state<dynamic>& x, std::string& line) {
                    vec<dynamic> r, rate;
                    c.reference(t, r, rate);
                    const double e = sys.energy(x), w = st.total_work();
                    append_values(line,
                                  {e, w, e - e0 - w, (b * x.q - r).lpNorm<Eigen::Infinity>()});
                });
        } catch (const std::invalid_argument& e) {
            throw usage_error(std::string("arm: ") + e.what());
        }
    };
    return m;
}

} // namespace varsym::cli
