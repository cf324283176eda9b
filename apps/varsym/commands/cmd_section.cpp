// apps/varsym/commands/cmd_section.cpp: `varsym section`, Poincaré sections: the crossings of a
// plane q_i = c or p_i = c by orbits from a grid or a CSV file of initial states (the members of
// `varsym ensemble`), located on each step's interpolating polynomial and refined on the
// scheme's own map (varsym/run/section.hpp); CSV in member order and a scatter plot.
#include <algorithm>
#include <atomic>
#include <charconv>
#include <cstdio>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "commands/commands.hpp"
#include "ensemble/ensemble_members.hpp"
#include "ensemble/ensemble_writer.hpp"
#include "models/models.hpp"
#include "options/shared_options.hpp"
#include "output/files.hpp"
#include "output/plot.hpp"

namespace varsym::cli {

namespace {

struct section_options {
    member_run_options run;
    std::string plane = "q1=0";
    std::string direction = "+";
    long long crossings = 500;
    unsigned threads = 0;
    std::string output;
    std::vector<std::string> plot;
    std::string plot_columns;
};

section_plane parse_plane(const std::string& text, const std::string& direction, int d) {
    section_plane p;
    const std::size_t eq = text.find('=');
    const std::string key = text.substr(0, eq);
    std::size_t i = 0;
    const auto [end, ec] = key.size() > 1
                               ? std::from_chars(key.data() + 1, key.data() + key.size(), i)
                               : std::from_chars_result{key.data(), std::errc::invalid_argument};
    if (eq == std::string::npos || (key[0] != 'q' && key[0] != 'p') || ec != std::errc() ||
        end != key.data() + key.size() || i < 1 || i > static_cast<std::size_t>(d))
        throw usage_error("--plane needs qI=VALUE or pI=VALUE with I from 1 to " +
                          std::to_string(d) + ", got " + shown(text));
    const std::string value = text.substr(eq + 1);
    const auto [vend, vec_] = std::from_chars(value.data(), value.data() + value.size(), p.value);
    if (vec_ != std::errc() || vend != value.data() + value.size() || !std::isfinite(p.value))
        throw usage_error("--plane: " + shown(value) + " is not a finite number");
    p.momentum = key[0] == 'p';
    p.index = static_cast<int>(i) - 1;
    p.direction = direction == "+" ? 1 : direction == "-" ? -1 : 0;
    return p;
}

void run_section(const section_options& o) {
    ensemble_model model = find_ensemble_model(o.run);
    if (!model.section)
        throw usage_error("varsym section needs a stepper with dense output (not the rigid "
                          "bodies' or the constrained mechanisms'); " +
                          model.name + "'s has none (see 'varsym models')");
    const member_set set = make_member_set(o.run.members, model);
    const int d = model.dim;
    const section_plane plane = parse_plane(o.plane, o.direction, d);
    const ensemble_setup setup = make_setup(o.run, model, set.size);
    const std::string cols = state_columns_of(d);
    std::string x = o.plot_columns, y;
    if (x.empty())
        x = d == 1 ? "t,p_1"
                   : "q_" + std::to_string(plane.index == 0 ? 2 : 1) + ",p_" +
                         std::to_string(plane.index == 0 ? 2 : 1);
    const std::size_t comma = x.find(',');
    if (comma == std::string::npos) throw usage_error("--plot-columns needs X,Y");
    y = x.substr(comma + 1);
    x.resize(comma);
    std::string header = "member";
    for (const auto& k : set.keys)
        header += ',' + k;
    header += ",crossing,t," + cols + "\n";
    auto column = [&](const std::string& name) {
        const std::string all = "t," + cols;
        const std::size_t c = column_of(all, name);
        if (c == std::string::npos)
            throw usage_error("--plot-columns: " + shown(name) + " is not one of " + all);
        return c;
    };
    const std::size_t cx = column(x), cy = column(y);
    file_roles roles;
    roles.add_output("--output", o.output);
    add_member_inputs(roles, o.run);
    if (!o.plot.empty()) {
        check_pictures(o.plot);
        add_figure_files(roles, {".points.csv"}, o.plot);
    }
    roles.check();
    output_file out(o.output);
    out.write(header);
    // Each member's rows go out as soon as the members before it are done: memory holds the
    // rows of members finished ahead of a slower one, not the output (and the plot's points
    // where a plot is drawn).
    ordered_writer writer([&out](const std::string& rows) { out.write(rows); }, 0);
    std::string points = "# member," + x + "," + y + "\n";
    std::mutex points_mutex;
    std::atomic<long long> invalid{0}, failed{0}, count{0};
    const std::size_t base = 2 + set.keys.size(); // member, keys, crossing
    try {
        for_each_member(set.size, o.threads, [&](std::size_t m) {
            std::vector<double> keys;
            set.values(m, keys);
            std::string prefix = std::to_string(m);
            for (double v : keys) {
                prefix += ',';
                append_number(prefix, v);
            }
            // The crossings come a few thousand at a time and go out as they come (the
            // writer holds them only while a member before this one runs).
            long long k = 0;
            const auto emit = [&](const std::string& body) {
                std::string r, p;
                for (std::size_t at = 0; at < body.size();) {
                    const std::size_t end = body.find('\n', at);
                    if (body.compare(at, end - at, "failed") == 0) {
                        ++failed;
                        break;
                    }
                    const std::size_t first = r.size();
                    r += prefix + ',' + std::to_string(k++) + ',';
                    r.append(body, at, end + 1 - at);
                    at = end + 1;
                    ++count;
                    if (o.plot.empty()) continue;
                    std::vector<std::string_view> f; // the row's fields, for the plot's points
                    const std::string_view row(r.data() + first, r.size() - first - 1);
                    for (std::size_t i = 0, from = 0; i <= row.size(); ++i)
                        if (i == row.size() || row[i] == ',') {
                            f.push_back(row.substr(from, i - from));
                            from = i + 1;
                        }
                    p.append(f[0]).append(",").append(f[base + cx]).append(",");
                    p.append(f[base + cy]).append("\n");
                }
                if (!p.empty()) {
                    const std::lock_guard lock(points_mutex);
                    points += p;
                }
                writer.partial(m, std::move(r));
            };
            try {
                model.section(set.input(keys), setup, plane, o.crossings,
                              [&](std::string body) { emit(body); });
            } catch (const std::exception&) {
                // Refused by the model (its data, found when the member is prepared, before
                // any crossing): counted invalid.
                ++invalid;
            }
            writer.done(m, {});
        });
    } catch (...) {
        writer.flush_all();
        throw;
    }
    writer.flush_all();
    if (!o.plot.empty()) {
        const std::string title = model.name + ": section " + o.plane + " (" +
                                  (plane.direction > 0   ? "upwards"
                                   : plane.direction < 0 ? "downwards"
                                                         : "both ways") +
                                  "), " + std::to_string(set.size) + " orbits, " +
                                  setup.spec.label();
        std::string script = script_preamble(800, 720) + "set title '" + title +
                             "' noenhanced font ',13'\nset xlabel '" + x +
                             "' noenhanced\n"
                             "set ylabel '" +
                             y +
                             "' noenhanced\nunset colorbox\n"
                             "set palette defined (0 '#1b9e77', 1 '#d95f02', 2 '#7570b3', "
                             "3 '#e7298a', 4 '#66a61e', 5 '#e6ab02')\n"
                             "plot stem.'.points.csv' using 2:3:1 with points pt 7 ps 0.35 "
                             "lc palette notitle\n";
        file_roles others;
        others.add_output("--output", o.output);
        render_figure({{{".points.csv", points}}, script}, o.plot, others);
    }
    out.commit();
    std::fprintf(stderr, "varsym section: %zu orbits, %lld crossings, %lld invalid, %lld failed\n",
                 set.size, count.load(), invalid.load(), failed.load());
}

} // namespace

void add_section_command(CLI::App& app, action& todo) {
    auto o = std::make_shared<section_options>();
    auto* cmd = app.add_subcommand("section", "Poincare sections: where orbits cross a plane");
    cmd->footer(
        "Each member (the orbits: --grid or --members, keys as for varsym ensemble) runs up to\n"
        "--steps steps of --time / --steps, or until --crossings crossings. A crossing is found\n"
        "on the step's own interpolating polynomial, then refined by Newton on the scheme's map\n"
        "of the shortened step: the points lie on the discrete flow to the scheme's order.\n"
        "Output: member, the keys, crossing, t, q_1.., p_1.. (in member order, for any\n"
        "--threads). A summary line on stderr counts crossings and invalid or failed orbits.\n\n"
        "Example (docs/figures/sections.sh):\n"
        "  varsym section --model henon-heiles --set energy=0.125 --members orbits.csv \\\n"
        "      --plane q1=0 --direction + --crossings 400 -o sec.csv --plot sec.png\n");
    // The models whose steppers have dense output (a crossing is found on the step's
    // polynomial); lagrangian and urdf run the general engine, which has it.
    std::string with;
    for (const ensemble_model& m : ensemble_models())
        if (m.section) with += (with.empty() ? "" : ", ") + m.name;
    add_member_run_options(*cmd, o->run, with + ", lagrangian, urdf");
    cmd->add_option("--plane", o->plane, "qI=VALUE or pI=VALUE (I from 1)")->capture_default_str();
    cmd->add_option("--direction", o->direction, "+ (increasing), - or both")
        ->check(CLI::IsMember({"+", "-", "both"}))
        ->capture_default_str();
    cmd->add_option("--crossings", o->crossings, "Most crossings per orbit")
        ->transform(positive_integer)
        ->capture_default_str();
    cmd->add_option("--threads", o->threads,
                    "Threads, at most 4096 (default 0: every CPU this process may use)")
        ->transform(non_negative_integer)
        ->check(CLI::Range(0, 4096));
    cmd->add_option("--output,-o", o->output, "CSV file (default: standard output)");
    cmd->add_option("--plot", o->plot, "Scatter plot, .png or .svg (data and script kept beside)");
    cmd->add_option("--plot-columns", o->plot_columns,
                    "X,Y columns drawn (default: the other coordinate and its momentum)");
    cmd->callback([o, &todo] { todo = [o] { run_section(*o); }; });
}

} // namespace varsym::cli
