// python/src/optimal.cpp: varsym._core.optimize, the optimal control of a model with inputs, a
// URDF robot or a typed Lagrangian with inputs on named coordinates (varsym::optimal's one
// transcription, varsym/optimal/transcription.hpp, through the model's m.optimal).
// The solver runs without the GIL; each iteration takes it back to report progress and to see
// Ctrl-C (KeyboardInterrupt stops the solver, which keeps its last iterate).
#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include <limits>
#include <memory>
#include <optional>

#include "bindings.hpp"
#include "varsym/models/expression.hpp"
#include "varsym/models/model.hpp"
#include "varsym/models/robot.hpp"
#include "varsym/multibody/spatial.hpp"
#include "varsym/optimal/problem.hpp"
#include "varsym/optimal/solution_check.hpp"
#include "varsym/optimal/solve.hpp"

namespace py = pybind11;
using namespace varsym;

namespace {

py::dict optimize(const py::object& source, const std::vector<std::string>& inputs,
                  const std::vector<std::string>& constraints, bool limits,
                  std::vector<double> values, const models::lists& lists, double time, int steps,
                  const std::string& scheme, int degree, const Eigen::VectorXd& q0,
                  const Eigen::VectorXd& v0, const Eigen::VectorXd& q1, const Eigen::VectorXd& v1,
                  double max_control, double effort, double invariant, double power,
                  double time_weight, const std::vector<bool>& free_q,
                  const std::vector<bool>& free_v, const Eigen::VectorXd& terminal_q,
                  const Eigen::VectorXd& terminal_v, const std::string& hessian, int max_iterations,
                  int refine, const std::optional<py::function>& progress,
                  const std::string& ipopt_options, const std::string& reach,
                  const Eigen::Vector3d& reach_position,
                  const std::optional<Eigen::Vector3d>& reach_rpy, double reach_weight,
                  double max_velocity) {
    // The model: a registry name, a _Robot's, or a _Lagrangian's with its inputs.
    std::optional<models::model> typed;
    const models::model* found = robot_model_of(source);
    if (py::isinstance<py::str>(source)) {
        found = &models::get(source.cast<std::string>());
    } else if (py::isinstance<expression_lagrangian>(source)) {
        const auto& l = source.cast<const expression_lagrangian&>();
        if (inputs.empty())
            throw std::invalid_argument("a Lagrangian needs inputs: the coordinates the controls "
                                        "act on, e.g. inputs=[\"th1\", \"th2\"]");
        typed = models::expression_model(l);
        models::add_expression_inputs(*typed, l.text(), l.coordinates(), l.parameters(), inputs,
                                      constraints);
        found = &*typed;
        values = typed->defaults();
    }
    if (found == nullptr) throw std::invalid_argument("optimize: not a model");
    const models::model& m = *found;
    if (!m.optimal)
        throw std::invalid_argument("model " + m.name + " has no control input to optimise");
    // A parameter only a simulation uses (a controller's gains, a constant torque) set away from
    // its default would be silently dropped: refused, as the tool refuses --kp.
    for (const std::string& only : m.simulation_only) {
        for (std::size_t i = 0; i < m.parameters.size() && i < values.size(); ++i)
            if (m.parameters[i].name == only && values[i] != m.parameters[i].value)
                throw std::invalid_argument(only + " is a simulation's parameter of " + m.name +
                                            "; optimize computes the inputs (bound them with "
                                            "max_control)");
        for (std::size_t i = 0; i < m.lists.size() && i < lists.size(); ++i)
            if (m.lists[i].name == only && !lists[i].empty())
                throw std::invalid_argument(only + " is a simulation's parameter of " + m.name +
                                            "; optimize computes the inputs (bound them with "
                                            "max_control)");
    }
    (void)m.prepare(values, {}, lists); // the parameters' ranges
    optimal::control_problem p;
    p.time = time;
    p.steps = steps;
    p.scheme = spec_of(scheme, degree);
    p.q_start = q0;
    p.v_start = v0;
    p.q_end = q1;
    p.v_end = v1;
    p.cost = {.effort = effort, .invariant = invariant, .power = power, .time = time_weight};
    p.free_time = time_weight > 0.0;
    p.free_end_position = free_q;
    p.free_end_velocity = free_v;
    p.cost.terminal_position = terminal_q;
    p.cost.terminal_velocity = terminal_v;
    p.control_lower = Eigen::VectorXd::Constant(1, -max_control); // on every input
    p.control_upper = Eigen::VectorXd::Constant(1, max_control);
    if (std::isfinite(max_velocity)) { // else unbounded, or a robot's URDF velocity limits
        p.velocity_lower = Eigen::VectorXd::Constant(1, -max_velocity);
        p.velocity_upper = Eigen::VectorXd::Constant(1, max_velocity);
    }
    std::optional<Eigen::Matrix3d> reach_rotation;
    if (reach_rpy) reach_rotation = multibody::roll_pitch_yaw(*reach_rpy);
    if (!reach.empty()) { // a link's target pose (models/robot.hpp)
        if (!robot_tree_of(source))
            throw std::invalid_argument("reach names a link of a robot: give a varsym.Robot");
        p.end_target =
            models::frame_target(robot_tree_of(source), reach, reach_position, reach_rotation);
        p.end_target_weight = reach_weight;
    }
    if (limits && m.limits) m.limits(values, p); // a URDF robot's joint and effort limits
    auto tr = m.optimal(values, lists, p);
    optimal::solver_options so;
    so.max_iterations = max_iterations;
    so.options_file = ipopt_options;
    if (hessian == "exact")
        so.hessian = optimal::hessian_kind::exact;
    else if (hessian == "limited-memory")
        so.hessian = optimal::hessian_kind::limited_memory;
    else if (hessian != "automatic")
        throw std::invalid_argument("hessian must be automatic, exact or limited-memory, got '" +
                                    hessian + "'");
    bool interrupted = false;
    std::exception_ptr failure; // raised by the progress callback: re-raised after the solve
    so.progress = [&](const optimal::iteration& it) {
        py::gil_scoped_acquire gil;
        try {
            if (PyErr_CheckSignals() != 0) throw py::error_already_set();
            if (progress) (*progress)(it.number, it.cost, it.primal_infeasibility);
            return true;
        } catch (py::error_already_set& e) {
            if (e.matches(PyExc_KeyboardInterrupt))
                interrupted = true;
            else
                failure = std::current_exception();
            return false;
        }
    };
    optimal::nlp_result r;
    {
        py::gil_scoped_release nogil;
        if (refine > 0) {
            auto refined = optimal::solve_refined(
                [&](int n) {
                    auto q = p;
                    q.steps = n;
                    return m.optimal(values, lists, q);
                },
                steps, refine, so);
            r = std::move(refined.result);
            tr = std::move(refined.problem);
        } else {
            r = optimal::solve(*tr, so);
        }
    }
    if (failure) std::rethrow_exception(failure);
    const optimal::trajectory path = tr->unpack(r);
    optimal::solution_check check; // ours, whatever IPOPT says (solution_check.hpp)
    if (r.converged()) check = optimal::check_solution(*tr, r, path);
    py::dict out;
    out["t"] = path.node_times;
    out["q"] = Eigen::MatrixXd(path.q.transpose());
    out["v"] = Eigen::MatrixXd(path.v.transpose());
    out["p"] = Eigen::MatrixXd(path.p.transpose());
    out["costate"] = Eigen::MatrixXd(path.costate.transpose());
    out["control_t"] = path.control_times;
    out["u"] = Eigen::MatrixXd(path.u.transpose());
    out["cost"] = path.cost;
    out["status"] = std::string(optimal::status_name(r.verdict));
    out["message"] = r.message;
    out["iterations"] = r.iterations;
    out["constraint_violation"] = r.converged() ? check.residual : r.constraint_violation;
    out["closure"] = check.closure.error;
    out["trusted"] = !r.converged() || check.ok();
    out["closure_advice"] = check.ok() ? std::string() : check.advice();
    out["interrupted"] = interrupted;
    out["controls_at_bound"] = check.controls_at_bound; // active bounds (solution_check.hpp)
    out["velocity_excess"] = check.velocity_excess;
    if (!reach.empty()) {
        const auto miss =
            models::frame_target_miss(*robot_tree_of(source), reach, path.q.col(path.q.cols() - 1),
                                      reach_position, reach_rotation);
        out["reach_miss"] = py::make_tuple(miss.distance, miss.angle);
    } else {
        out["reach_miss"] = py::none();
    }
    return out;
}

} // namespace

void bind_optimal(py::module_& m) {
    m.def("optimize", &optimize);
}
