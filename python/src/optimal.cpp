// python/src/optimal.cpp: varsym._core.optimize, the optimal control of a model with inputs, a
// URDF robot or a typed Lagrangian with inputs on named coordinates, by varsym::optimal's
// service optimize(model, parameters, request) (varsym/optimize/model.hpp), which the command
// line calls too: this file translates the arguments and presents the outcome.
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
#include "varsym/optimize/model.hpp"

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
                  double max_velocity, int threads) {
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
    optimal::model_request request;
    request.limits = limits;
    request.refine = refine;
    request.threads = threads;
    optimal::control_problem& p = request.problem;
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
    if (!reach.empty()) { // a link's target pose (models/robot.hpp)
        if (!robot_tree_of(source))
            throw std::invalid_argument("reach names a link of a robot: give a varsym.Robot");
        request.reach = optimal::reach_request{
            .robot = robot_tree_of(source),
            .frame = reach,
            .position = reach_position,
            .rotation =
                reach_rpy ? std::optional(multibody::roll_pitch_yaw(*reach_rpy)) : std::nullopt,
            .weight = reach_weight};
    }
    optimal::solver_options& so = request.solver;
    so.max_iterations = max_iterations;
    so.options_file = ipopt_options;
    so.hessian = optimal::hessian_of(hessian);
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
    optimal::model_outcome out;
    {
        py::gil_scoped_release nogil;
        out = optimal::optimize(m, values, lists, std::move(request));
    }
    if (failure) std::rethrow_exception(failure);
    const optimal::trajectory& path = out.path;
    const optimal::solution_check& check = out.check;
    py::dict d;
    d["t"] = path.node_times;
    d["q"] = Eigen::MatrixXd(path.q.transpose());
    d["v"] = Eigen::MatrixXd(path.v.transpose());
    d["p"] = Eigen::MatrixXd(path.p.transpose());
    d["costate"] = Eigen::MatrixXd(path.costate.transpose());
    d["control_t"] = path.control_times;
    d["u"] = Eigen::MatrixXd(path.u.transpose());
    d["cost"] = path.cost;
    d["status"] = std::string(optimal::status_name(out.result.verdict));
    d["message"] = out.result.message;
    d["iterations"] = out.result.iterations;
    d["constraint_violation"] = out.residual();
    d["closure"] = check.closure.error;
    d["trusted"] = !out.result.converged() || check.ok();
    d["closure_advice"] = check.ok() ? std::string() : check.advice();
    // The service's verdict (varsym/optimize/model.hpp) and its line, as the tool reports them.
    constexpr const char* verdicts[] = {"solved", "not_solved", "not_trusted", "time_bound",
                                        "interrupted"};
    d["verdict"] = std::string(verdicts[static_cast<int>(out.verdict)]);
    d["verdict_message"] = out.message;
    d["interrupted"] = interrupted;
    d["controls_at_bound"] = check.controls_at_bound; // active bounds (solution_check.hpp)
    d["velocity_excess"] = check.velocity_excess;
    if (out.reach_miss)
        d["reach_miss"] = py::make_tuple(out.reach_miss->distance, out.reach_miss->angle);
    else
        d["reach_miss"] = py::none();
    return d;
}

} // namespace

void bind_optimal(py::module_& m) {
    m.def("optimize", &optimize);
}
