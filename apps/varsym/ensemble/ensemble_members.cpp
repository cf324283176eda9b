// apps/varsym/ensemble/ensemble_members.cpp: the models, members and event of `varsym ensemble`.
#include "ensemble/ensemble_members.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string_view>

#include <boost/crc.hpp>

#include "models/models.hpp"
#include "models/registry_models.hpp"
#include "options/expression_options.hpp"
#include "output/files.hpp"
#include "varsym/models/event.hpp"

namespace varsym::cli {

namespace {

/// A whole string as a number ("nan" allowed where `nan_ok`), else usage_error naming `what`.
double number(std::string_view s, const std::string& what, bool nan_ok = false) {
    double v = 0.0;
    const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || p != s.data() + s.size() || (!nan_ok && !std::isfinite(v)))
        throw usage_error(what + ": " + shown(std::string(s)) + " is not a finite number");
    return v;
}

std::vector<std::string_view> split(std::string_view s, char sep) {
    std::vector<std::string_view> out;
    for (std::size_t at = 0;;) {
        const std::size_t end = s.find(sep, at);
        out.push_back(s.substr(at, end == std::string_view::npos ? end : end - at));
        if (end == std::string_view::npos) return out;
        at = end + 1;
    }
}

void add_identity(std::string& id, const char* name, const std::vector<double>& v) {
    id += ' ';
    id += name;
    for (std::size_t i = 0; i < v.size(); ++i) {
        id += i == 0 ? '=' : ':';
        append_number(id, v[i]);
    }
}

} // namespace

/// Where key `k` goes for `model`: q0_i, p0_i (1 ≤ i ≤ d), q0_NAME, p0_NAME (NAME a
/// coordinate's name) or a parameter's name. A key that is both (a joint named "2" that is not
/// the second coordinate) is refused: the column q_2 of `run` names the joint.
std::pair<int, std::size_t> target_of(const std::string& k, const ensemble_model& model) {
    for (int kind = 0; kind < 2 && !model.fixed_start; ++kind) {
        const std::string prefix = kind == 0 ? "q0_" : "p0_";
        if (!k.starts_with(prefix)) continue;
        const std::string rest = k.substr(prefix.size());
        const auto named = std::find(model.coordinates.begin(), model.coordinates.end(), rest);
        const bool by_name = named != model.coordinates.end();
        const auto j = static_cast<std::size_t>(named - model.coordinates.begin());
        std::size_t i = 0;
        const auto [p, ec] = std::from_chars(rest.data(), rest.data() + rest.size(), i);
        if (ec == std::errc() && p == rest.data() + rest.size() && i >= 1 &&
            i <= static_cast<std::size_t>(model.dim)) {
            if (by_name && j != i - 1)
                throw usage_error("'" + k + "' is ambiguous for " + model.name + ": coordinate " +
                                  std::to_string(i) + ", or the coordinate named '" + rest +
                                  "' (coordinate " + std::to_string(j + 1) +
                                  "); rename that joint");
            if (!by_name && k != prefix + std::to_string(i)) // q0_01: one spelling per key
                throw usage_error("'" + k + "' is not a key of " + model.name + "; did you mean " +
                                  prefix + std::to_string(i) + "?");
            return {kind, i - 1};
        }
        if (by_name) return {kind, j}; // q0_NAME
    }
    for (std::size_t j = 0; j < model.parameters.size(); ++j)
        if (model.parameters[j].first == k) return {2, j};
    std::string known;
    for (int i = 1; i <= (model.fixed_start ? 0 : model.dim); ++i)
        known += " q0_" + std::to_string(i) + " p0_" + std::to_string(i);
    for (const std::string& c : model.fixed_start ? std::vector<std::string>{} : model.coordinates)
        known += " q0_" + c + " p0_" + c;
    for (const auto& p : model.parameters)
        known += " " + p.first;
    throw usage_error("'" + k + "' is not a key of " + model.name + "; its keys:" + known);
}

