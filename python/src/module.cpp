// python/src/module.cpp: varsym._core, the C++ side of the Python package. It holds no
// integrator of its own: the tool's front end (every model, scheme and paper command, run
// in-process) and the general engine compiled once for expression Lagrangians
// (apps/varsym/expression_run.hpp) are linked in from the tool's object libraries.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <map>
#include <string>
#include <vector>

#include "expression_run.hpp"
#include "front_end.hpp"
#include "models.hpp"

namespace py = pybind11;
using namespace varsym;

namespace {

vec<dynamic> to_vec(const std::vector<double>& x) {
    return Eigen::Map<const vec<dynamic>>(x.data(), static_cast<Eigen::Index>(x.size()));
}
py::array_t<double> to_array(const vec<dynamic>& x) {
    return py::array_t<double>(x.size(), x.data());
}
py::array_t<double> to_array(const mat<dynamic>& m) {
    py::array_t<double> a({m.rows(), m.cols()});
    for (Eigen::Index i = 0; i < m.rows(); ++i)
        for (Eigen::Index j = 0; j < m.cols(); ++j)
            a.mutable_at(i, j) = m(i, j);
    return a;
}
void check_size(const std::vector<double>& x, int d, const char* what) {
    if (static_cast<int>(x.size()) != d)
        throw std::invalid_argument(std::string(what) + " needs " + std::to_string(d) +
                                    " entries (one per coordinate), got " +
                                    std::to_string(x.size()));
}
/// Throws std::invalid_argument("unknown WHAT 'VALUE': CHOICES") (built by append: GCC 12's
/// -Wrestrict misfires on operator+ chains of std::string here).
[[noreturn]] void unknown(const char* what, const std::string& value, const char* choices) {
    std::string m("unknown ");
    m.append(what).append(" '").append(value).append("': ").append(choices);
    throw std::invalid_argument(m);
}

/// A rows × d array from values stored row by row.
py::array_t<double> rows(const std::vector<double>& v, int d) {
    const auto n = static_cast<py::ssize_t>(v.size()) / d;
    py::array_t<double> a({n, static_cast<py::ssize_t>(d)});
    std::copy(v.begin(), v.end(), a.mutable_data());
    return a;
}

} // namespace

PYBIND11_MODULE(_core, m) {
    m.doc() = "varsym's compiled core; use the package varsym, not this module";

    // The Python classes of varsym.errors carry the C++ exceptions' details as attributes.
    py::module_ errors = py::module_::import("varsym.errors");
    static PyObject* expression_error = py::object(errors.attr("ExpressionError")).release().ptr();
    static PyObject* step_error = py::object(errors.attr("StepFailure")).release().ptr();
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const expr::parse_error& e) {
            PyErr_SetObject(expression_error, py::make_tuple(e.what(), e.position()).ptr());
        } catch (const step_failure& e) {
            PyErr_SetObject(step_error, py::make_tuple(e.what(), e.step(), e.time()).ptr());
        }
    });

    m.def(
        "run_cli",
        [](const std::vector<std::string>& args) {
            int status = 0;
            {
                py::gil_scoped_release unlocked;
                cli::set_quiet_failures(true);
                cli::front_end fe;
                status = fe.parse(args);
                if (status < 0) status = fe.run();
                cli::set_quiet_failures(false);
            }
            return py::make_tuple(status, status == 0 ? std::string() : cli::last_failure());
        },
        py::arg("args"),
        "Runs the varsym command line in-process; returns (exit code, error message).");

    m.def("models", [] {
        std::vector<std::tuple<std::string, std::string, std::string>> out;
        for (const auto& mod : cli::make_models())
            out.emplace_back(mod.name, mod.summary, mod.description);
        return out;
    });

    py::class_<expression_lagrangian>(m, "_Lagrangian")
        .def(py::init([](const std::string& text, const std::vector<std::string>& coordinates,
                         const std::map<std::string, double>& parameters) {
                 std::vector<expression_parameter> par;
                 for (const auto& [name, value] : parameters)
                     par.push_back({name, value});
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

    py::class_<cli::expression_stepper>(m, "_Stepper")
        .def(py::init([](const expression_lagrangian& l, const std::vector<std::string>& force,
                         double h, const std::string& scheme, int degree,
                         const std::vector<double>& q0, const std::vector<double>& p0, double t0,
                         const std::string& iteration) {
                 const auto kind = parse_scheme(scheme);
                 if (!kind)
                     throw std::invalid_argument("unknown scheme '" + scheme +
                                                 "': newmark, simpson, lobatto or gauss");
                 const scheme_spec spec =
                     degree > 0 ? scheme_spec(*kind, degree) : scheme_spec(*kind);
                 check_size(q0, l.dimension(), "q0");
                 check_size(p0, l.dimension(), "p0");
                 newton_options opt;
                 if (iteration == "simplified")
                     opt.iteration = iteration_kind::simplified;
                 else if (iteration == "fixed-point")
                     opt.iteration = iteration_kind::fixed_point;
                 else if (iteration != "newton")
                     unknown("iteration", iteration, "newton, simplified or fixed-point");
                 const expression_force f =
                     force.empty() ? expression_force(l.dimension())
                                   : expression_force(force, l.coordinates(), l.parameters());
                 return std::make_unique<cli::expression_stepper>(l, f, h, spec, opt, to_vec(q0),
                                                                  to_vec(p0), t0);
             }),
             py::arg("lagrangian"), py::arg("force"), py::arg("h"), py::arg("scheme"),
             py::arg("degree"), py::arg("q0"), py::arg("p0"), py::arg("t0"), py::arg("iteration"))
        .def(
            "step", [](cli::expression_stepper& s, std::size_t n) { s.step(n); }, py::arg("n") = 1,
            py::call_guard<py::gil_scoped_release>())
        .def(
            "run",
            [](cli::expression_stepper& s, std::size_t n, std::size_t every, bool start) {
                std::vector<double> t, q, p, e;
                const int d = static_cast<int>(s.q().size());
                py::dict out;
                auto fill = [&] {
                    out["t"] = py::array_t<double>(static_cast<py::ssize_t>(t.size()), t.data());
                    out["q"] = rows(q, d);
                    out["p"] = rows(p, d);
                    out["energy"] =
                        py::array_t<double>(static_cast<py::ssize_t>(e.size()), e.data());
                };
                try {
                    py::gil_scoped_release unlocked;
                    s.run(n, every, start, t, q, p, e);
                } catch (const step_failure& f) {
                    fill(); // the rows before the failure, on the exception
                    PyErr_SetObject(step_error,
                                    py::make_tuple(f.what(), f.step(), f.time(), out).ptr());
                    throw py::error_already_set();
                }
                fill();
                return out;
            },
            py::arg("n"), py::arg("every"), py::arg("start"))
        .def_property_readonly("q",
                               [](const cli::expression_stepper& s) { return to_array(s.q()); })
        .def_property_readonly("p",
                               [](const cli::expression_stepper& s) { return to_array(s.p()); })
        .def_property_readonly("t", &cli::expression_stepper::time)
        .def_property_readonly("steps", &cli::expression_stepper::steps)
        .def_property_readonly("h", &cli::expression_stepper::step_size)
        .def_property_readonly("energy", &cli::expression_stepper::energy)
        .def_property_readonly("work", &cli::expression_stepper::work)
        .def_property_readonly("mean_newton_iterations",
                               &cli::expression_stepper::mean_newton_iterations);
}
