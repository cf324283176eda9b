// apps/varsym/model_kepler.cpp: `--model kepler`, the planar two-body problem, exact through
// Kepler's equation.
#include <memory>

#include "model_run.hpp"
#include "varsym/problems/kepler.hpp"
#include "varsym/schemes/scheme_kind.hpp"

namespace varsym::cli {

namespace {
struct kepler_parameters {
    double eccentricity = 0.6, semi_major_axis = 1.0, mu = 1.0;
};
} // namespace

model make_kepler_model() {
    auto par = std::make_shared<kepler_parameters>();
    model m;
    m.name = "kepler";
    m.summary = "planar two-body problem from pericentre, exact orbit by Kepler's equation";
    m.description =
        "  L = |qdot|^2/2 + mu/|q| per unit reduced mass; q = (x, y) the relative position,\n"
        "  mu = G (m1 + m2). Parameters: --eccentricity e in [0, 1) (0.6), --semi-major-axis a\n"
        "  (1), --mu (1). Starts at pericentre (a(1 - e), 0), counter-clockwise; --q0/--p0 do\n"
        "  not apply. Conserved: energy -mu/(2a), angular_momentum x p_y - y p_x (exactly, by\n"
        "  discrete Noether). Exact solution: yes. Period: the orbital period 2 pi sqrt(a^3/mu);\n"
        "  default 200 steps per orbit.";
    m.options = {"--eccentricity", "--semi-major-axis", "--mu"};
    m.add_options = [par](CLI::App& cmd) {
        cmd.add_option("--eccentricity", par->eccentricity, "kepler: eccentricity e, 0 <= e < 1")
            ->transform(eccentricity_range)
            ->capture_default_str();
        cmd.add_option("--semi-major-axis", par->semi_major_axis, "kepler: semi-major axis a")
            ->transform(positive_number)
            ->capture_default_str();
        cmd.add_option("--mu", par->mu, "kepler: gravitational parameter mu = G (m1 + m2)")
            ->transform(positive_number)
            ->capture_default_str();
    };
    m.run = [par](const run_setup& s) {
        if (!s.q0.empty() || !s.p0.empty() || !s.v0.empty())
            throw usage_error(
                "--model kepler starts at pericentre: set the orbit with --eccentricity "
                "and --semi-major-axis instead of --q0/--p0/--v0");
        const kepler::orbit orbit(par->eccentricity, par->semi_major_axis, par->mu);
        const auto sys = kepler::make_system(par->mu);
        const run_plan plan = plan_steps(s, "kepler", orbit.period(), 200, 0.0, 0);
        stream_trajectory<2>(
            s, plan, orbit.at(0.0), ",energy,angular_momentum," + state_columns(2, "_exact"),
            [&](auto&& f) { return with_stepper(s.spec, sys, plan.h, s.newton, f); },
            [&](double t, const phase_state<2>& x, std::string& line) {
                const auto ref = orbit.at(t);
                append_values(line, {sys.energy(x), kepler::angular_momentum(x), ref.q(0), ref.q(1),
                                     ref.p(0), ref.p(1)});
            });
    };
    return m;
}

} // namespace varsym::cli
