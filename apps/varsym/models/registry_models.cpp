// apps/varsym/models/registry_models.cpp: the models of the models layer (varsym/models/model.hpp)
// as the tool's commands see them: `varsym run` options, help and runs, and `varsym ensemble` and
// `varsym section` models, all generated from each model's one definition.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <map>
#include <optional>

#include "ensemble/ensemble.hpp"
#include "models/model_run.hpp"
#include "models/registry_models.hpp"
#include "varsym/models/event.hpp"
#include "varsym/models/robot.hpp"

namespace varsym::cli {

namespace {

/// The shortest text that reads back as v.
std::string number_text(double v) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return {buf, r.ptr};
}

/// "--masses (value 1 of 2)" or "--mass".
std::string option_text(const models::model& m, const models::parameter& p) {
    std::string o = "--" + p.option_name();
    if (p.option_index < 0) return o;
    int count = 0;
    for (const auto& q : m.parameters)
        count += q.option == p.option ? 1 : 0;
    return o + " (value " + std::to_string(p.option_index + 1) + " of " + std::to_string(count) +
           ")";
}

std::string values_text(const std::vector<double>& v) {
    std::string s;
    for (double x : v)
        s += (s.empty() ? "" : ", ") + number_text(x);
    return s;
}

/// The lines every generated description ends with: parameters, initial state, run length.
std::string parameter_lines(const models::model& m, bool ensemble) {
    std::string s;
    for (const auto& l : m.lists) {
        s += "\n  " + (ensemble ? l.name : "--" + l.option_name());
        if (!l.value.empty()) s += " = " + values_text(l.value);
        if (!l.unit.empty()) s += " [" + l.unit + "]";
        s += ": " + l.doc;
        if (l.range() != "finite") s += "; each " + l.range();
        if (ensemble) s += " (its default in ensembles)";
    }
    for (const auto& p : m.parameters) {
        if (p.flag && !ensemble) {
            s += "\n  " + option_text(m, p) + " (a flag): " + p.doc;
            continue;
        }
        s += "\n  " + (ensemble ? p.name : option_text(m, p)) + " = " + number_text(p.value);
        if (!p.unit.empty()) s += " [" + p.unit + "]";
        s += ": " + p.doc + "; " + p.range();
        if (!p.nan_means.empty()) s += " (nan: " + p.nan_means + ")";
    }
    return s;
}

} // namespace

std::string describe(const models::model& m, bool ensemble) {
    std::string s = m.description;
    if (!m.parameters.empty() || !m.lists.empty())
        s +=
            ensemble ? "\n  Parameters (keys for --grid, --members and --set):" : "\n  Parameters:";
    s += parameter_lines(m, ensemble);
    if (m.fixed_start.empty()) {
        s += ensemble
                 ? "\n  Initial state: q0_1.. (" + values_text(m.q0) + "), p0_1.. (" +
                       values_text(m.p0) + ")"
                 : "\n  Initial state: --q0 " + m.coordinates + " (" + values_text(m.q0) +
                       "), --p0 (" + values_text(m.p0) + ")" + (m.velocities ? " or --v0" : "");
    } else {
        s += "\n  Initial state: from the parameters.";
    }
    if (ensemble)
        s += "\n  Default --time " + number_text(m.ensemble_time) + " --steps " +
             std::to_string(m.ensemble_steps) + ".";
    else if (m.steps_per_period > 0)
        s += "\n  Default " + std::to_string(m.steps_per_period) + " steps per period.";
    else
        s += "\n  Default --time " + number_text(m.time) + " --steps " + std::to_string(m.steps) +
             ".";
    if (ensemble && !m.ensemble_note.empty()) s += "\n  " + m.ensemble_note;
    return s;
}

