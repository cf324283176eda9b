// models/src/animation_figure.cpp: the animation page of a built-in model (models/animation.hpp):
// its figure's parts (models/figure.hpp), posed at each kept row by the figure's own placement.
#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "animation_data.hpp"
#include "varsym/models/animation.hpp"

namespace varsym::models {

using namespace animation_detail;

animation_report write_animation(const figure& f, std::span<const double> t,
                                 const Eigen::MatrixXd& q, const std::string& path,
                                 const animation_options& options,
                                 const std::vector<std::string>& names) {
    if (!f.place || f.bodies < 1)
        throw std::invalid_argument("write_animation: the figure has no bodies to place");
    if (!options.urdf.empty() || !options.mesh_path.empty() || !options.world.empty() ||
        !options.forces.empty())
        throw std::invalid_argument("a URDF, mesh directories, obstacles and contact forces are a "
                                    "robot's: a built-in model's figure has none");
    if (q.cols() != f.coordinates || q.rows() != static_cast<Eigen::Index>(t.size()))
        throw std::invalid_argument("the motion has " + std::to_string(t.size()) + " times and a " +
                                    std::to_string(q.rows()) + " x " + std::to_string(q.cols()) +
                                    " q; the figure needs one row of " +
                                    std::to_string(f.coordinates) + " coordinates per time");
    check_motion(t, q);
    if (!(options.fps >= 0.0) || !std::isfinite(options.fps))
        throw std::invalid_argument("fps must be a finite number >= 0 (0 keeps every row)");
    if (!names.empty() && names.size() != static_cast<std::size_t>(f.coordinates))
        throw std::invalid_argument("write_animation: " + std::to_string(names.size()) +
                                    " names for " + std::to_string(f.coordinates) + " coordinates");
    const std::string three = find_three_js(options.three_js);

    page_data page;
    page.title = options.title.empty() ? "motion" : options.title;
    for (int i = 0; i < f.coordinates; ++i) {
        if (!names.empty()) {
            page.names.push_back(names[static_cast<std::size_t>(i)]);
            continue;
        }
        std::string name("q"); // appended: GCC 12 -O2 warns on "q" + std::string (PR 105651)
        name += std::to_string(i + 1);
        page.names.push_back(name);
    }
    page.bodies = static_cast<std::size_t>(f.bodies);
    page.floor = f.floor;
    page.note = f.scale;
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
    auto extend = [&](const Eigen::Vector3d& x, double r) {
        lo = lo.cwiseMin(x - Eigen::Vector3d::Constant(r));
        hi = hi.cwiseMax(x + Eigen::Vector3d::Constant(r));
    };
    std::vector<double> half; // each part's half size [m]
    for (const figure_part& p : f.parts) {
        if (p.body < -1 || p.body >= f.bodies)
            throw std::invalid_argument("write_animation: a part on body " +
                                        std::to_string(p.body) + " of a figure of " +
                                        std::to_string(f.bodies));
        shape_record s;
        s.body = p.body;
        s.page_body = p.body + 1;
        s.kind = p.kind;
        s.size = p.size;
        s.offset = p.offset;
        s.rgba = p.rgba;
        page.shapes.shapes.push_back(s);
        half.push_back(p.kind == "box"      ? p.size.norm() / 2
                       : p.kind == "sphere" ? p.size(0)
                                            : p.size(0) + p.size(1) / 2);
        if (p.body < 0) extend(p.offset.origin, half.back());
    }
    const std::vector<std::size_t> rows = animation_rows(t, options.fps);
    std::vector<multibody::pose> poses(static_cast<std::size_t>(f.bodies));
    page.poses.reserve(rows.size() * poses.size() * 7);
    for (std::size_t k : rows) {
        const Eigen::VectorXd qk = q.row(static_cast<Eigen::Index>(k)).transpose();
        f.place(std::span<const double>(qk.data(), static_cast<std::size_t>(qk.size())), poses);
        page.times.push_back(t[k]);
        for (const multibody::pose& x : poses) {
            const Eigen::Quaterniond u(x.rotation);
            for (double v : {x.origin.x(), x.origin.y(), x.origin.z(), u.x(), u.y(), u.z(), u.w()})
                page.poses.push_back(static_cast<float>(v));
        }
        for (std::size_t i = 0; i < f.parts.size(); ++i) // the camera frames every part
            if (const figure_part& p = f.parts[i]; p.body >= 0)
                extend(poses[static_cast<std::size_t>(p.body)].point(p.offset.origin), half[i]);
        for (Eigen::Index i = 0; i < qk.size(); ++i)
            page.values.push_back(static_cast<float>(qk(i)));
    }
    page.centre = (lo + hi) / 2;
    page.radius = std::max((hi - lo).norm() / 2, 0.2);

    animation_report report;
    report.frames = rows.size();
    report.bytes = save_page(page, path, options, three);
    return report;
}

} // namespace varsym::models
