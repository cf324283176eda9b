// python/src/convert.cpp: what every binding file shares, and calls nothing of theirs: NumPy
// arrays of Eigen vectors and matrices, the StepFailure raised with the state reached, and the
// scheme of a name and degree. The binding files call one another one way only: module.cpp
// binds them all; robot.cpp uses simulation.cpp's model_info and ensemble.cpp's run_ensemble;
// optimal.cpp uses robot.cpp's robot_model_of.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>

#include "bindings.hpp"
#include "varsym/schemes/scheme_kind.hpp"

namespace py = pybind11;
using namespace varsym;

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

void raise_step_failure(const step_failure& e, std::span<const double> q, std::span<const double> p,
                        std::size_t rows) {
    py::dict details;
    details["step"] = e.step();
    details["time"] = e.time();
    details["cause"] = e.cause();
    details["q"] = py::array_t<double>(static_cast<py::ssize_t>(q.size()), q.data());
    details["p"] = py::array_t<double>(static_cast<py::ssize_t>(p.size()), p.data());
    details["rows"] = rows;
    const py::object failure = py::module_::import("varsym.errors").attr("StepFailure");
    PyErr_SetObject(failure.ptr(), py::make_tuple(e.what(), details).ptr());
    throw py::error_already_set();
}

scheme_spec spec_of(const std::string& scheme, int degree) {
    const auto kind = parse_scheme(scheme);
    if (!kind)
        throw std::invalid_argument("unknown scheme '" + scheme +
                                    "': newmark, simpson, lobatto or gauss");
    return degree > 0 ? scheme_spec(*kind, degree) : scheme_spec(*kind);
}
