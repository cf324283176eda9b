// python/src/robot.cpp: varsym._core._Robot, a robot read from a URDF file (the models layer's
// load_urdf and robot_model): its joints, limits and frames, its dynamics at a state (M(q), g(q),
// the bias C(q, q̇)q̇ + g(q), the energy, frame poses) by the recursive algorithms, and the
// problems and ensembles of its model, which varsym.Robot (a varsym.Model) simulates.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "varsym/models/animation.hpp"
#include "varsym/models/robot.hpp"
#include "varsym/multibody/algorithms.hpp"

namespace py = pybind11;
using namespace varsym;

namespace {

struct robot {
    std::shared_ptr<const multibody::tree> tree;
    models::model model;

    /// x as the tree's coordinates (refused for a free base: its model's coordinates are a
    /// position and a quaternion, not the tree's).
    [[nodiscard]] vec<dynamic> vector(const std::vector<double>& x, const char* what) const {
        if (tree->base == multibody::base_kind::free)
            throw std::invalid_argument(
                "mass_matrix, bias, energy and pose take the tree's coordinates: not available "
                "for a robot with a free base (its results' columns give the base's motion, "
                "momenta and centre of mass)");
        if (static_cast<int>(x.size()) != tree->dof())
            throw std::invalid_argument(std::string(what) + " needs " +
                                        std::to_string(tree->dof()) +
                                        " values (one per joint), got " + std::to_string(x.size()));
        vec<dynamic> v = Eigen::Map<const vec<dynamic>>(x.data(), std::ssize(x));
        if (!v.allFinite()) throw std::invalid_argument(std::string(what) + " must be finite");
        return v;
    }
};

} // namespace

const models::model* robot_model_of(py::handle h) {
    return py::isinstance<robot>(h) ? &h.cast<const robot&>().model : nullptr;
}

std::shared_ptr<const multibody::tree> robot_tree_of(py::handle h) {
    return py::isinstance<robot>(h) ? h.cast<const robot&>().tree : nullptr;
}

