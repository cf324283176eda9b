// python/src/bindings.hpp: what the translation units of varsym._core share.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstddef>
#include <memory>
#include <span>
#include <string>

#include "varsym/integrate.hpp"
#include "varsym/models/model.hpp"
#include "varsym/multibody/tree.hpp"
#include "varsym/schemes/scheme_kind.hpp"

/// The models layer's registry, problems and simulations (simulation.cpp).
void bind_simulation(pybind11::module_& m);
/// Optimal control of a model with inputs (optimal.cpp).
void bind_optimal(pybind11::module_& m);
/// Ensembles of a built-in model or of a Lagrangian typed as an expression (ensemble.cpp).
void bind_ensemble(pybind11::module_& m);

/// URDF robots: varsym._core._Robot (robot.cpp).
void bind_robot(pybind11::module_& m);
/// The model of a _Robot, or nullptr if `h` is not one (robot.cpp).
const varsym::models::model* robot_model_of(pybind11::handle h);
/// The multibody tree of a _Robot, or nullptr if `h` is not one (robot.cpp).
std::shared_ptr<const varsym::multibody::tree> robot_tree_of(pybind11::handle h);
/// A model's data as the Python registry gives it: name, parameters, lists, dim, …
/// (simulation.cpp).
pybind11::dict model_info(const varsym::models::model& mod);
/// The members of model `mod`, one row of `values` each (and of q0 and p0 where given), on
/// `threads` threads without the GIL: a dict of arrays, one entry per member (ensemble.cpp).
pybind11::dict run_ensemble(const varsym::models::model& mod,
                            pybind11::array_t<double, pybind11::array::c_style> values,
                            pybind11::array_t<double, pybind11::array::c_style> q0,
                            pybind11::array_t<double, pybind11::array::c_style> p0, double h,
                            long long steps, const std::string& scheme, int degree, bool indicators,
                            unsigned threads, const std::string& event,
                            const varsym::models::lists& lists);

/// A vector or matrix as a NumPy array (a copy) (module.cpp).
pybind11::array_t<double> to_array(const varsym::vec<varsym::dynamic>& x);
pybind11::array_t<double> to_array(const varsym::mat<varsym::dynamic>& m);

/// The scheme named `scheme` ("simpson", "gauss", …) of `degree` (0: the scheme's default);
/// throws std::invalid_argument naming the choices (simulation.cpp).
varsym::scheme_spec spec_of(const std::string& scheme, int degree);

/// Raises varsym.StepFailure for e: its message, step, time and cause, the last good state
/// (q, p) and the number of rows recorded before it (module.cpp). Needs the GIL.
[[noreturn]] void raise_step_failure(const varsym::step_failure& e, std::span<const double> q,
                                     std::span<const double> p, std::size_t rows);
