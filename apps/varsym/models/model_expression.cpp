// apps/varsym/models/model_expression.cpp: `varsym run --lagrangian EXPR` (the model `lagrangian`): the
// user's own Lagrangian, given as an expression, run by the general engine with its symbolic
// derivatives (the models layer's simulate_expression, shared with the Python package).
#include <charconv>
#include <memory>
#include <numbers>
#include <optional>

#include "expression_options.hpp"
#include "model_run.hpp"
#include "registry_models.hpp"
#include "varsym/models/expression.hpp"

namespace varsym::cli {

namespace {

using expression_system = lagrangian_system<expression_lagrangian>;

std::string trimmed(const std::string& s) {
    const auto a = s.find_first_not_of(" \t");
    if (a == std::string::npos) return {};
    return s.substr(a, s.find_last_not_of(" \t") - a + 1);
}

struct expression_options {
    std::string lagrangian, coordinates = "q", parameters, force;
};

/// The force of --force: components separated by commas (none: the zero force).
expression_force make_force(const std::string& text, const expression_lagrangian& l) {
    if (text.empty()) return expression_force(l.dimension());
    const std::vector<std::string> parts = split_list(text, "--force", "-c*q1_dot,0");
    try {
        return expression_force(parts, l.coordinates(), l.parameters());
    } catch (const std::exception& e) {
        throw usage_error(std::string("--force: ") + e.what());
    }
}

} // namespace

std::vector<std::string> split_list(const std::string& list, const char* option,
                                    const char* example) {
    std::vector<std::string> items;
    std::size_t from = 0;
    for (;;) {
        const auto comma = list.find(',', from);
        const std::string item = trimmed(list.substr(from, comma - from));
        if (item.empty())
            throw usage_error(std::string(option) + ": empty entry in " + shown(list) +
                              " (give entries separated by commas, e.g. " + example + ")");
        items.push_back(item);
        if (comma == std::string::npos) return items;
        from = comma + 1;
    }
}

std::vector<expression_parameter> parse_parameters(const std::string& list) {
    std::vector<expression_parameter> out;
    if (trimmed(list).empty()) return out;
    for (const std::string& entry : split_list(list, "--parameters", "m=1,g=9.81")) {
        const auto eq = entry.find('=');
        const std::string name = trimmed(entry.substr(0, eq));
        const std::string value = eq == std::string::npos ? "" : trimmed(entry.substr(eq + 1));
        double v = 0.0;
        const char* end = value.data() + value.size();
        const auto r = std::from_chars(value.data() + (value.starts_with('+') ? 1 : 0), end, v);
        if (name.empty() || value.empty() || r.ec != std::errc() || r.ptr != end ||
            !std::isfinite(v))
            throw usage_error("--parameters: " + shown(entry) +
                              " is not NAME=NUMBER (e.g. --parameters m=1,g=9.81)");
        out.push_back({name, v});
    }
    return out;
}

model make_expression_model() {
    auto par = std::make_shared<expression_options>();
    model m;
    m.name = "lagrangian";
    m.summary = "your own L(q, qdot, t) given as an expression (--lagrangian), no compiling";
    m.description =
        "  --lagrangian EXPR over the coordinates of --coordinates (default: q), their\n"
        "  velocities NAME_dot, the time t and the parameters of --parameters NAME=VALUE,...\n"
        "  Python syntax: + - * / ** (or ^), parentheses, sin cos tan exp log sqrt sinh cosh\n"
        "  tanh asin acos atan, pi, E. E.g. the pendulum:\n"
        "    --lagrangian \"0.5*m*l**2*th_dot**2 + m*g*l*cos(th)\" --coordinates th\n"
        "    --parameters m=1,g=9.81,l=1 --q0 1\n"
        "  Derivatives are exact (symbolic), evaluated as compiled code. Units: the user's.\n"
        "  Initial state --q0 (0), --v0 (0) or --p0, in the order of --coordinates; columns\n"
        "  q_i, p_i in that order. Conserved: energy, unless L depends on t (then E(t) is\n"
        "  written but not watched). --force f_1,...,f_d adds a generalized force (same\n"
        "  names; units of dL/dq_i), e.g. damping -c*th_dot; then the columns work and\n"
        "  energy_balance (E - E0 - W) follow. No period: default --time 10 --steps 10000.";
    m.options = {"--lagrangian", "--coordinates", "--parameters", "--force"};
    m.add_options = [par](CLI::App& cmd) {
        cmd.add_option("--lagrangian", par->lagrangian,
                       "lagrangian: L as an expression (implies --model lagrangian; see "
                       "'varsym models')");
        cmd.add_option("--coordinates", par->coordinates,
                       "lagrangian: the coordinates' names, comma-separated (velocities: "
                       "NAME_dot)")
            ->capture_default_str();
        cmd.add_option("--parameters", par->parameters,
                       "lagrangian: parameters of the expression, NAME=VALUE,...");
        cmd.add_option("--force", par->force,
                       "lagrangian: a generalized force, one expression per coordinate, "
                       "comma-separated (e.g. -c*th_dot)");
    };
    m.run = [par](const run_setup& s) {
        if (par->lagrangian.empty())
            throw usage_error("--model lagrangian needs --lagrangian EXPR (see 'varsym models')");
        if (s.newton.predictor != predictor_kind::taylor)
            throw usage_error("--predictor previous is for the separable models; --lagrangian "
                              "runs the general engine: use --predictor taylor");
        std::unique_ptr<expression_system> sys;
        try {
            sys = std::make_unique<expression_system>(expression_lagrangian(
                par->lagrangian, split_list(par->coordinates, "--coordinates", "th1,th2"),
                parse_parameters(par->parameters)));
        } catch (const expr::parse_error& e) {
            throw usage_error(std::string("--lagrangian: ") + e.what());
        } catch (const std::invalid_argument& e) {
            throw usage_error(std::string("--lagrangian: ") + e.what());
        }
        const expression_lagrangian& l = sys->lagrangian();
        if (l.depends_on_time() && s.max_energy_error > 0.0)
            throw usage_error("--max-energy-error: this Lagrangian depends on t, so its energy "
                              "is not conserved; leave the energy watch out");
        const int d = l.dimension();
        std::string names;
        for (const auto& c : l.coordinates())
            names += (names.empty() ? "" : ", ") + c;
        if (!s.p0.empty() && !s.v0.empty()) throw usage_error("give --p0 or --v0, not both");
        const vec<dynamic> zero = vec<dynamic>::Zero(d);
        phase_state<dynamic> x0;
        x0.q = initial_vector(s.q0, "--q0", d, names, zero);
        const vec<dynamic> v = initial_vector(s.v0, "--v0", d, "the velocities of " + names, zero);
        try {
            sys->check_regular(x0.q, v, 0.0);
            x0.p = s.p0.empty() ? sys->momentum(x0.q, v, 0.0)
                                : initial_vector(s.p0, "--p0", d, "the momenta of " + names, {});
            sys->check_regular(x0.q, sys->velocity(x0.q, x0.p, 0.0), 0.0);
        } catch (const usage_error&) {
            throw;
        } catch (const std::exception& e) {
            throw usage_error(std::string("--lagrangian: ") + e.what());
        }
        const expression_force force = make_force(par->force, l);
        const run_plan plan = plan_steps(s, "lagrangian", 0.0, 0, 10.0, 10000);
        const auto sim = models::simulate_expression(l, force, x0, {s.spec, s.newton, plan.h});
        stream_simulation(s, plan, *sim);
    };
    return m;
}

} // namespace varsym::cli
