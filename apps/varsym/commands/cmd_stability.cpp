// apps/varsym/commands/cmd_stability.cpp: the linear stability limits of the schemes, computed by
// running each stepper on the harmonic oscillator (diagnostics/stability.hpp), for the exit-3
// advice and for `varsym stability`.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>

#include "commands/commands.hpp"
#include "models/models.hpp"
#include "varsym/diagnostics/stability.hpp"
#include "varsym/models/model.hpp"

namespace varsym::cli {

namespace {

/// Scan resolution in h·ω; every edge is then bisected to ~1e-12. No scheme here has an
/// interval of instability (or stability) narrower than 0.01 below 50; the test checks the
/// edges against closed forms.
constexpr double scan_step = 0.01;

/// One step of the unit oscillator (m = 1, ω = 1) with step z from x, by the models layer's
/// oscillator; false if Newton did not converge. The scan steps from two states at each z: the
/// simulation is kept while z stays.
bool unit_oscillator_step(const scheme_spec& spec, double z, phase_state<1>& x) {
    static const models::model& m = models::get("oscillator");
    thread_local std::unique_ptr<models::simulation> sim;
    thread_local scheme_spec sim_spec;
    thread_local double sim_z = 0.0;
    if (!sim || sim_z != z || sim_spec.label() != spec.label()) {
        sim = m.prepare(std::vector<double>{1.0}, {}, {{1.0}, {1.0}})
                  .simulate({spec, newton_options{}, z});
        sim_z = z;
        sim_spec = spec;
    }
    run_state<dynamic> r = run_state<dynamic>::start(phase_state<dynamic>{x.q, x.p});
    try {
        sim->restore(r);
        sim->advance(1);
    } catch (const step_failure&) {
        return false;
    }
    x = phase_state<1>{vec<1>{sim->q()[0]}, vec<1>{sim->p()[0]}};
    return true;
}

std::vector<instability_interval> intervals_of(const scheme_spec& spec, double z_max) {
    return instability_intervals(
        [&](double z, phase_state<1>& x) { return unit_oscillator_step(spec, z, x); }, z_max,
        scan_step);
}

std::vector<scheme_spec> all_specs() {
    std::vector<scheme_spec> specs{scheme_kind::newmark, scheme_kind::simpson};
    for (auto kind : {scheme_kind::lobatto, scheme_kind::gauss})
        for (int s = 1; s <= galerkin::max_degree; ++s)
            specs.emplace_back(kind, s);
    return specs;
}

std::string number(double v) {
    if (std::isinf(v)) return "inf";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.10g", v);
    return buf;
}

struct stability_options {
    double max = stability_scan_end;
    std::string format = "text";
};

void print_table(const stability_options& o) {
    const bool csv = o.format == "csv";
    if (csv) {
        std::cout << "scheme,order,limit,unstable_intervals\n";
    } else {
        std::cout
            << "# Linear stability on the harmonic oscillator: the step map is stable where its\n"
               "# |trace| < 2. Scanned over 0 < h*omega <= "
            << o.max << " in steps of " << scan_step
            << ", edges bisected.\n# limit = where the first instability starts "
               "('none' = stable on the whole scan).\n";
        std::printf("%-11s %5s  %-14s %s\n", "scheme", "order", "limit h*omega",
                    "unstable intervals");
    }
    for (const scheme_spec& spec : all_specs()) {
        const auto iv = intervals_of(spec, o.max);
        std::string list;
        for (const auto& i :
             iv) { // appended piece by piece: GCC 12's -Wrestrict misfires on a + chain
            if (!list.empty()) list += ' ';
            list += '(';
            list += number(i.from);
            list += ';';
            list += number(i.to);
            list += ')';
        }
        const std::string limit = iv.empty() ? "none" : number(iv.front().from);
        if (csv)
            std::cout << spec.label() << ',' << spec.order() << ',' << limit << ',' << list << '\n';
        else
            std::printf("%-11s %5d  %-14s %s\n", spec.label().c_str(), spec.order(), limit.c_str(),
                        list.empty() ? "none" : list.c_str());
    }
}

} // namespace

double linear_stability_limit(const scheme_spec& spec) {
    const auto iv = intervals_of(spec, stability_scan_end);
    return iv.empty() ? std::numeric_limits<double>::infinity() : iv.front().from;
}

void add_stability_command(CLI::App& app, action& todo) {
    auto o = std::make_shared<stability_options>();
    auto* cmd = app.add_subcommand(
        "stability",
        "Compute each scheme's linear stability limit h*omega on the harmonic oscillator");
    cmd->footer(
        "For each scheme, runs its stepper on q'' = -q with step z = h*omega from (1, 0) and (0, "
        "1)\n"
        "to get the 2x2 step map; being symplectic it has determinant 1, so it is stable where\n"
        "|trace| < 2. A run whose highest frequency omega (at the current state, from the\n"
        "Hessian) has h*omega above the limit blows up; 'varsym run' uses this limit to propose\n"
        "a safer step when a step fails. Gauss members are stable at every h*omega; Lobatto\n"
        "members have a finite limit and further unstable intervals.");
    cmd->add_option("--max", o->max, "Scan h*omega up to this value (0.1 to 200: 7 s)")
        ->transform(number_in(0.1, 200.0, "0.1<=Z<=200"))
        ->capture_default_str();
    cmd->add_option("--format", o->format, "text or csv")
        ->check(CLI::IsMember({"text", "csv"}))
        ->capture_default_str();
    cmd->callback([o, &todo] { todo = [o] { print_table(*o); }; });
}

} // namespace varsym::cli
