// apps/varsym/models/model_expression.cpp: the options of the model `lagrangian`, the user's own
// Lagrangian given as an expression (--lagrangian EXPR): parsed into the models layer's
// expression_model, which `varsym run` and `varsym ensemble` run like any registry model.
#include <charconv>
#include <memory>
#include <numbers>

#include "models/model_run.hpp"
#include "models/registry_models.hpp"
#include "options/expression_options.hpp"
#include "varsym/models/expression.hpp"

namespace varsym::cli {

namespace {

std::string trimmed(const std::string& s) {
    const auto a = s.find_first_not_of(" \t");
    if (a == std::string::npos) return {};
    return s.substr(a, s.find_last_not_of(" \t") - a + 1);
}

/// The components of --force, checked over the coordinates and parameters (none: no force).
std::vector<std::string> force_of(const std::string& text,
                                  const std::vector<std::string>& coordinates,
                                  const std::vector<expression_parameter>& parameters) {
    if (text.empty()) return {};
    std::vector<std::string> parts = split_list(text, "--force", "-c*q1_dot,0");
    if (parts.size() != coordinates.size())
        throw usage_error("--force: " + std::to_string(parts.size()) +
                          " components for the Lagrangian's " + std::to_string(coordinates.size()) +
                          " coordinates");
    try {
        (void)expression_force(parts, coordinates, parameters);
    } catch (const std::exception& e) {
        throw usage_error(std::string("--force: ") + e.what());
    }
    return parts;
}

} // namespace

std::vector<std::string> constraints_of(const std::string& text,
                                        const std::vector<std::string>& coordinates,
                                        const std::vector<expression_parameter>& parameters) {
    if (text.empty()) return {};
    std::vector<std::string> parts = split_list(text, "--constraints", "x**2+y**2-l**2");
    try {
        (void)expression_constraint(parts, coordinates, parameters);
    } catch (const std::exception& e) {
        throw usage_error(std::string("--constraints: ") + e.what());
    }
    return parts;
}

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

std::shared_ptr<const models::model> expression_model_of(const expression_spec& e) {
    if (e.lagrangian.empty())
        throw usage_error("--model lagrangian needs --lagrangian EXPR (see 'varsym models')");
    const std::vector<std::string> coordinates =
        split_list(e.coordinates, "--coordinates", "th1,th2");
    const std::vector<expression_parameter> parameters = parse_parameters(e.parameters);
    // The force and constraints are checked first, alone, so that what the layer refuses next
    // is L's.
    const std::vector<std::string> force = force_of(e.force, coordinates, parameters);
    const std::vector<std::string> constraints =
        constraints_of(e.constraints, coordinates, parameters);
    try {
        return std::make_shared<const models::model>(
            models::expression_model(e.lagrangian, coordinates, parameters, force, constraints));
    } catch (const std::exception& err) { // a parse error, a bad name, the size guard
        throw usage_error(std::string("--lagrangian: ") + err.what());
    }
}

void add_expression_options(CLI::App& cmd, expression_spec& e) {
    cmd.add_option("--lagrangian", e.lagrangian,
                   "lagrangian: L as an expression (implies --model lagrangian; see "
                   "'varsym models')");
    cmd.add_option("--coordinates", e.coordinates,
                   "lagrangian: the coordinates' names, comma-separated (velocities: NAME_dot)")
        ->capture_default_str();
    cmd.add_option("--parameters", e.parameters,
                   "lagrangian: parameters of the expression, NAME=VALUE,...");
    cmd.add_option("--force", e.force,
                   "lagrangian: a generalized force, one expression per coordinate, "
                   "comma-separated (e.g. -c*th_dot)");
    cmd.add_option("--constraints", e.constraints,
                   "lagrangian: holonomic constraints g(q) = 0, one expression per equation, "
                   "comma-separated (e.g. x**2+y**2-l**2)");
}

model make_expression_model(std::shared_ptr<parameter_options> po) {
    auto par = std::make_shared<expression_spec>();
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
        "  q_i, p_i in that order. Conserved: energy; where L depends on t or there is a\n"
        "  force, E - W (W = integral of f.qdot - dL/dt: the columns work, energy_balance),\n"
        "  which the energy watch follows. --force f_1,...,f_d adds a generalized force (same\n"
        "  names; units of dL/dq_i), e.g. damping -c*th_dot; then the columns work and\n"
        "  energy_balance (E - E0 - W) follow. --constraints g_1,...,g_m adds holonomic\n"
        "  constraints g(q) = 0 (no velocities, no t), run by the constrained engine\n"
        "  (Newton): then the columns work, energy_balance, constraint_residual,\n"
        "  hidden_residual, lambda_1..m; the start must be on the constraints with a tangent\n"
        "  velocity, or --project moves it there. No period: default --time 10 --steps 10000.\n"
        "  Ensembles take the same options; their keys are q0_I, p0_I and the names of\n"
        "  --parameters (default run: 10 s in 1000 steps); converge takes q0_I, p0_I and\n"
        "  the parameters by --set. Sections: on the step's own polynomial (dense output;\n"
        "  not with --constraints).";
    m.options = {"--lagrangian", "--coordinates", "--parameters",
                 "--force",      "--constraints", "--project"};
    m.add_options = [par](CLI::App& cmd) { add_expression_options(cmd, *par); };
    m.run = [par, po](const run_setup& s) {
        // --predictor previous/forces: taken where L is separable (the models layer refuses it
        // where L runs the general engine).
        const bool project = po && po->given("project");
        if (project && par->constraints.empty())
            throw usage_error("--project moves the start onto the constraints: it needs "
                              "--constraints");
        const auto em = expression_model_of(*par);
        // L's parameters come from --parameters; --project is the flag a model with
        // --constraints has (the constrained models' parameter `project`, its last).
        std::vector<double> values = em->defaults();
        if (project) values.back() = 1.0;
        run_model(*em, s, values, {});
    };
    return m;
}

} // namespace varsym::cli