void add_member_options(CLI::App& cmd, member_options& o) {
    cmd.add_option("--grid", o.grid,
                   "KEY=FIRST:LAST:COUNT, one axis of a grid of members (repeat for more axes; "
                   "the last varies fastest); KEY is q0_I, p0_I or a model parameter");
    cmd.add_option("--members", o.members_file,
                   "CSV file of members instead of --grid: a header of keys, one row each");
    cmd.add_option("--q0", o.q0, "Initial coordinates of every member before the keys apply")
        ->delimiter(',')
        ->transform(finite_number);
    cmd.add_option("--p0", o.p0, "Initial momenta of every member before the keys apply")
        ->delimiter(',')
        ->transform(finite_number);
    cmd.add_option("--set", o.set, "NAME=VALUE: a model parameter for every member (repeat)");
}

void add_member_run_options(CLI::App& cmd, member_run_options& o, const std::string& models) {
    cmd.add_option("--model", o.model,
                   "Model: " + models + " (--lagrangian implies lagrangian, --urdf urdf)");
    add_expression_options(cmd, o.expression);
    add_urdf_option(cmd, o.urdf);
    add_scheme_options(cmd, o.scheme);
    cmd.add_option("--time", o.time, "Length of every member's run (default: the model's)")
        ->transform(positive_number);
    cmd.add_option("--steps", o.steps, "Steps of every member's run (default: the model's)")
        ->transform(positive_integer);
    add_member_options(cmd, o.members);
}

ensemble_setup make_setup(const member_run_options& o, const ensemble_model& model,
                          std::size_t members) {
    ensemble_setup setup;
    setup.spec = make_spec(o.scheme);
    const double time = o.time > 0 ? o.time : model.time;
    setup.plan.steps = o.steps > 0 ? o.steps : model.steps;
    setup.h = time / static_cast<double>(setup.plan.steps);
    if (static_cast<double>(members) * static_cast<double>(setup.plan.steps) > max_run_steps) {
        std::string limit;
        append_number(limit, max_run_steps);
        throw usage_error("more than " + limit + " steps requested (members times steps)");
    }
    return setup;
}

