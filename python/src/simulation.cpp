// python/src/simulation.cpp: the models layer in Python: the registry's data, problems, and
// simulations (varsym/models/simulation.hpp) bound directly, with a recording loop that fills
// NumPy arrays allocated once by the caller, releases the GIL while it steps, and looks at
// signals and the progress callback every 50 ms.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <chrono>
#include <optional>
#include <thread>

#include "bindings.hpp"
#include "interruptible.hpp"
#include "varsym/models/animation.hpp"
#include "varsym/models/event.hpp"
#include "varsym/models/expression.hpp"
#include "varsym/models/model.hpp"
#include "varsym/run/energy.hpp"
#include "varsym/run/ensemble.hpp"
#include "varsym/solvers/solver_name.hpp"

namespace py = pybind11;
using namespace varsym;

namespace {

py::array_t<double> array_of(std::span<const double> v) {
    return py::array_t<double>(static_cast<py::ssize_t>(v.size()), v.data());
}

/// The columns a row shows besides t, q and p: the state's own (a rigid body's quaternion and
/// Ω, where they are not q and p) and the model's.
std::vector<std::string> row_columns(const models::simulation& sim) {
    std::vector<std::string> names = sim.state_columns();
    // q and p under other names (a robot's joints: the Trajectory's coordinates name them), or
    // under their own: no columns of their own.
    if (names.size() == 2 * static_cast<std::size_t>(sim.dim())) names.clear();
    names.insert(names.end(), sim.columns().begin(), sim.columns().end());
    return names;
}

/// Their values at the current state; `state` = the state's own columns' count (0 or 2d+).
void row_values(const models::simulation& sim, std::size_t state, std::vector<double>& out) {
    if (state > 0) sim.state_values(out);
    sim.values(std::span<double>(out).subspan(state));
}

/// What record() did: the rows written; whether SIGINT's handler raised KeyboardInterrupt (then
/// cleared, for the caller to raise varsym.Interrupted with the rows); whether the energy watch
/// stopped the run, and its relative error then.
struct recorded {
    std::size_t rows = 0;
    bool interrupted = false;
    bool energy = false;
    double energy_error = 0.0;
};

/// Steps sim to step `last`, writing rows (t, q, p, the model's columns) into the arrays from
/// row `row` on: every `every` steps and at `last`. Every 50 ms it takes the GIL to run the
/// signal handlers and call progress(step). A failed step raises StepFailure carrying the step,
/// the time, the cause, the last good state and the rows written.
recorded record(models::simulation& sim, std::size_t last, std::size_t every, py::array_t<double> t,
                py::array_t<double> q, py::array_t<double> p, py::array_t<double> columns,
                std::size_t row, const py::object& progress, const energy_watch& watch) {
    const auto d = static_cast<std::size_t>(sim.dim());
    const std::size_t ncol = row_columns(sim).size();
    const std::size_t state = ncol - sim.columns().size();
    auto tw = t.mutable_unchecked<1>();
    auto qw = q.mutable_unchecked<2>();
    auto pw = p.mutable_unchecked<2>();
    auto cw = columns.mutable_unchecked<2>();
    const auto capacity = static_cast<std::size_t>(tw.shape(0));
    if (static_cast<std::size_t>(qw.shape(1)) != d || static_cast<std::size_t>(cw.shape(1)) != ncol)
        throw std::invalid_argument("record: arrays of the wrong width");
    std::vector<double> values(ncol);
    recorded out{row, false};
    auto write = [&] {
        if (out.rows >= capacity) throw std::invalid_argument("record: the arrays are full");
        const auto r = static_cast<py::ssize_t>(out.rows);
        tw(r) = sim.time();
        for (std::size_t i = 0; i < d; ++i) {
            qw(r, static_cast<py::ssize_t>(i)) = sim.q()[i];
            pw(r, static_cast<py::ssize_t>(i)) = sim.p()[i];
        }
        row_values(sim, state, values);
        for (std::size_t k = 0; k < ncol; ++k)
            cw(r, static_cast<py::ssize_t>(k)) = values[k];
        ++out.rows;
    };
    using clock = std::chrono::steady_clock;
    auto next = clock::now() + std::chrono::milliseconds(50);
    // Ctrl-C and the progress callback are looked at every 50 ms of wall time, whatever a step
    // costs: the clock is read every `stride` steps, the stride doubled (up to 64) while the
    // steps between two reads took less than 1 ms and reset to 1 when they took more. The
    // cheapest steps (tens of ns) then pay one read per 64 steps; a 1000-link robot's (tens of
    // ms) one per step, not 64 steps of seconds before Ctrl-C is seen.
    std::size_t stride = 1, since_read = 0;
    auto last_read = clock::now();
    std::optional<py::error_already_set> raised; // by a signal handler or the callback
    {
        py::gil_scoped_release unlocked;
        try {
            sim.advance(last, [&] {
                const std::size_t j = sim.step();
                const bool written = (every != 0 && j % every == 0) || j == last;
                if (written) models::evaluated(sim, write);
                // The energy watch at each written row and every 256 steps (an energy costs
                // about a step), as the tool's.
                if (watch.on() && (written || (j & 255U) == 0) &&
                    watch.exceeded(models::evaluated(sim, [&] { return sim.watched_energy(); }))) {
                    out.energy = true;
                    out.energy_error = watch.error(sim.watched_energy());
                    return true;
                }
                if (++since_read < stride) return false;
                since_read = 0;
                const auto now = clock::now();
                stride = now - last_read < std::chrono::milliseconds(1)
                             ? std::min<std::size_t>(2 * stride, 64)
                             : 1;
                last_read = now;
                if (now < next) return false;
                next = now + std::chrono::milliseconds(50);
                py::gil_scoped_acquire locked;
                try {
                    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
                    if (!progress.is_none()) progress(j);
                } catch (py::error_already_set& e) {
                    raised.emplace(std::move(e));
                    return true;
                }
                return false;
            });
        } catch (const step_failure& e) {
            py::gil_scoped_acquire locked;
            raise_step_failure(e, sim.q(), sim.p(), out.rows);
        }
    }
    if (raised) {
        if (!raised->matches(PyExc_KeyboardInterrupt)) throw std::move(*raised);
        out.interrupted = true; // the caller raises varsym.Interrupted with the rows
    }
    return out;
}

/// The force of L from its components' expressions (none: zero).
expression_force force_of(const expression_lagrangian& l, const std::vector<std::string>& force) {
    return force.empty() ? expression_force(l.dimension())
                         : expression_force(force, l.coordinates(), l.parameters());
}

/// (q0, p0) as a state.
phase_state<dynamic> state_of(const std::vector<double>& q0, const std::vector<double>& p0) {
    const auto map = [](const std::vector<double>& v) {
        return vec<dynamic>(Eigen::Map<const vec<dynamic>>(v.data(), std::ssize(v)));
    };
    return {map(q0), map(p0)};
}

} // namespace

