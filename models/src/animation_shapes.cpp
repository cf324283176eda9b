// models/src/animation_shapes.cpp: the shapes an animation page draws (animation_data.hpp): the
// URDF's <visual> shapes, their mesh files found (package://, relative, absolute; the search
// path of animation_options) and read, and capsules for the bodies left without a shape.
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>

#include <Eigen/Geometry>

#include "animation_data.hpp"

namespace varsym::models::animation_detail {

namespace fs = std::filesystem;

namespace {

/// Where mesh `name` may be, in the order looked at.
std::vector<fs::path> mesh_places(const std::string& name, const animation_options& o) {
    std::vector<fs::path> dirs;
    for (const std::string& d : o.mesh_path)
        dirs.emplace_back(d);
    std::vector<fs::path> beside; // the URDF's directory and its parents
    if (!o.urdf.empty()) {
        fs::path d = fs::absolute(fs::path(o.urdf)).lexically_normal().parent_path();
        for (int up = 0; up < 4 && !d.empty(); ++up) {
            beside.push_back(d);
            if (d == d.parent_path()) break;
            d = d.parent_path();
        }
    }
    std::vector<fs::path> out;
    const std::string package = "package://", file = "file://";
    if (name.rfind(package, 0) == 0) {
        const std::string rest = name.substr(package.size());
        const auto slash = rest.find('/');
        const std::string pkg = rest.substr(0, slash);
        const std::string inner = slash == std::string::npos ? "" : rest.substr(slash + 1);
        for (const auto* list : {&dirs, &beside})
            for (const fs::path& d : *list) {
                out.push_back(d / pkg / inner);
                if (!inner.empty()) out.push_back(d / inner);
            }
    } else if (name.rfind(file, 0) == 0) {
        out.emplace_back(name.substr(file.size()));
    } else if (fs::path(name).is_absolute()) {
        out.emplace_back(name);
    } else {
        for (const fs::path& d : dirs)
            out.push_back(d / name);
        if (!beside.empty()) out.push_back(beside.front() / name);
    }
    return out;
}

std::string lower_extension(const std::string& name) {
    std::string e = fs::path(name).extension().string();
    std::transform(e.begin(), e.end(), e.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return e.empty() ? e : e.substr(1);
}

/// A capsule of radius `radius` from a to b in the body's frame.
shape_record capsule(int body, const Eigen::Vector3d& a, const Eigen::Vector3d& b, double radius,
                     const std::array<double, 4>& rgba) {
    shape_record s;
    s.body = body;
    s.kind = "capsule";
    s.rgba = rgba;
    const Eigen::Vector3d d = b - a;
    s.size = Eigen::Vector3d(radius, d.norm(), 0.0);
    s.offset.origin = (a + b) / 2;
    s.offset.rotation =
        Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), d).toRotationMatrix();
    return s;
}

double half_size(const multibody::collision_shape& v) {
    switch (v.kind) {
    case multibody::shape_kind::box:
        return v.size.norm() / 2;
    case multibody::shape_kind::sphere:
        return v.size(0);
    case multibody::shape_kind::mesh:
        return 0.0;
    default:
        return v.size(0) + v.size(1) / 2;
    }
}

} // namespace

