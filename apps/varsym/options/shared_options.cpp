// apps/varsym/options/shared_options.cpp: the pendulum and scheme options shared by subcommands.
#include "options/shared_options.hpp"

namespace varsym::cli {

const char* const pendulum_help =
    "\nThe pendulum: L = (m/2) (dq/dt)^2 - m omega^2 (1 - cos q). q [rad] is the angle from the\n"
    "downward vertical, t [s] the time, m the moment of inertia (m = M l^2 for a mass M on a\n"
    "rod of length l; omega^2 = g/l), p = m dq/dt the angular momentum, energy = p^2/(2m) + V(q).\n"
    "Schemes: newmark (order 2) and simpson (order 4) are the paper's; lobatto and gauss with\n"
    "--degree s are the variational family of order 2s (lobatto 1 = Stormer-Verlet, lobatto 2 =\n"
    "simpson, gauss 1 = newmark).\n";

void add_pendulum_options(CLI::App& cmd, pendulum_options& o) {
    cmd.add_option("--mass", o.mass, "Moment of inertia m [kg m^2]")
        ->transform(positive_number)
        ->capture_default_str();
    cmd.add_option("--omega", o.omega,
                   "Small-oscillation angular frequency omega [rad/s] (default 2 pi)")
        ->transform(positive_number)
        ->capture_default_str();
    cmd.add_option("--q0", o.q0, "Initial angle q(0) [rad] (default pi/2)")
        ->transform(finite_number)
        ->capture_default_str();
    cmd.add_option("--p0", o.p0, "Initial angular momentum p(0) [kg m^2/s]")
        ->transform(finite_number)
        ->capture_default_str();
}

pendulum::system make_system(const pendulum_options& o) {
    try {
        return pendulum::make_system(o.mass, o.omega);
    } catch (const std::invalid_argument& e) {
        throw usage_error(e.what());
    }
}

pendulum::exact_solution make_exact(const pendulum_options& o) {
    try {
        return pendulum::exact_solution(o.mass, o.omega, o.q0, o.p0);
    } catch (const std::invalid_argument& e) {
        throw usage_error(e.what());
    }
}

void add_scheme_options(CLI::App& cmd, scheme_options& o) {
    cmd.add_option("--scheme", o.scheme,
                   "simpson (order 4), newmark (order 2), or the family lobatto|gauss (order 2s)")
        ->check(CLI::IsMember({"simpson", "newmark", "lobatto", "gauss"}))
        ->capture_default_str();
    cmd.add_option("--degree", o.degree,
                   "Degree s of q(t) on a step, for lobatto and gauss (1 to 8; default 2)")
        ->transform(positive_integer);
}

scheme_spec make_spec(const scheme_options& o) {
    const scheme_kind kind = *parse_scheme(o.scheme);
    if (o.degree == 0) return kind;
    if (!has_degree_choice(kind))
        throw usage_error("--degree applies to --scheme lobatto or gauss; " + o.scheme +
                          " has degree " + std::to_string(natural_degree(kind)));
    try {
        return {kind, o.degree};
    } catch (const std::invalid_argument& e) {
        throw usage_error(std::string("--degree: ") + e.what());
    }
}

} // namespace varsym::cli