py::dict model_info(const models::model& mod) {
    py::list parameters, lists;
    for (const auto& l : mod.lists)
        lists.append(py::dict(
            py::arg("name") = l.name, py::arg("default") = l.value, py::arg("unit") = l.unit,
            py::arg("doc") = l.doc, py::arg("range") = "each " + l.range(),
            py::arg("sets_dimension") = l.sets_dimension, py::arg("option") = l.option_name()));
    for (const auto& p : mod.parameters)
        parameters.append(py::dict(
            py::arg("name") = p.name, py::arg("default") = p.value, py::arg("unit") = p.unit,
            py::arg("doc") = p.doc, py::arg("range") = p.range(),
            py::arg("nan_means") = p.nan_means, py::arg("integer") = p.integer,
            py::arg("flag") = p.flag, py::arg("sets_dimension") = p.sets_dimension,
            py::arg("option") = p.option_name(), py::arg("option_index") = p.option_index));
    return py::dict(py::arg("name") = mod.name, py::arg("summary") = mod.summary,
                    py::arg("description") = mod.description, py::arg("dim") = mod.dim,
                    py::arg("coordinates") = mod.coordinates, py::arg("parameters") = parameters,
                    py::arg("q0") = mod.q0, py::arg("p0") = mod.p0,
                    py::arg("fixed_start") = mod.fixed_start,
                    py::arg("velocities") = mod.velocities,
                    py::arg("short_start") = mod.short_start, py::arg("lists") = lists,
                    py::arg("steps_per_period") = mod.steps_per_period, py::arg("time") = mod.time,
                    py::arg("steps") = mod.steps, py::arg("ensemble_time") = mod.ensemble_time,
                    py::arg("ensemble_steps") = mod.ensemble_steps,
                    py::arg("integrator_note") = mod.integrator_note,
                    py::arg("drawn") = static_cast<bool>(mod.drawing));
}

