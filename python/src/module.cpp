// python/src/module.cpp: varsym._core, the C++ side of the Python package. It holds no
// integrator of its own: it binds the models layer (varsym::models: the registry's models and
// typed Lagrangians, in simulation.cpp) and the expression Lagrangians. The tool's engine, which
// the models outside the registry still need, is the separate module varsym._tool (tool.cpp).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <map>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "varsym/models/expression.hpp"
#include "varsym/systems/expression_lagrangian.hpp"
#include "varsym/version.hpp"

namespace py = pybind11;
using namespace varsym;

namespace {

vec<dynamic> to_vec(const std::vector<double>& x) {
    return Eigen::Map<const vec<dynamic>>(x.data(), static_cast<Eigen::Index>(x.size()));
}
void check_size(const std::vector<double>& x, int d, const char* what) {
    if (static_cast<int>(x.size()) != d)
        throw std::invalid_argument(std::string(what) + " needs " + std::to_string(d) +
                                    " entries (one per coordinate), got " +
                                    std::to_string(x.size()));
}
PyObject* step_error = nullptr;  ///< varsym.errors.StepFailure
PyObject* usage_error = nullptr; ///< varsym.errors.UsageError

} // namespace

PYBIND11_MODULE(_core, m) {
    m.doc() = "varsym's compiled core; use the package varsym, not this module";

    // The Python classes of varsym.errors carry the C++ exceptions' details as attributes.
    m.attr("__version__") = VARSYM_VERSION_STRING;
    py::module_ errors = py::module_::import("varsym.errors");
    static PyObject* expression_error = py::object(errors.attr("ExpressionError")).release().ptr();
    step_error = py::object(errors.attr("StepFailure")).release().ptr();
    usage_error = py::object(errors.attr("UsageError")).release().ptr();
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const expr::parse_error& e) {
            PyErr_SetObject(expression_error, py::make_tuple(e.what(), e.position()).ptr());
        } catch (const step_failure& e) {
            py::dict details;
            details["step"] = e.step();
            details["time"] = e.time();
            details["cause"] = e.cause();
            PyErr_SetObject(step_error, py::make_tuple(e.what(), details).ptr());
        } catch (const std::invalid_argument& e) { // bad input: the library's one-line message
            PyErr_SetString(usage_error, e.what());
        }
    });

    py::class_<expression_lagrangian>(m, "_Lagrangian")
        .def(py::init([](const std::string& text, const std::vector<std::string>& coordinates,
                         const std::map<std::string, double>& parameters) {
                 std::vector<expression_parameter> par;
                 for (const auto& [name, value] : parameters)
                     par.push_back({name, value});
                 models::check_expression_size(static_cast<int>(coordinates.size()), text.size());
                 return expression_lagrangian(text, coordinates, par);
             }),
             py::arg("expression"), py::arg("coordinates"), py::arg("parameters"))
        .def_property_readonly("dimension", &expression_lagrangian::dimension)
        .def_property_readonly("expression", &expression_lagrangian::text)
        .def_property_readonly("coordinates", &expression_lagrangian::coordinates)
        .def_property_readonly("depends_on_time", &expression_lagrangian::depends_on_time)
        .def_property_readonly("instructions", &expression_lagrangian::instructions)
        .def(
            "value",
            [](const expression_lagrangian& l, const std::vector<double>& q,
               const std::vector<double>& v, double t) {
                check_size(q, l.dimension(), "q");
                check_size(v, l.dimension(), "v");
                return l(to_vec(q), to_vec(v), t);
            },
            py::arg("q"), py::arg("v"), py::arg("t") = 0.0)
        .def(
            "derivatives",
            [](const expression_lagrangian& l, const std::vector<double>& q,
               const std::vector<double>& v, double t) {
                check_size(q, l.dimension(), "q");
                check_size(v, l.dimension(), "v");
                lagrangian_terms<dynamic> d;
                l.derivatives(to_vec(q), to_vec(v), t, d);
                py::dict out;
                out["value"] = d.value;
                out["L_q"] = to_array(d.lq);
                out["L_v"] = to_array(d.lv);
                out["L_qq"] = to_array(d.lqq);
                out["L_qv"] = to_array(d.lqv);
                out["L_vv"] = to_array(d.lvv);
                return out;
            },
            py::arg("q"), py::arg("v"), py::arg("t") = 0.0)
        .def(
            "momentum",
            [](const expression_lagrangian& l, const std::vector<double>& q,
               const std::vector<double>& v, double t) {
                check_size(q, l.dimension(), "q");
                check_size(v, l.dimension(), "v");
                return to_array(
                    lagrangian_system<expression_lagrangian>(l).momentum(to_vec(q), to_vec(v), t));
            },
            py::arg("q"), py::arg("v"), py::arg("t") = 0.0)
        .def(
            "velocity",
            [](const expression_lagrangian& l, const std::vector<double>& q,
               const std::vector<double>& p, double t) {
                check_size(q, l.dimension(), "q");
                check_size(p, l.dimension(), "p");
                return to_array(
                    lagrangian_system<expression_lagrangian>(l).velocity(to_vec(q), to_vec(p), t));
            },
            py::arg("q"), py::arg("p"), py::arg("t") = 0.0)
        .def(
            "check_regular",
            [](const expression_lagrangian& l, const std::vector<double>& q,
               const std::vector<double>& v, double t) {
                check_size(q, l.dimension(), "q");
                check_size(v, l.dimension(), "v");
                lagrangian_system<expression_lagrangian>(l).check_regular(to_vec(q), to_vec(v), t);
            },
            py::arg("q"), py::arg("v"), py::arg("t") = 0.0);

    bind_simulation(m);
    bind_ensemble(m);
    bind_optimal(m);
    bind_robot(m);
}