void bind_robot(py::module_& m) {
    py::class_<robot>(m, "_Robot")
        .def(py::init([](const std::string& source, bool text,
                         const std::vector<std::string>& torques, const std::string& base) {
                 const multibody::base_kind b = models::base_of(base);
                 auto tree =
                     text ? models::parse_urdf(source, "<urdf>", b) : models::load_urdf(source, b);
                 return robot{tree, models::robot_model(tree, torques)};
             }),
             py::arg("source"), py::arg("text") = false,
             py::arg("torques") = std::vector<std::string>{}, py::arg("base") = "fixed")
        .def_property_readonly("base",
                               [](const robot& r) {
                                   return std::string(
                                       r.tree->base == multibody::base_kind::free     ? "free"
                                       : r.tree->base == multibody::base_kind::planar ? "planar"
                                                                                      : "fixed");
                               })
        .def_property_readonly("name", [](const robot& r) { return r.tree->name; })
        .def_property_readonly("info", [](const robot& r) { return model_info(r.model); })
        .def_property_readonly("joints",
                               [](const robot& r) { return models::robot_coordinates(*r.tree); })
        .def_property_readonly("frames",
                               [](const robot& r) {
                                   std::vector<std::string> out;
                                   for (const auto& f : r.tree->frames)
                                       out.push_back(f.name);
                                   return out;
                               })
        .def_property_readonly("limits",
                               [](const robot& r) {
                                   multibody::tree::limit_vectors l = r.tree->limits();
                                   if (r.tree->base == multibody::base_kind::free) {
                                       // The model's coordinates: the base's seven (unbounded,
                                       // unactuated; the tree's six virtual ones) and the joints.
                                       for (vec<dynamic>* v : {&l.lower, &l.upper, &l.effort,
                                                               &l.velocity, &l.damping}) {
                                           vec<dynamic> grown(v->size() + 1);
                                           grown << v->head(6), (*v)(0), v->tail(v->size() - 6);
                                           *v = grown;
                                       }
                                   }
                                   py::dict out;
                                   out["lower"] = to_array(l.lower);
                                   out["upper"] = to_array(l.upper);
                                   out["effort"] = to_array(l.effort);
                                   out["velocity"] = to_array(l.velocity);
                                   out["damping"] = to_array(l.damping);
                                   return out;
                               })
        .def(
            "mass_matrix",
            [](const robot& r, const std::vector<double>& q) {
                multibody::workspace w;
                mat<dynamic> out(r.tree->dof(), r.tree->dof());
                multibody::mass_matrix(*r.tree, w, r.vector(q, "q"), out);
                return to_array(out);
            },
            py::arg("q"))
        .def(
            "bias",
            [](const robot& r, const std::vector<double>& q, const std::vector<double>& v,
               double g) {
                multibody::workspace w;
                vec<dynamic> out(r.tree->dof());
                multibody::bias_forces(r.tree->with_gravity(g), w, r.vector(q, "q"),
                                       r.vector(v, "v"), out);
                return to_array(out);
            },
            py::arg("q"), py::arg("v"), py::arg("gravity"))
        .def(
            "energy",
            [](const robot& r, const std::vector<double>& q, const std::vector<double>& v,
               double g) {
                multibody::workspace w;
                return multibody::energy(r.tree->with_gravity(g), w, r.vector(q, "q"),
                                         r.vector(v, "v"));
            },
            py::arg("q"), py::arg("v"), py::arg("gravity"))
        .def(
            "pose",
            [](const robot& r, const std::string& frame, const std::vector<double>& q) {
                const multibody::pose x = models::frame_pose_at(*r.tree, frame, r.vector(q, "q"));
                mat<dynamic> out = mat<dynamic>::Identity(4, 4);
                out.topLeftCorner(3, 3) = x.rotation;
                out.topRightCorner(3, 1) = x.origin;
                return to_array(out);
            },
            py::arg("frame"), py::arg("q"))
        .def(
            "animate",
            [](const robot& r, const std::vector<double>& t,
               py::array_t<double, py::array::c_style | py::array::forcecast> q,
               const std::string& path, const std::string& urdf,
               const std::vector<std::string>& mesh_path, double fps, const std::string& title,
               const std::vector<double>& values, const models::lists& lists) {
                if (q.ndim() != 2) throw std::invalid_argument("q must be a rows x d array");
                const Eigen::MatrixXd rows = Eigen::Map<
                    const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
                    q.data(), q.shape(0), q.shape(1));
                models::animation_options o;
                o.urdf = urdf;
                o.mesh_path = mesh_path;
                o.fps = fps;
                o.title = title;
                if (!values.empty() && rows.rows() > 0) // what a contact simulation touches
                    o.world =
                        models::robot_obstacles(r.tree, values, lists, rows.row(0).transpose());
                models::animation_report rep;
                {
                    py::gil_scoped_release unlocked;
                    rep = models::write_animation(r.tree, t, rows, path, o);
                }
                py::dict out;
                out["frames"] = rep.frames;
                out["bytes"] = rep.bytes;
                out["warnings"] = rep.warnings;
                return out;
            },
            py::arg("t"), py::arg("q"), py::arg("path"), py::arg("urdf"), py::arg("mesh_path"),
            py::arg("fps"), py::arg("title"), py::arg("values"), py::arg("lists"))
        .def(
            "prepare",
            [](const robot& r, const std::vector<double>& values, const std::vector<double>& q0,
               const std::vector<double>& p0, const std::vector<double>& v0,
               const models::lists& lists) {
                return r.model.prepare(values, {q0, p0, v0}, lists);
            },
            py::arg("values"), py::arg("q0"), py::arg("p0"), py::arg("v0"), py::arg("lists"))
        .def(
            "ensemble",
            [](const robot& r, py::array_t<double, py::array::c_style> values,
               py::array_t<double, py::array::c_style> q0,
               py::array_t<double, py::array::c_style> p0, double h, long long steps,
               const std::string& scheme, int degree, bool indicators, unsigned threads,
               const std::string& event, const models::lists& lists) {
                return run_ensemble(r.model, values, q0, p0, h, steps, scheme, degree, indicators,
                                    threads, event, lists);
            },
            py::arg("values"), py::arg("q0"), py::arg("p0"), py::arg("h"), py::arg("steps"),
            py::arg("scheme"), py::arg("degree"), py::arg("indicators"), py::arg("threads"),
            py::arg("event"), py::arg("lists"));
}