scene_shapes collect_shapes(const multibody::tree& r, const animation_options& o,
                            std::vector<std::string>& warnings) {
    scene_shapes out;
    const auto nb = r.bodies.size();
    // Per body, its <visual> shapes and those drawn: a body with one that cannot be drawn (a
    // link whose mesh is missing, beside a fixed link's sphere) or with none gets the capsules.
    std::vector<int> shapes(nb, 0), shown(nb, 0);
    std::vector<std::array<double, 4>> colour(nb, {1.0, 0.6, 0.1, 1.0}); // the capsules'
    std::map<std::string, int> mesh_id;                                  // by the file found
    for (const multibody::visual_shape& v : r.visuals) {
        const auto b = static_cast<std::size_t>(v.body);
        if (v.body >= 0 && v.rgba[3] >= 0.0) colour[b] = v.rgba;
        const std::string fallback = v.body >= 0
                                         ? "drawn as capsules from its joint to its children's"
                                         : "not drawn (it is fixed to the ground)";
        if (v.body >= 0) ++shapes[b];
        if (!v.problem.empty()) {
            warnings.push_back(v.problem + ": " + fallback);
            continue;
        }
        shape_record s;
        s.body = v.body;
        s.offset = v.offset;
        s.size = v.size;
        s.rgba = v.rgba;
        if (v.kind == multibody::shape_kind::mesh) {
            const std::string format = lower_extension(v.mesh);
            if (format != "stl" && format != "obj" && format != "dae") {
                warnings.push_back("link " + v.link + ": mesh '" + v.mesh +
                                   "' is not STL, OBJ or COLLADA (.dae): " + fallback);
                continue;
            }
            std::optional<fs::path> found;
            const std::vector<fs::path> places = mesh_places(v.mesh, o);
            for (const fs::path& p : places)
                if (fs::is_regular_file(p)) {
                    found = fs::weakly_canonical(p);
                    break;
                }
            if (!found) {
                std::string where;
                for (std::size_t i = 0; i < places.size() && i < 3; ++i)
                    where.append(i ? ", " : "").append(places[i].string());
                if (places.size() > 3) where += ", ...";
                warnings.push_back("link " + v.link + ": mesh '" + v.mesh + "' not found" +
                                   (where.empty() ? "" : " (looked for " + where + ")") + "; " +
                                   fallback + " (give the meshes' directory with --mesh-path)");
                continue;
            }
            auto it = mesh_id.find(found->string());
            if (it == mesh_id.end()) {
                std::error_code ec;
                const auto bytes = fs::file_size(*found, ec);
                if (ec || bytes > o.max_mesh_bytes) {
                    warnings.push_back("link " + v.link + ": mesh '" + found->string() + "' " +
                                       (ec ? "cannot be read" : "is larger than the limit") + "; " +
                                       fallback);
                    continue;
                }
                std::ifstream f(*found, std::ios::binary);
                std::ostringstream text;
                text << f.rdbuf();
                if (!f) {
                    warnings.push_back("link " + v.link + ": mesh '" + found->string() +
                                       "' cannot be read; " + fallback);
                    continue;
                }
                out.meshes.push_back({format, text.str()});
                it =
                    mesh_id.emplace(found->string(), static_cast<int>(out.meshes.size()) - 1).first;
            }
            s.kind = "mesh";
            s.mesh = it->second;
        } else {
            s.kind = v.kind == multibody::shape_kind::box       ? "box"
                     : v.kind == multibody::shape_kind::sphere  ? "sphere"
                     : v.kind == multibody::shape_kind::capsule ? "capsule"
                                                                : "cylinder";
            out.extent = std::max(out.extent, v.offset.origin.norm() + half_size(v));
        }
        if (v.body >= 0) ++shown[b];
        out.shapes.push_back(std::move(s));
    }
    // The bodies left without a shape: capsules from the joint to the children's joints (or to
    // the centre of mass of a last link). The massless bodies of a floating base are not links.
    const int first = std::max(0, r.base_coordinates() - 1);
    double longest = 0.0;
    std::vector<std::vector<Eigen::Vector3d>> ends(nb);
    for (std::size_t c = 0; c < nb; ++c) {
        const int p = r.bodies[c].parent;
        if (p >= first) ends[static_cast<std::size_t>(p)].push_back(r.bodies[c].placement.origin);
    }
    for (std::size_t b = static_cast<std::size_t>(first); b < nb; ++b) {
        if (ends[b].empty() && r.bodies[b].com.norm() > 1e-9)
            ends[b].push_back(2 * r.bodies[b].com);
        for (const Eigen::Vector3d& e : ends[b])
            longest = std::max(longest, e.norm());
    }
    const double radius = std::clamp(0.06 * longest, 0.005, 0.04);
    for (std::size_t b = static_cast<std::size_t>(first); b < nb; ++b) {
        if (shapes[b] > 0 && shown[b] == shapes[b]) continue;
        const int body = static_cast<int>(b);
        shape_record joint;
        joint.body = body;
        joint.kind = "sphere";
        joint.size(0) = 1.3 * radius;
        joint.rgba = colour[b];
        out.shapes.push_back(joint);
        for (const Eigen::Vector3d& e : ends[b])
            if (e.norm() > 1e-9) {
                out.shapes.push_back(capsule(body, Eigen::Vector3d::Zero(), e, radius, colour[b]));
                out.extent = std::max(out.extent, e.norm() + radius);
            }
    }
    out.extent = std::max(out.extent, 1.3 * radius);
    return out;
}

} // namespace varsym::models::animation_detail