void parameter_options::add(CLI::App& cmd, const std::function<bool(const models::model&)>& which) {
    // option → what it sets: (the models, their text), models with the same text together
    std::map<std::string, std::vector<std::pair<std::string, std::string>>> texts;
    std::map<std::string, bool> list; // option → whether it takes several values
    std::map<std::string, std::vector<models::parameter>> uses; // each value's range
    auto describe_use = [&](const models::model& m, const std::string& option,
                            const std::string& doc, const std::string& unit) {
        const std::string text = doc + (unit.empty() ? "" : " [" + unit + "]");
        auto& known = texts[option];
        for (auto& [names, t] : known)
            if (t == text) {
                names += ", " + m.name;
                return;
            }
        known.emplace_back(m.name, text);
    };
    std::vector<const models::model*> all;
    for (const auto& m : models::registry())
        all.push_back(&m);
    all.push_back(&models::robot_options()); // `--urdf FILE`'s, the same for every robot
    for (const models::model* mp : all) {
        const models::model& m = *mp;
        if (which && !which(m)) continue;
        for (const auto& p : m.parameters) {
            uses[p.option_name()].push_back(p);
            list[p.option_name()] = list[p.option_name()] || p.option_index >= 0;
            describe_use(m, p.option_name(), p.doc, p.unit);
        }
        for (const auto& l : m.lists) { // a list's values, each checked as a scalar would be
            uses[l.option_name()].push_back(l.each());
            list[l.option_name()] = true;
            describe_use(m, l.option_name(), l.doc, l.unit);
        }
    }
    std::map<std::string, std::string> help; // option → its help text
    for (const auto& [option, known] : texts)
        for (const auto& [names, text] : known)
            help[option] += (help[option].empty() ? "" : "; ") + names + ": " + text;
    for (const auto& [name, text] : help) {
        if (CLI::Option* existing = cmd.get_option_no_throw("--" + name)) { // a mechanism's too
            existing->description(existing->get_description() + "; " + text);
            options_[name] = existing;
        } else if (uses[name].front().flag) { // a switch (the mechanisms' --project)
            options_[name] = cmd.add_flag("--" + name, text);
        } else {
            const bool whole = std::all_of(uses[name].begin(), uses[name].end(),
                                           [](const models::parameter& p) { return p.integer; });
            options_[name] = cmd.add_option("--" + name, text)
                                 ->delimiter(',')
                                 ->type_name(list[name] ? list_type_name
                                             : whole    ? "INT"
                                                        : "FLOAT");
            if (list[name]) options_[name]->expected(1, CLI::detail::expected_max_vector_size);
            // Checked while parsing (so that a config file's line is named) where every model
            // with this option takes the same range; else when the model runs.
            const auto& ps = uses[name];
            const models::parameter first = ps.front();
            if (std::all_of(ps.begin(), ps.end(), [&](const models::parameter& p) {
                    return p.range() == first.range() && p.nan_means == first.nan_means;
                }))
                options_[name]->check(CLI::Validator(
                    [first](std::string& value) -> std::string {
                        double v = 0.0;
                        if (!CLI::detail::lexical_cast(value, v))
                            return shown(value) + " is not a number";
                        try {
                            first.check(v);
                        } catch (const std::invalid_argument& e) {
                            return e.what();
                        }
                        return {};
                    },
                    first.range()));
        }
    }
}

bool parameter_options::given(const std::string& name) const {
    const auto it = options_.find(name);
    return it != options_.end() && it->second->count() > 0;
}

std::vector<std::string> parameter_options::given_names() const {
    std::vector<std::string> out;
    for (const auto& [name, option] : options_)
        if (option->count() > 0) out.push_back(name);
    return out;
}

std::vector<double> parameter_options::values(const models::model& m) const {
    std::vector<double> v = m.defaults();
    for (std::size_t i = 0; i < m.parameters.size(); ++i) {
        const auto& p = m.parameters[i];
        const auto it = options_.find(p.option_name());
        if (it == options_.end() || it->second->count() == 0) continue;
        if (p.flag) {
            v[i] = 1.0;
            continue;
        }
        const std::string option = "--" + p.option_name();
        std::vector<double> given;
        for (const std::string& r : it->second->results()) {
            double x = 0.0;
            if (!CLI::detail::lexical_cast(r, x))
                throw usage_error(option + ": " + shown(r) + " is not a number");
            given.push_back(x);
        }
        int count = 0;
        for (const auto& q : m.parameters)
            count += (q.option_name() == p.option_name()) ? 1 : 0;
        if (static_cast<int>(given.size()) != count)
            throw usage_error(m.name + ": " + option + " needs " + std::to_string(count) +
                              " value" + (count == 1 ? "" : "s") + ", got " +
                              std::to_string(given.size()));
        v[i] = given[static_cast<std::size_t>(std::max(p.option_index, 0))];
    }
    return v;
}

models::lists parameter_options::lists(const models::model& m) const {
    models::lists out(m.lists.size());
    for (std::size_t i = 0; i < m.lists.size(); ++i) {
        const auto it = options_.find(m.lists[i].option_name());
        if (it == options_.end() || it->second->count() == 0) continue;
        for (const std::string& r : it->second->results()) {
            double x = 0.0;
            if (!CLI::detail::lexical_cast(r, x))
                throw usage_error("--" + m.lists[i].option_name() + ": " + shown(r) +
                                  " is not a number");
            out[i].push_back(x);
        }
    }
    return out;
}

