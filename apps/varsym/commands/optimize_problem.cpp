// apps/varsym/commands/optimize_problem.cpp: `varsym optimize`'s options as an optimal control
// problem: the boundary states, the cost's terms, the free final coordinates and their terminal
// weights, the bounds.
#include "commands/optimize_problem.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <set>

#include "models/models.hpp"
#include "options/expression_options.hpp"
#include "varsym/models/expression.hpp"
#include "varsym/models/robot.hpp"
#include "varsym/multibody/spatial.hpp"

namespace varsym::cli {

namespace {

std::vector<double> vector_of(const std::string& list, const char* option, int d,
                              const models::model& m, bool zero_default) {
    std::vector<double> v = parse_number_list(list);
    if (v.empty() && zero_default) v.assign(static_cast<std::size_t>(d), 0.0);
    if (static_cast<int>(v.size()) != d)
        throw usage_error(std::string(option) + " needs " + std::to_string(d) + " values (" +
                          m.coordinates + ") for " + m.name + ", got " + std::to_string(v.size()));
    return v;
}

/// --cost NAME[=WEIGHT][,NAME[=WEIGHT]...]: effort, invariant, power (weight 1 if not given).
optimal::cost_weights cost_of(const std::string& text) {
    optimal::cost_weights w;
    w.effort = 0.0;
    std::size_t at = 0;
    while (at <= text.size()) {
        const std::size_t end = std::min(text.find(',', at), text.size());
        const std::string item = text.substr(at, end - at);
        const std::size_t eq = item.find('=');
        const std::string name = item.substr(0, eq);
        double weight = 1.0;
        if (eq != std::string::npos) {
            const auto v = parse_number_list(item.substr(eq + 1));
            if (v.size() != 1 || !(v[0] >= 0.0))
                throw usage_error("--cost: the weight of " + name + " must be a number >= 0, got " +
                                  shown(item.substr(eq + 1)));
            weight = v[0];
        }
        if (name == "effort")
            w.effort = weight;
        else if (name == "invariant")
            w.invariant = weight;
        else if (name == "power")
            w.power = weight;
        else if (name == "time")
            w.time = weight;
        else
            throw usage_error("--cost: unknown term " + shown(name) +
                              "; the terms are effort, invariant, power and time (e.g. "
                              "--cost power,effort=0.01)");
        at = end + 1;
    }
    return w;
}

/// --free-end q1,v2,…: the freed final coordinates (q) and velocities (v), numbered from 1, with
/// --terminal-weight's weight for each (0 if not given), into the problem.
void free_end_of(const std::string& list, const std::string& weights, int d,
                 optimal::control_problem& p) {
    const std::vector<double> w = parse_number_list(weights);
    p.free_end_position.assign(static_cast<std::size_t>(d), false);
    p.free_end_velocity.assign(static_cast<std::size_t>(d), false);
    p.cost.terminal_position = p.cost.terminal_velocity = Eigen::VectorXd::Zero(d);
    std::set<std::string> seen;
    std::size_t count = 0, at = 0;
    while (!list.empty() && at <= list.size()) {
        const std::size_t end = std::min(list.find(',', at), list.size());
        const std::string item = list.substr(at, end - at);
        int i = 0;
        try {
            std::size_t used = 0;
            i = item.size() >= 2 ? std::stoi(item.substr(1), &used) : 0;
            if (used + 1 != item.size()) i = 0;
        } catch (const std::exception&) {
            i = 0;
        }
        if ((item.empty() || (item[0] != 'q' && item[0] != 'v')) || i < 1 || i > d)
            throw usage_error("--free-end: " + shown(item) + " is not a coordinate: give q1 … q" +
                              std::to_string(d) + " (positions) or v1 … v" + std::to_string(d) +
                              " (velocities), e.g. --free-end q1,v1");
        if (!seen.insert(item).second) throw usage_error("--free-end: " + item + " is given twice");
        const auto k = static_cast<std::size_t>(i - 1);
        const double weight = count < w.size() ? w[count] : 0.0;
        (item[0] == 'q' ? p.free_end_position : p.free_end_velocity)[k] = true;
        (item[0] == 'q' ? p.cost.terminal_position : p.cost.terminal_velocity)(i - 1) = weight;
        ++count;
        at = end + 1;
    }
    if (!w.empty() && w.size() != count)
        throw usage_error("--terminal-weight needs one weight per --free-end entry (" +
                          std::to_string(count) + "), got " + std::to_string(w.size()));
}

/// The three numbers of --reach-position or --reach-rpy.
Eigen::Vector3d three(const std::string& list, const char* option, const char* example) {
    const std::vector<double> v = parse_number_list(list);
    if (v.size() != 3)
        throw usage_error(std::string(option) + " needs 3 values, e.g. " + option + " " + example +
                          ", got " + std::to_string(v.size()));
    return {v[0], v[1], v[2]};
}

std::optional<Eigen::Matrix3d> reach_rotation(const optimize_options& o) {
    if (o.reach_rpy.empty()) return std::nullopt;
    return multibody::roll_pitch_yaw(three(o.reach_rpy, "--reach-rpy", "0,3.14159,0"));
}

/// --reach LINK: the link's target pose (the URDF read again: a few milliseconds), checked here
/// so that a bad link is an error naming --reach.
std::optional<optimal::reach_request> reach_of(const optimize_options& o) {
    if (o.reach.empty()) {
        if (!o.reach_position.empty() || !o.reach_rpy.empty() || o.reach_weight != 0.0)
            throw usage_error("--reach-position, --reach-rpy and --reach-weight need --reach LINK");
        return std::nullopt;
    }
    if (o.model != "urdf")
        throw usage_error("--reach needs a robot (--urdf FILE): it names one of its links");
    if (o.reach_position.empty())
        throw usage_error("--reach needs --reach-position X,Y,Z: where the link's origin must be "
                          "at T [m, world frame]");
    optimal::reach_request r;
    r.frame = o.reach;
    r.position = three(o.reach_position, "--reach-position", "0.5,0,0.6");
    r.rotation = reach_rotation(o);
    r.weight = o.reach_weight;
    try {
        r.robot = models::load_urdf(o.urdf);
        (void)models::frame_target(r.robot, r.frame, r.position, r.rotation);
    } catch (const std::invalid_argument& e) {
        throw usage_error("--reach: " + std::string(e.what()));
    }
    return r;
}

} // namespace

void add_velocity_and_reach_options(CLI::App& cmd, optimize_options& o) {
    cmd.add_option("--max-velocity", o.max_velocity,
                   "Bound |q'| <= V on every coordinate, at the nodes and the steps' quadrature "
                   "points (default: none; a robot's URDF velocity limits)")
        ->transform(positive_number);
    cmd.add_option("--reach", o.reach,
                   "urdf: a link whose frame must reach --reach-position (and --reach-rpy) at T; "
                   "the final joint positions are then free within their limits and --to, if "
                   "given, is only their first guess");
    cmd.add_option("--reach-position", o.reach_position,
                   "The link origin's target at T [m, in the URDF's world frame]")
        ->transform(number_list)
        ->type_name(list_type_name);
    cmd.add_option("--reach-rpy", o.reach_rpy,
                   "The link's target orientation at T: URDF roll, pitch, yaw [rad] (fixed axes "
                   "x, y, z); default: any orientation")
        ->transform(number_list)
        ->type_name(list_type_name);
    cmd.add_option("--reach-weight", o.reach_weight,
                   "0: reach the target exactly (a constraint; an unreachable one exits 3, "
                   "infeasible); W > 0: a terminal cost W/2 (|miss|^2 [m^2] + (2 sin(angle/2))^2, "
                   "about angle^2 [rad^2]) instead")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
}

std::string reach_report(const optimize_options& o, const optimal::model_outcome& out) {
    if (!out.reach_miss) return {};
    char line[240], angle[64] = "";
    if (!o.reach_rpy.empty())
        std::snprintf(angle, sizeof angle, " and %.3g rad", out.reach_miss->angle);
    std::snprintf(line, sizeof line, "varsym optimize: %s ends %.3g m%s from its target\n",
                  o.reach.c_str(), out.reach_miss->distance, angle);
    return line;
}

optimal::model_request request_of(const optimize_options& o, const models::model& m,
                                  std::span<const double> values, const models::lists& lists) {
    const int d = m.dimension_at(values, lists);
    optimal::model_request r;
    r.limits = !o.no_limits;
    r.refine = o.refine;
    optimal::control_problem& p = r.problem;
    p.time = o.time;
    p.steps = o.steps;
    p.scheme = make_spec(o.scheme);
    const auto as_vector = [](const std::vector<double>& v) {
        return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
    };
    p.q_start = as_vector(vector_of(o.from, "--from", d, m, false));
    if (o.to.empty() && o.reach.empty())
        throw usage_error("optimize needs --to (the final joint positions) or --reach LINK (a "
                          "link's target pose)");
    p.q_end = o.to.empty() ? p.q_start : as_vector(vector_of(o.to, "--to", d, m, false));
    p.v_start = as_vector(vector_of(o.from_velocity, "--from-velocity", d, m, true));
    p.v_end = as_vector(vector_of(o.to_velocity, "--to-velocity", d, m, true));
    p.cost = cost_of(o.cost);
    if (p.cost.time > 0.0) { // minimum time: T free, --time its first guess
        p.free_time = true;
        if (!std::isfinite(o.max_control) && (o.no_limits || !m.limits))
            throw usage_error("--cost time needs --max-control (or a robot's URDF efforts, its "
                              "limits kept): with unbounded inputs the motion can be made as fast "
                              "as one likes");
    }
    p.control_lower = Eigen::VectorXd::Constant(1, -o.max_control); // on every input
    p.control_upper = Eigen::VectorXd::Constant(1, o.max_control);
    if (std::isfinite(o.max_velocity)) { // else unbounded, or a robot's URDF velocity limits
        p.velocity_lower = Eigen::VectorXd::Constant(1, -o.max_velocity);
        p.velocity_upper = Eigen::VectorXd::Constant(1, o.max_velocity);
    }
    free_end_of(o.free_end, o.terminal_weight, d, p);
    r.reach = reach_of(o);
    r.solver.max_iterations = o.max_iterations;
    r.threads = o.threads;
    r.solver.options_file = o.ipopt_options;
    r.solver.hessian = optimal::hessian_of(o.hessian); // CLI11 checked the word
    return r;
}

std::shared_ptr<const models::model> optimize_model(const optimize_options& o,
                                                    std::vector<double>& values) {
    // A typed Lagrangian's options would be silently dropped by any other model.
    if (o.model != "lagrangian" && !o.typed_options.empty())
        throw usage_error(o.typed_options.front() +
                          ": --coordinates, --parameters, --inputs and --constraints are a typed "
                          "Lagrangian's options; they need --lagrangian EXPR, not " +
                          (o.model == "urdf" ? std::string("a URDF robot (its inputs are its "
                                                           "actuated joints' torques)")
                                             : "--model " + o.model));
    if (o.model == "urdf") {
        auto robot = robot_model_of(urdf_spec{o.urdf, "", ""});
        values = o.parameters->values(*robot);
        return robot;
    }
    if (o.model == "lagrangian") {
        if (o.lagrangian.empty())
            throw usage_error("--model lagrangian needs --lagrangian EXPR and --inputs NAMES");
        if (o.inputs.empty())
            throw usage_error("--lagrangian needs --inputs: the coordinates the controls act on, "
                              "comma-separated (e.g. --inputs th1,th2)");
        const auto coordinates = split_list(o.coordinates, "--coordinates", "th1,th2");
        const auto parameters = parse_parameters(o.expression_parameters);
        const auto inputs = split_list(o.inputs, "--inputs", "th1,th2");
        const auto constraints = constraints_of(o.constraints, coordinates, parameters);
        try {
            auto m = models::expression_model(o.lagrangian, coordinates, parameters);
            models::add_expression_inputs(m, o.lagrangian, coordinates, parameters, inputs,
                                          constraints);
            values = m.defaults();
            return std::make_shared<const models::model>(std::move(m));
        } catch (const usage_error&) {
            throw;
        } catch (const std::exception& e) { // a parse error, a bad name, an input not a coordinate
            throw usage_error(std::string("--lagrangian: ") + e.what());
        }
    }
    if (!o.urdf.empty() || !o.lagrangian.empty())
        throw usage_error(std::string(o.urdf.empty() ? "--lagrangian" : "--urdf") +
                          " gives the model itself: leave --model " + o.model + " out");
    const models::model& m = [&]() -> const models::model& {
        try {
            return models::get(o.model);
        } catch (const std::invalid_argument& e) {
            throw usage_error(e.what());
        }
    }();
    if (!m.has_inputs()) {
        std::string with;
        for (const auto& other : models::registry())
            if (other.has_inputs()) with += (with.empty() ? "" : ", ") + other.name;
        throw usage_error("model " + m.name +
                          " has no control input to optimise; models with inputs: " + with +
                          ", and a URDF robot (--urdf) or a typed L (--lagrangian --inputs)");
    }
    values = o.parameters->values(m);
    return unowned(m);
}

void hide_simulation_only(CLI::App& cmd) {
    // The parameters only a simulation uses (--push, --torque, a controller's --kp) are hidden
    // from --help where no model with inputs optimises with them, and refused with a word when
    // given (optimize()).
    std::vector<const models::model*> all;
    for (const auto& m : models::registry())
        all.push_back(&m);
    all.push_back(&models::robot_options());
    std::map<std::string, bool> used; // option name → whether an optimisation uses it
    for (const models::model* m : all) {
        if (!m->has_inputs()) continue;
        const auto note = [&](const std::string& key) {
            std::string name = key;
            std::replace(name.begin(), name.end(), '_', '-');
            const bool only = std::find(m->simulation_only.begin(), m->simulation_only.end(),
                                        key) != m->simulation_only.end();
            used[name] = used[name] || !only;
        };
        for (const auto& p : m->parameters)
            note(p.name);
        for (const auto& l : m->lists)
            note(l.name);
    }
    for (const auto& [name, optimising] : used)
        if (!optimising)
            if (auto* opt = cmd.get_option_no_throw("--" + name)) opt->group("");
}

void check_ipopt_options(const std::string& file, file_roles& roles) {
    if (file.empty()) return;
    try {
        for (const auto& o : optimal::parse_ipopt_options(
                 read_regular_file(file, optimal::max_ipopt_options_bytes, "IPOPT options file"),
                 file))
            if (o.name == "output_file") roles.add("--ipopt-options' output_file", o.value);
    } catch (const std::invalid_argument& e) {
        throw usage_error(e.what());
    }
}

} // namespace varsym::cli
