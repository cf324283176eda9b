// models/src/animation.cpp: the data of a robot's animation page (models/animation.hpp): the
// rows kept, the drawn bodies' poses by forward kinematics, the shapes with their meshes found
// and embedded, the fallback capsules, as the JSON the page's script reads (animation_page.cpp).
#include "varsym/models/animation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "animation_data.hpp"
#include "varsym/contact/geometry.hpp"
#include "varsym/models/robot.hpp"

namespace varsym::models {

namespace fs = std::filesystem;
using namespace animation_detail;

std::string find_three_js(const std::string& given) {
    std::vector<std::string> tried;
    if (!given.empty()) tried.push_back(given);
    if (const char* env = std::getenv("VARSYM_THREE_JS"); env && *env) tried.emplace_back(env);
    tried.emplace_back("/usr/share/javascript/three");
    for (const std::string& d : tried)
        if (fs::is_regular_file(fs::path(d) / "three.min.js") ||
            fs::is_regular_file(fs::path(d) / "build" / "three.min.js"))
            return d;
    throw animation_error("three.js is missing (looked for three.min.js in " + tried.back() +
                          "): install Debian's libjs-three (apt-get install libjs-three), or set "
                          "VARSYM_THREE_JS to the directory holding three.min.js");
}

std::vector<std::size_t> animation_rows(std::span<const double> t, double fps) {
    std::vector<std::size_t> keep;
    if (t.empty()) return keep;
    // Frame n is the first row at or after t0 + n/fps (and the last row): 60 frames a second
    // on average, whatever the rows' spacing.
    double next = t[0];
    for (std::size_t k = 0; k < t.size(); ++k) {
        if (k + 1 == t.size() || fps <= 0.0 || t[k] >= next - 1e-9 / fps) {
            keep.push_back(k);
            if (fps > 0.0) next = t[0] + (std::floor((t[k] - t[0]) * fps + 1e-6) + 1.0) / fps;
        }
    }
    return keep;
}

void animation_detail::check_motion(std::span<const double> t, const Eigen::MatrixXd& q) {
    if (t.empty()) throw std::invalid_argument("the motion has no rows");
    for (std::size_t k = 0; k < t.size(); ++k) {
        if (!std::isfinite(t[k]) || !q.row(static_cast<Eigen::Index>(k)).allFinite())
            throw std::invalid_argument("row " + std::to_string(k) +
                                        " of the motion is not finite: nothing to draw there");
        if (k > 0 && t[k] < t[k - 1])
            throw std::invalid_argument("the motion's times decrease at row " + std::to_string(k));
    }
}

namespace {

/// The bodies whose poses the page needs: those carrying a shape (the ground is −1).
struct drawn_bodies {
    std::vector<int> body;  ///< page index → body
    std::vector<int> index; ///< body → page index + 1 (0: not drawn)
    int add(int b) {
        if (b < 0) return 0;
        int& i = index[static_cast<std::size_t>(b)];
        if (i == 0) {
            body.push_back(b);
            i = static_cast<int>(body.size());
        }
        return i;
    }
};

void check_rows(const multibody::tree& r, std::span<const double> t, const Eigen::MatrixXd& q) {
    const auto d = static_cast<Eigen::Index>(robot_coordinates(r).size());
    if (q.cols() != d || q.rows() != static_cast<Eigen::Index>(t.size()))
        throw std::invalid_argument("the motion has " + std::to_string(t.size()) + " times and a " +
                                    std::to_string(q.rows()) + " x " + std::to_string(q.cols()) +
                                    " q; robot " + r.name + " needs one row of " +
                                    std::to_string(d) + " coordinates per time");
    check_motion(t, q);
    if (r.base == multibody::base_kind::free)
        for (Eigen::Index k = 0; k < q.rows(); ++k)
            if (q.row(k).segment(3, 4).norm() == 0.0)
                throw std::invalid_argument("row " + std::to_string(k) +
                                            " of the motion has a zero base quaternion");
}

} // namespace

std::uintmax_t animation_detail::save_page(const page_data& page, const std::string& path,
                                           const animation_options& options,
                                           const std::string& three) {
    const fs::path out(path);
    std::error_code ec;
    if (fs::is_directory(out, ec))
        throw animation_error("cannot write '" + path + "': it is a directory");
    if (!options.urdf.empty() && fs::equivalent(out, options.urdf, ec))
        throw animation_error("will not write the page over the robot's URDF '" + options.urdf +
                              "'");
    for (const std::string& d : options.mesh_path)
        if (fs::equivalent(out, d, ec))
            throw animation_error("cannot write '" + path + "': it is a mesh directory");
    std::ostringstream text;
    write_page(text, page, three);
    // Written to PATH.tmp, created exclusively (never someone's file), then renamed over PATH.
    const std::string tmp = path + ".tmp";
    std::FILE* f = std::fopen(tmp.c_str(), "wbx");
    if (f == nullptr)
        throw animation_error("cannot write '" + tmp + "'" +
                              (fs::exists(tmp, ec) ? ": it exists (move it away)" : ""));
    const std::string& bytes = text.str();
    const bool written = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
    if (std::fclose(f) != 0 || !written) {
        fs::remove(tmp, ec);
        throw animation_error("cannot write '" + tmp + "' (disk full?)");
    }
    fs::rename(tmp, out, ec);
    if (ec) {
        const std::string why = ec.message();
        fs::remove(tmp, ec);
        throw animation_error("cannot rename '" + tmp + "' to '" + path + "': " + why);
    }
    return fs::file_size(out, ec);
}

animation_report write_animation(std::shared_ptr<const multibody::tree> r,
                                 std::span<const double> t, const Eigen::MatrixXd& q,
                                 const std::string& path, const animation_options& options,
                                 const std::vector<std::string>& names) {
    if (!r) throw std::invalid_argument("write_animation: no robot");
    check_rows(*r, t, q);
    if (!(options.fps >= 0.0) || !std::isfinite(options.fps))
        throw std::invalid_argument("fps must be a finite number >= 0 (0 keeps every row)");
    const std::vector<std::string> coords = robot_coordinates(*r);
    if (!names.empty() && names.size() != coords.size())
        throw std::invalid_argument("write_animation: " + std::to_string(names.size()) +
                                    " names for " + std::to_string(coords.size()) + " coordinates");
    const std::string three = find_three_js(options.three_js);
    animation_report report;
    scene_shapes shapes = collect_shapes(*r, options, report.warnings);

    drawn_bodies drawn{{}, std::vector<int>(r->bodies.size(), 0)};
    for (shape_record& s : shapes.shapes)
        s.page_body = drawn.add(s.body);

    if (!options.forces.empty() && options.forces.size() != t.size())
        throw std::invalid_argument("write_animation: forces for " +
                                    std::to_string(options.forces.size()) + " rows of " +
                                    std::to_string(t.size()));
    for (const std::vector<double>& f : options.forces)
        if (f.size() % 6 != 0 ||
            !std::all_of(f.begin(), f.end(), [](double v) { return std::isfinite(v); }))
            throw std::invalid_argument("write_animation: a row's forces are not finite points "
                                        "and forces, six numbers each");
    const std::vector<std::size_t> rows = animation_rows(t, options.fps);
    report.frames = rows.size();
    std::vector<double> times;
    std::vector<float> poses, values;
    poses.reserve(rows.size() * drawn.body.size() * 7);
    contact::robot_kinematics kin(r);
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
    for (const multibody::collision_shape& s : r->visuals) // the ground's shapes
        if (s.body < 0) {
            lo = lo.cwiseMin(s.offset.origin);
            hi = hi.cwiseMax(s.offset.origin);
        }
    page_data page;
    double strongest = 0.0; // the largest contact force [N]
    std::vector<float> touch;
    std::vector<std::uint32_t> touches;
    const std::vector<contact::contact_point> points =
        options.world.empty() ? std::vector<contact::contact_point>{} : contact::contact_points(*r);
    for (std::size_t k : rows) {
        const Eigen::VectorXd qk = q.row(static_cast<Eigen::Index>(k)).transpose();
        kin.at(qk);
        times.push_back(t[k]);
        for (int b : drawn.body) {
            const multibody::pose x = kin.pose(b);
            const Eigen::Quaterniond u(x.rotation);
            for (double v : {x.origin.x(), x.origin.y(), x.origin.z(), u.x(), u.y(), u.z(), u.w()})
                poses.push_back(static_cast<float>(v));
            lo = lo.cwiseMin(x.origin);
            hi = hi.cwiseMax(x.origin);
        }
        for (Eigen::Index i = 0; i < qk.size(); ++i)
            values.push_back(static_cast<float>(qk(i)));
        if (!options.forces.empty()) {
            const std::vector<double>& f = options.forces[k];
            for (std::size_t i = 0; i < f.size(); ++i) {
                page.arrows.push_back(static_cast<float>(f[i]));
                if (i % 6 == 5)
                    strongest =
                        std::max(strongest, Eigen::Vector3d(f[i - 2], f[i - 1], f[i]).norm());
            }
            page.arrow_counts.push_back(static_cast<std::uint32_t>(f.size() / 6));
        }
        if (options.world.empty()) continue;
        std::uint32_t n = 0; // the collision points within 1e-6 m of an obstacle
        for (const contact::contact_point& c : points) {
            const Eigen::Vector3d x = kin.pose(c.body).point(c.point);
            for (const contact::obstacle& w : options.world) {
                Eigen::Vector3d normal;
                if (w.distance(x, normal) - c.radius > 1e-6) continue;
                const Eigen::Vector3d at = x - c.radius * normal; // on the surface
                for (double v : {at.x(), at.y(), at.z()})
                    touch.push_back(static_cast<float>(v));
                ++n;
                break;
            }
        }
        touches.push_back(n);
    }
    if (!(lo.array() <= hi.array()).all()) lo = hi = Eigen::Vector3d::Zero();

    page.title = options.title.empty() ? r->name : options.title;
    page.names = names.empty() ? coords : names;
    page.bodies = drawn.body.size();
    page.times = std::move(times);
    page.poses = std::move(poses);
    page.values = std::move(values);
    page.centre = (lo + hi) / 2;
    page.radius = std::max((hi - lo).norm() / 2 + shapes.extent, 0.2);
    page.warnings = report.warnings;
    page.shapes = std::move(shapes);
    page.world = options.world;
    page.touch = std::move(touch);
    page.touches = std::move(touches);
    if (strongest > 0.0) { // the largest force a third of the scene's radius
        page.arrow_scale = page.radius / 3 / strongest;
        char note[120];
        std::snprintf(note, sizeof note, "blue arrows: the contact forces, 1 m for %.3g N",
                      1.0 / page.arrow_scale);
        page.note = note;
    }

    report.bytes = save_page(page, path, options, three);
    return report;
}

} // namespace varsym::models
