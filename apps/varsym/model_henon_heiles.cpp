// apps/varsym/model_henon_heiles.cpp: `--model henon-heiles` for `varsym run` and `varsym
// ensemble`: the Hénon–Heiles system (varsym/problems/henon_heiles.hpp).
#include <cmath>
#include <limits>
#include <memory>

#include "ensemble.hpp"
#include "model_run.hpp"
#include "varsym/problems/henon_heiles.hpp"

namespace varsym::cli {

namespace {

constexpr const char* description =
    "  L = (x'^2 + y'^2)/2 - V, V = (x^2 + y^2)/2 + x^2 y - y^3/3 (Henon and Heiles 1964;\n"
    "  dimensionless, unit mass, p = q'). Bounded below the escape energy 1/6. Parameters:\n"
    "  --energy E: p_x >= 0 is computed from E at the initial q and p_y, replacing the first\n"
    "  --p0 value (a state outside that energy surface is refused). Initial state --q0\n"
    "  (0, 0.1), --p0 (p_x, p_y) (0, 0) with --energy 0.125 by default. Conserved: energy.\n"
    "  No exact solution, no period: default --time 200 --steps 4000 (h = 0.05).";

/// The initial state: p_x from the energy where one is given (finite).
phase_state<2> start(const vec<2>& q, vec<2> p, double energy) {
    if (std::isfinite(energy)) {
        const double px2 = 2.0 * (energy - henon_heiles::potential{}.value(q)) - p(1) * p(1);
        if (!(px2 >= 0.0))
            throw std::invalid_argument("the initial q and p_y lie outside the energy surface "
                                        "E = " +
                                        std::to_string(energy));
        p(0) = std::sqrt(px2);
    }
    return {q, p};
}

} // namespace

model make_henon_heiles_model() {
    auto energy = std::make_shared<double>(0.125);
    model m;
    m.name = "henon-heiles";
    m.summary = "Henon-Heiles: two coupled oscillators, ordered and chaotic orbits";
    m.description = description;
    m.options = {"--energy"};
    m.add_options = [energy](CLI::App& cmd) {
        cmd.add_option("--energy", *energy,
                       "henon-heiles: energy E, sets p_x >= 0 (NaN or 'nan': use --p0 as given)")
            ->capture_default_str();
    };
    m.run = [energy](const run_setup& s) {
        const auto sys = henon_heiles::make_system();
        phase_state<2> x0;
        try {
            x0 = start(initial_vector(s.q0, "--q0", 2, "x, y", vec<dynamic>{{0.0, 0.1}}),
                       initial_vector(s.p0, "--p0", 2, "p_x, p_y", vec<dynamic>{{0.0, 0.0}}),
                       *energy);
        } catch (const std::invalid_argument& e) {
            throw usage_error(std::string("henon-heiles: ") + e.what());
        }
        if (!s.v0.empty()) throw usage_error("henon-heiles has p = q': give --p0, not --v0");
        const run_plan plan = plan_steps(s, "henon-heiles", 0.0, 0, 200.0, 4000);
        stream_trajectory<2>(
            s, plan, x0, ",energy",
            [&](auto&& f) { return with_stepper(s.spec, sys, plan.h, s.newton, f); },
            [&](double, const phase_state<2>& x, std::string& line) {
                append_values(line, {sys.energy(x)});
            });
    };
    return m;
}

ensemble_model make_henon_heiles_ensemble() {
    ensemble_model m;
    m.name = "henon-heiles";
    m.dim = 2;
    m.q0 = {0.0, 0.1};
    m.p0 = {0.0, 0.0};
    m.parameters = {{"energy", 0.125}};
    m.help = "  V = (x^2 + y^2)/2 + x^2 y - y^3/3, unit mass, p = q' (as in `varsym models`).\n"
             "  Parameter: energy (0.125): p_x >= 0 from E at q0 and p0_2, replacing p0_1 (a\n"
             "  member outside that energy surface is invalid); energy=nan uses p0 as given.\n"
             "  Initial state q0 (0, 0.1), p0 (0, 0). Default --time 1000 --steps 20000.\n"
             "  The section x = 0: --grid q0_2=... --grid p0_2=... with energy set.";
    m.time = 1000.0;
    m.steps = 20000;
    m.run = [](const member_input& in, const ensemble_setup& e) {
        const auto sys = henon_heiles::make_system();
        const phase_state<2> x0 =
            start(vec<2>(in.q0[0], in.q0[1]), vec<2>(in.p0[0], in.p0[1]), in.parameters[0]);
        return with_stepper(e.spec, sys, e.h, e.newton, [&](auto& s) {
            return run_ensemble_member(s, x0, e,
                                       [&](const phase_state<2>& x) { return sys.energy(x); });
        });
    };
    m.section = [](const member_input& in, const ensemble_setup& e, const section_plane& plane,
                   long long crossings) {
        const auto sys = henon_heiles::make_system();
        const phase_state<2> x0 =
            start(vec<2>(in.q0[0], in.q0[1]), vec<2>(in.p0[0], in.p0[1]), in.parameters[0]);
        return with_stepper(e.spec, sys, e.h, e.newton,
                            [&](auto& s) { return section_rows(s, x0, e, plane, crossings); });
    };
    return m;
}

} // namespace varsym::cli