void refuse_scheme(const models::model& m, bool given, const std::string& how) {
    if (given && !m.integrator_note.empty())
        throw usage_error("--scheme and --degree do not apply to --model " + m.name + ": " +
                          m.integrator_note + (how.empty() ? "" : " (" + how + ")"));
}

model make_registry_model(const models::model& rm, std::shared_ptr<parameter_options> po) {
    model m;
    m.name = rm.name;
    m.summary = rm.summary;
    m.description = describe(rm, false);
    for (const auto& p : rm.parameters)
        if (std::find(m.options.begin(), m.options.end(), "--" + p.option_name()) ==
            m.options.end())
            m.options.push_back("--" + p.option_name());
    for (const auto& l : rm.lists)
        m.options.push_back("--" + l.option_name());
    m.add_options = [](CLI::App&) {}; // all at once: parameter_options::add
    m.run = [&rm, po](const run_setup& setup) {
        const std::vector<double> values = po->values(rm);
        const models::lists lists = po->lists(rm);
        if (setup.animate.empty()) {
            run_model(rm, setup, values, lists);
            return;
        }
        const int d = rm.dimension_at(values, lists);
        run_animated(
            setup, d, true, [&](const run_setup& r) { run_model(rm, r, values, lists); },
            [&](const frame_recorder& f, const Eigen::MatrixXd& q) {
                write_figure_animation(rm, values, lists, f.t, q, setup.animate, 0.0, setup.quiet,
                                       rm.name);
            });
    };
    return m;
}

void run_model(const models::model& rm, const run_setup& setup, const std::vector<double>& values,
               const models::lists& lists) {
    refuse_scheme(rm, setup.scheme_given, "");
    models::problem pr;
    try {
        pr = rm.prepare(values, {setup.q0, setup.p0, setup.v0}, lists);
    } catch (const std::invalid_argument& e) {
        throw usage_error(e.what());
    }
    run_setup s = setup; // with the model's own integrator, if it has one
    s.method = pr.integrator.label;
    s.method_order = pr.integrator.order;
    s.method_limit = pr.integrator.step_limit;
    if (pr.period == 0.0 && rm.steps_per_period > 0 && !s.by_time && !pr.no_period.empty())
        throw usage_error(rm.name + ": " + pr.no_period);
    const run_plan plan = plan_steps(s, rm.name, pr.period, rm.steps_per_period, rm.time, rm.steps);
    std::unique_ptr<models::simulation> sim;
    try {
        sim = pr.simulate({s.spec, s.newton, plan.h});
    } catch (const std::invalid_argument& e) {
        throw usage_error(rm.name + ": " + e.what());
    }
    if (!sim->conserves_energy() && s.max_energy_error > 0.0)
        throw usage_error("--max-energy-error: " + rm.name +
                          "'s energy is not conserved (it depends on t); leave the energy "
                          "watch out");
    stream_simulation(s, plan, *sim);
}

namespace {

/// A member's q0 or p0 as the model takes it: empty where none of it was given (NaN), the given
/// leading values alone where the model completes such a short start (the four-bar's crank
/// angle), else the given values with the rest from `fallback` (the default start at the
/// member's parameters, made by `fallback()` only when needed).
template <class Fallback>
std::vector<double> start_vector(const models::model& rm, const std::vector<double>& v,
                                 bool may_be_short, Fallback&& fallback) {
    const auto given = std::count_if(v.begin(), v.end(), [](double x) { return !std::isnan(x); });
    if (given == 0) return {};
    if (given == std::ssize(v)) return v;
    const bool leading =
        std::all_of(v.begin(), v.begin() + given, [](double x) { return !std::isnan(x); });
    if (may_be_short && leading &&
        std::find(rm.short_start.begin(), rm.short_start.end(), given) != rm.short_start.end())
        return {v.begin(), v.begin() + given};
    std::vector<double> out = fallback();
    for (std::size_t i = 0; i < v.size() && i < out.size(); ++i)
        if (!std::isnan(v[i])) out[i] = v[i];
    return out;
}

/// The simulation of one member (the start from its q0 and p0 unless the model's start follows
/// from its parameters).
std::unique_ptr<models::simulation>
member_simulation(const models::model& rm, const member_input& in, const ensemble_setup& e) {
    models::start st;
    if (rm.fixed_start.empty()) {
        std::optional<models::problem> defaults;
        auto at = [&](bool q) {
            if (!defaults) defaults = rm.prepare(in.parameters, {});
            return q ? defaults->q0 : defaults->p0;
        };
        st.q0 = start_vector(rm, in.q0, true, [&] { return at(true); });
        st.p0 = start_vector(rm, in.p0, false, [&] { return at(false); });
    }
    const models::problem pr = rm.prepare(in.parameters, st);
    return pr.simulate({e.spec, e.newton, e.h});
}

} // namespace

