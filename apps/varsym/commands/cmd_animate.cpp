// apps/varsym/commands/cmd_animate.cpp: `varsym animate`, a robot's motion from a CSV file of
// `varsym run` or `varsym optimize` as a 3-D animation page (models/animation.hpp), and what
// `run --animate` and `optimize --animate` share: the check that three.js is there and the
// writing of the page with its report on standard error.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>

#include "commands/commands.hpp"
#include "models/models.hpp"
#include "output/files.hpp"
#include "varsym/models/animation.hpp"
#include "varsym/models/robot.hpp"
#include "varsym/optimal/problem.hpp"

namespace varsym::cli {

void animation_check(const std::string& path) {
    try {
        models::find_three_js();
    } catch (const models::animation_error& e) {
        throw usage_error(std::string("--animate ") + path + ": " + e.what());
    }
}

void add_animation_roles(file_roles& roles, const std::string& option, const std::string& page) {
    if (page == "-" || kind_of(page) == file_kind::directory)
        throw usage_error(option + " '" + page +
                          "' is not a file name: name the HTML page, such as motion.html");
    roles.add(option, page);
    roles.add(option + "'s temporary file", page + ".tmp");
}

std::string drawn_models(bool with_inputs) {
    std::string s = "--animate draws a URDF robot (--urdf FILE) and the models ";
    bool first = true;
    for (const models::model& m : models::registry())
        if (m.drawing && (!with_inputs || m.has_inputs())) {
            if (!first) s += ", ";
            s += m.name;
            first = false;
        }
    return s;
}

std::vector<std::string> coordinate_names(const models::model& m, int d) {
    std::vector<std::string> names;
    std::stringstream list(m.coordinates);
    for (std::string name; std::getline(list, name, ',');) {
        const auto a = name.find_first_not_of(' ');
        names.push_back(a == std::string::npos ? "" : name.substr(a));
    }
    if (static_cast<int>(names.size()) == d) return names;
    names.clear(); // "th_1 ... th_n": numbered
    for (int i = 1; i <= d; ++i) {
        std::string name("q_"); // appended: GCC 12 -O2 warns on "q_" + std::string
        name += std::to_string(i);
        names.push_back(name);
    }
    return names;
}

namespace {

void report(const models::animation_report& r, const std::string& path, bool quiet) {
    if (!r.warnings.empty())
        std::fprintf(stderr, "varsym: warning: %s\n", r.warnings.front().c_str());
    if (r.warnings.size() > 1)
        std::fprintf(stderr, "varsym: warning: %zu more warnings, listed on the page\n",
                     r.warnings.size() - 1);
    if (!quiet)
        std::fprintf(stderr, "varsym: wrote %s (%zu frames, %.2f MB)\n", path.c_str(), r.frames,
                     static_cast<double>(r.bytes) / 1e6);
}

} // namespace

void write_animation(std::shared_ptr<const multibody::tree> tree, std::span<const double> t,
                     const Eigen::MatrixXd& q, const std::string& urdf, const std::string& path,
                     double fps, const std::vector<std::string>& mesh_path, bool quiet,
                     std::vector<contact::obstacle> world,
                     std::vector<std::vector<double>> forces) {
    models::animation_options o;
    o.world = std::move(world);
    o.forces = std::move(forces);
    o.urdf = urdf;
    o.mesh_path = mesh_path;
    o.fps = fps;
    try {
        report(models::write_animation(std::move(tree), t, q, path, o), path, quiet);
    } catch (const std::invalid_argument& e) {
        throw usage_error(std::string("--animate: ") + e.what());
    } catch (const models::animation_error& e) {
        throw std::runtime_error(std::string("--animate: ") + e.what());
    }
}

void write_figure_animation(const models::model& m, std::span<const double> values,
                            const models::lists& lists, std::span<const double> t,
                            const Eigen::MatrixXd& q, const std::string& path, double fps,
                            bool quiet, const std::string& title) {
    models::animation_options o;
    o.fps = fps;
    o.title = title;
    try {
        const models::figure f = m.drawing(values, lists);
        report(models::write_animation(f, t, q, path, o,
                                       coordinate_names(m, static_cast<int>(q.cols()))),
               path, quiet);
    } catch (const std::invalid_argument& e) {
        throw usage_error(std::string("--animate: ") + e.what());
    } catch (const models::animation_error& e) {
        throw std::runtime_error(std::string("--animate: ") + e.what());
    }
}

void write_optimal_animation(const optimal::trajectory& path, const models::model& m,
                             std::span<const double> values, const models::lists& lists,
                             const std::string& urdf, const std::string& page, double fps,
                             const std::vector<std::string>& mesh_path, bool quiet) {
    const double end = path.node_times(path.node_times.size() - 1);
    std::vector<double> t;
    if (fps > 0.0)
        for (double x = 0.0; x < end; x = static_cast<double>(t.size()) / fps)
            t.push_back(x);
    else
        t.assign(path.node_times.data(), path.node_times.data() + path.node_times.size() - 1);
    t.push_back(end);
    Eigen::MatrixXd q(static_cast<Eigen::Index>(t.size()), path.q.rows());
    for (std::size_t k = 0; k < t.size(); ++k) {
        const auto row = static_cast<Eigen::Index>(k);
        if (fps > 0.0)
            q.row(row) = path.position(t[k]).transpose();
        else
            q.row(row) = path.q.col(row).transpose();
    }
    if (urdf.empty())
        write_figure_animation(m, values, lists, t, q, page, 0.0, quiet,
                               m.name + ": optimal motion");
    else
        write_animation(robot_tree_of(urdf_spec{urdf, "", ""}), t, q, urdf, page, 0.0, mesh_path,
                        quiet);
}

void run_animated(const run_setup& s, int width, bool coordinates,
                  const std::function<void(const run_setup&)>& run,
                  const std::function<void(const frame_recorder&, const Eigen::MatrixXd&)>& write) {
    animation_check(s.animate); // three.js is there, before the run
    run_setup with = s;
    with.frames = std::make_shared<frame_recorder>();
    with.frames->every = s.animate_fps > 0.0 ? 1.0 / s.animate_fps : 0.0;
    with.frames->width = width;
    with.frames->coordinates = coordinates;
    auto page = [&](bool stopped) {
        const frame_recorder& f = *with.frames;
        if (f.t.empty()) return;
        const auto rows = static_cast<Eigen::Index>(f.t.size());
        const Eigen::MatrixXd q =
            Eigen::Map<const Eigen::MatrixXd>(f.q.data(), f.width, rows).transpose();
        if (stopped)
            std::fprintf(stderr, "varsym: the animation ends where the run stopped, t = %.6g s\n",
                         f.t.back());
        write(f, q);
    };
    try {
        run(with);
    } catch (...) { // a failed or stopped run: the frames it reached
        try {
            page(true);
        } catch (const std::exception& e) { // the run's own error is the one to report
            std::fprintf(stderr, "varsym: warning: no animation page: %s\n", e.what());
        }
        throw;
    }
    page(false);
}

namespace {

struct animate_options {
    urdf_spec urdf;
    std::string input, output, snapshot, times;
    double fps = 60.0;
    std::vector<std::string> mesh_path;
    bool quiet = false;
};

/// The columns t and q_NAME (or NAME) of robot coordinates `names` in CSV file `path`.
void read_motion(const std::string& path, const std::vector<std::string>& names,
                 std::vector<double>& t, Eigen::MatrixXd& q) {
    std::ifstream in(path);
    if (!in) throw usage_error("--input: cannot read '" + path + "'");
    // Cells trimmed of spaces, a CR (a file from Windows) and double quotes.
    auto cells = [](const std::string& text) {
        std::vector<std::string> out;
        std::stringstream ss(text);
        for (std::string cell; std::getline(ss, cell, ',');) {
            const auto a = cell.find_first_not_of(" \t\r\"");
            const auto b = cell.find_last_not_of(" \t\r\"");
            out.push_back(a == std::string::npos ? "" : cell.substr(a, b - a + 1));
        }
        return out;
    };
    std::string line;
    if (!std::getline(in, line)) throw usage_error("--input: '" + path + "' is empty");
    const std::vector<std::string> header = cells(line);
    // A coordinate's column: q_NAME (run), qI (optimize, from 1), q_I, or q for one coordinate.
    auto column = [&](const std::vector<std::string>& names_of, const std::string& shown) {
        for (const std::string& name : names_of)
            for (std::size_t i = 0; i < header.size(); ++i)
                if (header[i] == name) return static_cast<int>(i);
        throw usage_error("--input: '" + path + "' has no column " + shown +
                          " (the robot's coordinates are q_NAME as varsym run writes them, or "
                          "q1, q2, ... as varsym optimize does; is it this robot's, with this "
                          "--base?)");
    };
    const int ct = column({"t"}, "t");
    std::vector<int> cq;
    for (std::size_t i = 0; i < names.size(); ++i) {
        const std::string k = std::to_string(i + 1);
        std::vector<std::string> candidates{"q_" + names[i], "q" + k, "q_" + k};
        if (names.size() == 1) candidates.emplace_back("q");
        cq.push_back(column(candidates, "q_" + names[i]));
    }
    std::vector<double> values, row;
    std::size_t rows = 0, number = 1;
    for (std::string text; std::getline(in, text);) {
        ++number;
        if (text.find_first_not_of(" \t\r") == std::string::npos) continue;
        row.clear();
        for (const std::string& cell : cells(text)) {
            char* end = nullptr;
            const double v = std::strtod(cell.c_str(), &end);
            row.push_back(!cell.empty() && *end == '\0' ? v : std::nan(""));
        }
        if (row.size() != header.size())
            throw usage_error("--input: line " + std::to_string(number) + " of '" + path +
                              "' has " + std::to_string(row.size()) + " values for " +
                              std::to_string(header.size()) + " columns");
        t.push_back(row[static_cast<std::size_t>(ct)]);
        for (int c : cq) {
            values.push_back(row[static_cast<std::size_t>(c)]);
            if (!std::isfinite(values.back()) || !std::isfinite(t.back()))
                throw usage_error("--input: line " + std::to_string(number) + " of '" + path +
                                  "' has a value that is not a finite number in t or q");
        }
        ++rows;
    }
    if (rows == 0) throw usage_error("--input: '" + path + "' has no rows");
    q = Eigen::Map<const Eigen::MatrixXd>(values.data(), static_cast<Eigen::Index>(names.size()),
                                          static_cast<Eigen::Index>(rows))
            .transpose();
}

void animate(const animate_options& o) {
    file_roles roles;
    if (!o.snapshot.empty()) {
        if (kind_of(o.snapshot) == file_kind::directory)
            throw usage_error("--snapshot '" + o.snapshot + "' is a directory: name the picture");
        roles.add("--snapshot", o.snapshot);
        roles.add("--snapshot's temporary file", o.snapshot + ".tmp.png");
    }
    roles.add("--urdf", o.urdf.path);
    roles.add("--input", o.input);
    add_animation_roles(roles, "--output", o.output);
    roles.check();
    animation_check(o.output);
    const auto tree = robot_tree_of(o.urdf);
    std::vector<double> t;
    Eigen::MatrixXd q;
    read_motion(o.input, models::robot_coordinates(*tree), t, q);
    std::vector<double> at;
    if (!o.snapshot.empty()) {
        at = o.times.empty() ? std::vector<double>{t.back()} : parse_number_list(o.times);
        for (double x : at)
            if (!(x >= t.front() && x <= t.back()))
                throw usage_error("--snapshot-times: " + std::to_string(x) +
                                  " s is outside the motion's times");
        find_chromium(); // before the page is written
    }
    write_animation(tree, t, q, o.urdf.path, o.output, o.fps, o.mesh_path, o.quiet);
    if (!o.snapshot.empty()) {
        take_snapshot(o.output, o.snapshot, at);
        if (!o.quiet) std::fprintf(stderr, "varsym: wrote %s\n", o.snapshot.c_str());
    }
}

} // namespace

void add_animate_command(CLI::App& app, action& todo) {
    auto o = std::make_shared<animate_options>();
    auto* cmd = app.add_subcommand(
        "animate", "Draw a robot's motion (a CSV of run or optimize) as a 3-D animation page");
    cmd->footer(
        "Writes one self-contained HTML page (three.js inlined from Debian's libjs-three) that\n"
        "any browser opens offline: the robot's URDF <visual> shapes and meshes (STL, OBJ,\n"
        "COLLADA) placed by forward kinematics at the CSV's rows, with play/pause, a time slider,\n"
        "speed, and the camera orbited (left drag), panned (right drag) and zoomed (wheel).\n"
        "The CSV needs t and each of the robot's coordinates: q_NAME as 'varsym run --urdf'\n"
        "writes them, or q1, q2, ... as 'varsym optimize --urdf' does. 'varsym run --animate' and\n"
        "'varsym optimize --animate' write the page directly. Page options in the URL after #:\n"
        "t=SECONDS, speed=X, cam=EX,EY,EZ,TX,TY,TZ, ghosts=T1,T2 (docs/robots.md).\n\n"
        "Examples:\n"
        "  varsym run --urdf ur5.urdf --time 2 --steps 2000 -o ur5.csv\n"
        "  varsym animate --urdf ur5.urdf --input ur5.csv --output ur5.html\n"
        "  varsym animate --urdf ur5.urdf -i ur5.csv -o ur5.html --snapshot ur5.png "
        "--snapshot-times 0,1,2\n");
    cmd->add_option("--urdf", o->urdf.path, "The robot's URDF file")->required();
    cmd->add_option("--base", o->urdf.base, "How the root link was held: fixed, free or planar")
        ->check(CLI::IsMember({"fixed", "free", "planar"}))
        ->default_str("fixed");
    cmd->add_option("--input,-i", o->input, "The motion: a CSV file with t and q_NAME columns")
        ->required();
    cmd->add_option("--output,-o", o->output, "The HTML page to write")->required();
    cmd->add_option("--fps", o->fps, "Frames kept per second of the motion's time (0: every row)")
        ->transform(non_negative_number)
        ->capture_default_str();
    cmd->add_option("--mesh-path", o->mesh_path,
                    "Directories where meshes are looked for first: package://PKG/PATH is "
                    "DIR/PKG/PATH or DIR/PATH (then beside the URDF and its parents)");
    auto* shot = cmd->add_option(
        "--snapshot", o->snapshot,
        "Also a PNG picture of the page (1200x800, no controls), taken by headless Chromium: "
        "the robot at the last of --snapshot-times and faintly at the others");
    cmd->add_option("--snapshot-times", o->times,
                    "Times [s] of the picture's poses, comma-separated (default: the last row)")
        ->check(number_list)
        ->type_name(list_type_name)
        ->needs(shot);
    cmd->add_flag("--quiet,-q", o->quiet, "No line saying what was written");
    cmd->callback([o, &todo] { todo = [o] { animate(*o); }; });
}

} // namespace varsym::cli