void bind_simulation(py::module_& m) {
    py::class_<models::simulation>(m, "_Simulation")
        .def_property_readonly("dim", &models::simulation::dim)
        .def_property_readonly("h", &models::simulation::step_size)
        .def_property_readonly("step", &models::simulation::step)
        .def_property_readonly("t", &models::simulation::time)
        .def_property_readonly("q", [](const models::simulation& s) { return array_of(s.q()); })
        .def_property_readonly("p", [](const models::simulation& s) { return array_of(s.p()); })
        .def_property_readonly("columns", &row_columns)
        .def_property_readonly("values",
                               [](const models::simulation& s) {
                                   const std::size_t n = row_columns(s).size();
                                   std::vector<double> v(n);
                                   row_values(s, n - s.columns().size(), v);
                                   return v;
                               })
        .def_property_readonly("has_tangent_map", &models::simulation::has_tangent_map)
        .def_property_readonly("watched_energy", &models::simulation::watched_energy)
        .def_property_readonly("conserves_energy", &models::simulation::conserves_energy)
        .def_property_readonly(
            "mean_newton_iterations",
            [](const models::simulation& s) { return s.stats().mean_newton_iterations(); })
        .def(
            "record",
            [](models::simulation& s, std::size_t last, std::size_t every, py::array_t<double> t,
               py::array_t<double> q, py::array_t<double> p, py::array_t<double> columns,
               std::size_t row, const py::object& progress, double e0, double bound) {
                const recorded r = record(s, last, every, t, q, p, columns, row, progress,
                                          energy_watch(e0, bound));
                return py::make_tuple(r.rows, r.interrupted, r.energy, r.energy_error);
            },
            py::arg("last"), py::arg("every"), py::arg("t"), py::arg("q"), py::arg("p"),
            py::arg("columns"), py::arg("row"), py::arg("progress"), py::arg("e0"),
            py::arg("bound"))
        .def_property_readonly("highest_frequency", &models::simulation::highest_frequency)
        .def("tangent_map",
             [](models::simulation& s) {
                 Eigen::MatrixXd j;
                 s.tangent_map(j);
                 py::array_t<double> a({j.rows(), j.cols()});
                 for (Eigen::Index r = 0; r < j.rows(); ++r)
                     for (Eigen::Index c = 0; c < j.cols(); ++c)
                         a.mutable_at(r, c) = j(r, c);
                 return a;
             })
        .def("has_dense_output", &models::simulation::has_dense_output)
        .def(
            "section",
            [](models::simulation& s, bool momentum, int index, double value, int direction,
               long long steps, long long crossings) {
                const section_plane plane{momentum, index, value, direction};
                models::section_result r;
                std::atomic<bool> stop{false};
                varsym_python::run_interruptible(
                    [&] { r = s.section(plane, steps, crossings, &stop); }, [&] { stop = true; });
                const auto w = static_cast<py::ssize_t>(2 * s.dim());
                py::array_t<double> states({static_cast<py::ssize_t>(r.time.size()), w});
                std::copy(r.states.begin(), r.states.end(), states.mutable_data());
                return py::make_tuple(array_of(r.time), states, r.failed, r.stopped);
            },
            py::arg("momentum"), py::arg("index"), py::arg("value"), py::arg("direction"),
            py::arg("steps"), py::arg("crossings"));

    py::class_<models::problem>(m, "_Problem")
        .def_property_readonly("q0", [](const models::problem& p) { return p.q0; })
        .def_property_readonly("p0", [](const models::problem& p) { return p.p0; })
        .def_property_readonly("period", [](const models::problem& p) { return p.period; })
        .def_property_readonly("no_period", [](const models::problem& p) { return p.no_period; })
        .def_property_readonly("integrator",
                               [](const models::problem& p) -> py::object {
                                   if (p.integrator.label.empty()) return py::none();
                                   return py::make_tuple(p.integrator.label, p.integrator.order);
                               })
        .def(
            "simulate",
            [](const models::problem& p, double h, const std::string& scheme, int degree,
               const std::string& iteration) {
                return p.simulate({spec_of(scheme, degree), parse_solver(iteration), h});
            },
            py::arg("h"), py::arg("scheme"), py::arg("degree"), py::arg("iteration"));

    m.def("default_energy_bound", &default_energy_bound, py::arg("order"), py::arg("h"),
          py::arg("omega"),
          "The energy watch's default bound: 100 (h omega)^order, between 0.01 and 0.5.");
    m.def(
        "scheme_order",
        [](const std::string& scheme, int degree) { return spec_of(scheme, degree).order(); },
        py::arg("scheme"), py::arg("degree"));
    m.def("registry", [] {
        py::list out;
        for (const models::model& mod : models::registry())
            out.append(model_info(mod));
        return out;
    });
    m.def(
        "check_parameters",
        [](const std::string& name, const std::vector<double>& values, const models::lists& lists) {
            const models::model& mod = models::get(name);
            try {
                for (std::size_t i = 0; i < mod.parameters.size() && i < values.size(); ++i)
                    mod.parameters[i].check(values[i]);
                for (std::size_t i = 0; i < mod.lists.size() && i < lists.size(); ++i)
                    if (!lists[i].empty()) mod.lists[i].check(lists[i]);
            } catch (const std::invalid_argument& e) {
                throw std::invalid_argument(name + ": " + e.what());
            }
        },
        py::arg("name"), py::arg("values"), py::arg("lists"),
        "Each parameter against its range (ValueError naming it), before anything is sized.");
    m.def(
        "animate_model",
        [](const std::string& name, const std::vector<double>& values, const models::lists& lists,
           const std::vector<double>& t,
           py::array_t<double, py::array::c_style | py::array::forcecast> q,
           const std::string& path, double fps, const std::string& title,
           const std::vector<std::string>& names) {
            const models::model& mod = models::get(name);
            if (!mod.drawing) throw std::invalid_argument(name + " has no 3-D figure");
            if (q.ndim() != 2) throw std::invalid_argument("q must be a rows x d array");
            const Eigen::MatrixXd rows = Eigen::Map<
                const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
                q.data(), q.shape(0), q.shape(1));
            models::animation_options o;
            o.fps = fps;
            o.title = title.empty() ? name : title;
            const models::figure f = mod.drawing(values, lists);
            models::animation_report rep;
            {
                py::gil_scoped_release unlocked;
                rep = models::write_animation(f, t, rows, path, o, names);
            }
            py::dict out;
            out["frames"] = rep.frames;
            out["bytes"] = rep.bytes;
            out["warnings"] = rep.warnings;
            return out;
        },
        py::arg("name"), py::arg("values"), py::arg("lists"), py::arg("t"), py::arg("q"),
        py::arg("path"), py::arg("fps"), py::arg("title"), py::arg("names"),
        "Model `name`'s motion (t, q) as its 3-D animation page (models/animation.hpp).");
    m.def(
        "prepare",
        [](const std::string& name, const std::vector<double>& values,
           const std::vector<double>& q0, const std::vector<double>& p0,
           const std::vector<double>& v0, const models::lists& lists) {
            return models::get(name).prepare(values, {q0, p0, v0}, lists);
        },
        py::arg("name"), py::arg("values"), py::arg("q0"), py::arg("p0"), py::arg("v0"),
        py::arg("lists") = models::lists{});
    m.def(
        "simulate_expression",
        [](const expression_lagrangian& l, const std::vector<std::string>& force,
           const std::vector<double>& q0, const std::vector<double>& p0, double t0, double h,
           const std::string& scheme, int degree, const std::string& iteration) {
            return models::simulate_expression(
                l, force_of(l, force), state_of(q0, p0),
                {spec_of(scheme, degree), parse_solver(iteration), h}, t0);
        },
        py::arg("lagrangian"), py::arg("force"), py::arg("q0"), py::arg("p0"), py::arg("t0"),
        py::arg("h"), py::arg("scheme"), py::arg("degree"), py::arg("iteration"));
    m.def(
        "simulate_constrained_expression",
        [](const expression_lagrangian& l, const std::vector<std::string>& constraints,
           const std::vector<std::string>& force, const std::vector<double>& q0,
           const std::vector<double>& p0, double t0, double h, const std::string& scheme,
           int degree, const std::string& iteration, bool project) {
            const expression_constraint c(constraints, l.coordinates(), l.parameters());
            return models::simulate_constrained_expression(
                l, c, force_of(l, force), state_of(q0, p0),
                {spec_of(scheme, degree), parse_solver(iteration), h}, t0, project);
        },
        py::arg("lagrangian"), py::arg("constraints"), py::arg("force"), py::arg("q0"),
        py::arg("p0"), py::arg("t0"), py::arg("h"), py::arg("scheme"), py::arg("degree"),
        py::arg("iteration"), py::arg("project"));
}