ensemble_model make_registry_ensemble(std::shared_ptr<const models::model> model) {
    const models::model& rm = *model;
    ensemble_model m;
    m.identity = rm.name;
    m.name = rm.name;
    m.dim = rm.dim;
    m.fixed_start = !rm.fixed_start.empty();
    // Names for the keys q0_NAME: the coordinates "x, theta" where each is a plain identifier
    // and there are d of them ("th_1 ... th_n" is not a list of names). A robot's joint names
    // may also hold spaces and non-ASCII (UTF-8) letters: its reader refuses the commas, quotes,
    // control characters and outer spaces that would make a name ambiguous here. A name may be
    // a number ("1"): the keys then know it, and refuse q0_1 where it means two joints.
    std::vector<std::string> names;
    for (std::size_t at = 0; at <= rm.coordinates.size();) {
        const std::size_t comma = std::min(rm.coordinates.find(',', at), rm.coordinates.size());
        std::string c = rm.coordinates.substr(at, comma - at);
        c.erase(0, c.find_first_not_of(' '));
        c.erase(c.find_last_not_of(' ') + 1);
        names.push_back(c);
        at = comma + 1;
    }
    const bool plain = std::all_of(names.begin(), names.end(), [](const std::string& c) {
        return !c.empty() && std::all_of(c.begin(), c.end(), [](char ch) {
            const auto u = static_cast<unsigned char>(ch);
            return std::isalnum(u) || ch == '_' || ch == '-' || ch == ' ' || u >= 0x80;
        });
    });
    if (plain && std::ssize(names) == rm.dim) m.coordinates = names;
    for (const auto& p : rm.parameters) {
        m.parameters.emplace_back(p.name, p.value);
        if (p.sets_dimension) m.dimension_keys.push_back(p.name);
    }
    m.check_parameter = [model](std::size_t i, double v) { model->parameters.at(i).check(v); };
    if (rm.dimension)
        m.dimension = [model](const std::vector<double>& v) { return model->dimension_at(v); };
    m.help = describe(rm, true);
    m.time = rm.ensemble_time;
    m.steps = rm.ensemble_steps;
    m.run = [model](const member_input& in, const ensemble_setup& e) {
        const auto sim = member_simulation(*model, in, e);
        // Each member evaluates its own copy of the tape: members run concurrently.
        const models::event_function event = e.event ? models::event_of(*e.event) : nullptr;
        return sim->run_member(e.plan, event);
    };
    // Sections need dense output: a probe at the defaults says whether the model's steppers have
    // it (not the rigid bodies' or the constrained mechanisms'; a lagrangian whose default
    // start L refuses: none).
    bool dense = false;
    try {
        dense = rm.prepare(rm.defaults()).simulate({{}, {}, 0.01})->has_dense_output();
    } catch (const std::invalid_argument&) {
    }
    if (dense)
        m.section = [model](const member_input& in, const ensemble_setup& e,
                            const section_plane& plane, long long crossings,
                            const std::function<void(std::string)>& emit) {
            const auto sim = member_simulation(*model, in, e);
            const std::size_t width = 2 * static_cast<std::size_t>(sim->dim());
            const auto rows_of = [&](const models::section_result& r) {
                std::string rows;
                for (std::size_t k = 0; k < r.time.size(); ++k) {
                    append_number(rows, r.time[k]);
                    for (std::size_t i = 0; i < width; ++i) {
                        rows += ',';
                        append_number(rows, r.states[k * width + i]);
                    }
                    rows += '\n';
                }
                return rows;
            };
            const models::section_result rest =
                sim->section(plane, e.plan.steps, crossings, e.plan.stop,
                             [&](const models::section_result& r) { emit(rows_of(r)); });
            emit(rows_of(rest) + (rest.failed ? "failed\n" : ""));
        };
    return m;
}

} // namespace varsym::cli