member_set make_member_set(const member_options& o, ensemble_model& model) {
    member_set s;
    if (model.fixed_start && (!o.q0.empty() || !o.p0.empty()))
        throw usage_error(model.name + " starts from its parameters: --q0 and --p0 do not apply");
    for (const auto& p : model.parameters)
        s.base.parameters.push_back(p.second);
    for (const auto& a : o.set) {
        const std::size_t eq = a.find('=');
        if (eq == std::string::npos) throw usage_error("--set needs NAME=VALUE, got " + shown(a));
        const auto [kind, i] = target_of(a.substr(0, eq), model);
        if (kind != 2) throw usage_error("--set is for parameters; use --q0/--p0 for " + shown(a));
        s.base.parameters[i] = number(std::string_view(a).substr(eq + 1), "--set", true);
        // One value for every member: one bad input, refused before any member runs (a count
        // that sets d is allocated by every member).
        if (model.check_parameter) try {
                model.check_parameter(i, s.base.parameters[i]);
            } catch (const std::invalid_argument& e) {
                throw usage_error("--set " + a.substr(0, eq) + ": " + e.what());
            }
    }
    if (model.dimension) model.dim = model.dimension(s.base.parameters);
    const auto d = static_cast<std::size_t>(model.dim);
    // What --q0 and --p0 do not give is the model's default start at each member's parameters.
    const double unset = std::numeric_limits<double>::quiet_NaN();
    s.base.q0 = o.q0.empty() ? std::vector<double>(d, unset) : o.q0;
    s.base.p0 = o.p0.empty() ? std::vector<double>(d, unset) : o.p0;
    if (s.base.q0.size() != d || s.base.p0.size() != d)
        throw usage_error("--q0 and --p0 need " + std::to_string(d) + " values for " + model.name);
    if (!o.grid.empty() && !o.members_file.empty())
        throw usage_error("give --grid or --members, not both");
    if (o.grid.empty() && o.members_file.empty())
        throw usage_error("no members: give --grid KEY=FIRST:LAST:COUNT or --members FILE.csv");
    if (!o.grid.empty()) {
        s.identity = "grid";
        for (const auto& g : o.grid) {
            const std::size_t eq = g.find('=');
            const auto parts =
                split(std::string_view(g).substr(eq == std::string::npos ? 0 : eq + 1), ':');
            if (eq == std::string::npos || parts.size() != 3)
                throw usage_error("--grid needs KEY=FIRST:LAST:COUNT, got " + shown(g));
            grid_axis a{g.substr(0, eq), number(parts[0], "--grid " + g.substr(0, eq)),
                        number(parts[1], "--grid " + g.substr(0, eq)), 0};
            const double count = number(parts[2], "--grid " + a.name + " count");
            if (!(count >= 1 && count <= 1e9 && count == std::floor(count)))
                throw usage_error("--grid " + a.name +
                                  ": the count must be a whole number "
                                  "from 1 to 1e9, got " +
                                  shown(std::string(parts[2])));
            a.count = static_cast<std::size_t>(count);
            s.keys.push_back(a.name);
            s.identity += ' ' + a.name + '=';
            append_number(s.identity, a.first);
            s.identity += ':';
            append_number(s.identity, a.last);
            s.identity += ':' + std::to_string(a.count);
            s.axes.push_back(a);
        }
        s.size = grid(s.axes).size();
        if (s.size > 1'000'000'000) throw usage_error("more than 1e9 members");
    } else {
        const std::string text =
            read_regular_file(o.members_file, std::uint64_t{1} << 32, "--members file");
        boost::crc_32_type crc;
        crc.process_bytes(text.data(), text.size());
        s.identity = "members=" + std::filesystem::absolute(o.members_file).string() +
                     " crc=" + std::to_string(crc.checksum());
        std::size_t line_no = 0;
        // A UTF-8 byte-order mark (spreadsheets write one) is not part of the first key.
        const std::string_view body = std::string_view(text).starts_with("\xEF\xBB\xBF")
                                          ? std::string_view(text).substr(3)
                                          : std::string_view(text);
        for (std::string_view line : split(body, '\n')) {
            ++line_no;
            if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
            if (line.empty() || line.front() == '#') continue;
            const auto fields = split(line, ',');
            if (s.keys.empty()) {
                for (auto f : fields)
                    s.keys.emplace_back(f);
                continue;
            }
            if (fields.size() != s.keys.size())
                throw usage_error(o.members_file + " line " + std::to_string(line_no) + ": " +
                                  std::to_string(fields.size()) + " values for " +
                                  std::to_string(s.keys.size()) + " keys");
            for (auto f : fields)
                s.table.push_back(number(f, o.members_file + " line " + std::to_string(line_no)));
            ++s.size;
        }
        if (s.size == 0)
            throw usage_error(o.members_file + " has no members (a header, then rows)");
    }
    for (const auto& k : s.keys) {
        if (std::count(s.keys.begin(), s.keys.end(), k) > 1)
            throw usage_error("the key " + k + " is given twice");
        const auto target = target_of(k, model);
        const auto same = std::find(s.targets.begin(), s.targets.end(), target);
        if (same != s.targets.end()) // q0_1 and q0_NAME of the same coordinate
            throw usage_error("the keys " +
                              s.keys[static_cast<std::size_t>(same - s.targets.begin())] + " and " +
                              k + " set the same value; give it once");
        s.targets.push_back(target);
        if (std::find(model.dimension_keys.begin(), model.dimension_keys.end(), k) !=
            model.dimension_keys.end())
            throw usage_error(k +
                              " sets the number of coordinates, which the members share: give "
                              "it with --set " +
                              k + "=VALUE, not as a member's key");
    }
    add_identity(s.identity, "q0", s.base.q0);
    add_identity(s.identity, "p0", s.base.p0);
    add_identity(s.identity, "parameters", s.base.parameters);
    return s;
}

void member_set::values(std::size_t m, std::vector<double>& out) const {
    if (!axes.empty()) {
        grid(axes).point(m, out);
        return;
    }
    const auto* row = table.data() + m * keys.size();
    out.assign(row, row + keys.size());
}

member_input member_set::input(const std::vector<double>& v) const {
    member_input in = base;
    for (std::size_t k = 0; k < v.size(); ++k) {
        const auto [kind, i] = targets[k];
        (kind == 0 ? in.q0 : kind == 1 ? in.p0 : in.parameters)[i] = v[k];
    }
    return in;
}

std::vector<ensemble_model> ensemble_models() {
    std::vector<ensemble_model> all;
    for (const models::model& m : models::registry())
        all.push_back(make_registry_ensemble(unowned(m)));
    return all;
}

void add_member_inputs(file_roles& roles, const member_run_options& o) {
    roles.add("--urdf", o.urdf.path);
    roles.add("--members", o.members.members_file);
}

ensemble_model find_ensemble_model(const member_run_options& given) {
    member_run_options o = given;
    if (o.model.empty()) {
        if (!o.expression.lagrangian.empty())
            o.model = "lagrangian";
        else if (!o.urdf.path.empty())
            o.model = "urdf";
        else
            throw usage_error("--model is required (one of " + ensemble_model_names() + ")");
    }
    if (o.model == "urdf") {
        // The robot's absolute path and content: a journal of another robot, or of this one
        // before an edit, belongs to another ensemble.
        checkpoint::input_file file;
        ensemble_model m = make_registry_ensemble(robot_model_of(o.urdf, &file));
        m.identity = "urdf file=[" + file.path + "] " + file.digest + " torques=[" +
                     o.urdf.torques + "]" +
                     (o.urdf.base.empty() || o.urdf.base == "fixed" ? "" : " base=" + o.urdf.base);
        std::replace_if(
            m.identity.begin(), m.identity.end(), [](char c) { return c == '\n' || c == '\r'; },
            ' ');
        return m;
    }
    if (!o.urdf.path.empty())
        throw usage_error("--urdf is for --model urdf, not " + shown(o.model));
    if (!o.urdf.base.empty())
        throw usage_error("--base is for --model urdf, not " + shown(o.model));
    if (o.model == "lagrangian") {
        ensemble_model m = make_registry_ensemble(expression_model_of(o.expression));
        m.identity = "lagrangian L=[" + o.expression.lagrangian + "] coordinates=[" +
                     o.expression.coordinates + "] parameters=[" + o.expression.parameters +
                     "] force=[" + o.expression.force + "] constraints=[" +
                     o.expression.constraints + "]";
        std::replace_if(
            m.identity.begin(), m.identity.end(), [](char c) { return c == '\n' || c == '\r'; },
            ' ');
        return m;
    }
    if (!o.expression.lagrangian.empty())
        throw usage_error("--lagrangian is for --model lagrangian, not " + shown(o.model));
    for (auto& m : ensemble_models())
        if (m.name == o.model) return m;
    throw usage_error("varsym ensemble has no model " + shown(o.model) + "; it runs " +
                      ensemble_model_names());
}

std::string ensemble_model_names() {
    std::string s;
    for (const auto& m : ensemble_models())
        s += (s.empty() ? "" : ", ") + m.name;
    return s + ", lagrangian, urdf";
}

expr::tape compile_event(const std::string& text, int d) {
    try {
        return models::compile_event(text, d);
    } catch (const std::invalid_argument& e) {
        throw usage_error(std::string("--event: ") + e.what() + " (names: q1..q" +
                          std::to_string(d) + ", p1..p" + std::to_string(d) + ", t)");
    }
}

std::string state_columns_of(int d) {
    std::string cols;
    for (const char* name : {"q_", "p_"})
        for (int i = 1; i <= d; ++i) {
            if (!cols.empty()) cols += ',';
            cols.append(name).append(std::to_string(i));
        }
    return cols;
}

} // namespace varsym::cli
