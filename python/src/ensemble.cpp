// python/src/ensemble.cpp: ensembles from Python, of a built-in model or of a Lagrangian typed
// as an expression: one member per row of the arrays given, run on every core without the GIL.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <optional>

#include "bindings.hpp"
#include "interruptible.hpp"
#include "varsym/models/event.hpp"
#include "varsym/models/expression.hpp"
#include "varsym/models/model.hpp"
#include "varsym/run/ensemble.hpp"

namespace py = pybind11;
using namespace varsym;

py::dict run_ensemble(const models::model& mod, py::array_t<double, py::array::c_style> values,
                      py::array_t<double, py::array::c_style> q0,
                      py::array_t<double, py::array::c_style> p0, double h, long long steps,
                      const std::string& scheme, int degree, bool indicators, unsigned threads,
                      const std::string& event, const models::lists& lists) {
    const auto n = static_cast<std::size_t>(values.shape(0));
    const auto np = mod.parameters.size();
    // Every member shares d: the parameters that set it (the chain's n) are the first
    // row's.
    const auto d = static_cast<std::size_t>(
        n > 0 && static_cast<std::size_t>(values.shape(1)) == np
            ? mod.dimension_at(std::span<const double>(values.data(), np), lists)
            : mod.dim);
    const bool start = q0.size() > 0;
    if (static_cast<std::size_t>(values.shape(1)) != np ||
        (start && (static_cast<std::size_t>(q0.shape(0)) != n ||
                   static_cast<std::size_t>(q0.shape(1)) != d || q0.size() != p0.size())))
        throw std::invalid_argument("ensemble: arrays of the wrong shape");
    const models::step_options opt{spec_of(scheme, degree), {}, h};
    member_plan plan;
    plan.steps = steps;
    plan.indicators = indicators;
    std::optional<expr::tape> event_tape;
    if (!event.empty()) event_tape = models::compile_event(event, static_cast<int>(d));
    std::vector<member_result> results(n);
    std::vector<std::string> invalid(n);
    const double* v = values.data();
    const double* qa = q0.data();
    const double* pa = p0.data();
    // Ctrl-C: the members in flight stop after their current step ("stopped"), the others are
    // not started ("not run"); the members done are returned.
    std::atomic<bool> stop{false};
    plan.stop = &stop;
    std::vector<char> started(n, 0);
    const bool interrupted = varsym_python::run_interruptible(
        [&] {
            for_each_member(n, threads, [&](std::size_t k) {
                if (stop.load()) return;
                started[k] = 1;
                try {
                    models::start st;
                    if (start) {
                        st.q0.assign(qa + k * d, qa + (k + 1) * d);
                        st.p0.assign(pa + k * d, pa + (k + 1) * d);
                    }
                    const auto sim = mod.prepare(std::span<const double>(v + k * np, np), st, lists)
                                         .simulate(opt);
                    if (static_cast<std::size_t>(sim->dim()) != d)
                        throw std::invalid_argument(
                            "the members share the first member's number of coordinates, " +
                            std::to_string(d) + ": the parameters that set it must not vary");
                    const models::event_function g =
                        event_tape ? models::event_of(*event_tape) : nullptr;
                    results[k] = sim->run_member(plan, g);
                } catch (const std::invalid_argument& e) {
                    invalid[k] = e.what();
                }
            });
        },
        [&] { stop = true; });
    py::array_t<double> q({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(d)});
    py::array_t<double> p({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(d)});
    py::array_t<double> t(static_cast<py::ssize_t>(n)), lyapunov(t.size()), megno(t.size()),
        energy(t.size()), event_time(t.size());
    std::vector<std::string> status(n), cause(n);
    for (std::size_t k = 0; k < n; ++k) {
        const member_result& r = results[k];
        const bool bad = !invalid[k].empty() || started[k] == 0;
        status[k] = started[k] == 0                               ? "not run"
                    : !invalid[k].empty()                         ? "invalid"
                    : r.status == member_result::outcome::failed  ? "failed"
                    : r.status == member_result::outcome::event   ? "event"
                    : r.status == member_result::outcome::stopped ? "stopped"
                                                                  : "completed";
        cause[k] = bad ? invalid[k] : r.cause;
        const double nan = std::numeric_limits<double>::quiet_NaN();
        for (std::size_t i = 0; i < d; ++i) {
            q.mutable_at(k, i) = bad ? nan : r.q[i];
            p.mutable_at(k, i) = bad ? nan : r.p[i];
        }
        t.mutable_at(k) = bad ? nan : r.time;
        lyapunov.mutable_at(k) = bad ? nan : r.lyapunov;
        megno.mutable_at(k) = bad ? nan : r.mean_megno;
        energy.mutable_at(k) = bad ? nan : r.max_energy_error;
        event_time.mutable_at(k) = bad ? nan : r.event_time;
    }
    py::dict out;
    out["status"] = status;
    out["t"] = t;
    out["q"] = q;
    out["p"] = p;
    out["lyapunov"] = lyapunov;
    out["mean_megno"] = megno;
    out["max_energy_error"] = energy;
    out["event_time"] = event_time;
    out["cause"] = cause;
    out["interrupted"] = interrupted;
    return out;
}

void bind_ensemble(py::module_& m) {
    m.def(
        "ensemble",
        [](const std::string& name, py::array_t<double, py::array::c_style> values,
           py::array_t<double, py::array::c_style> q0, py::array_t<double, py::array::c_style> p0,
           double h, long long steps, const std::string& scheme, int degree, bool indicators,
           unsigned threads, const std::string& event, const models::lists& lists) {
            return run_ensemble(models::get(name), values, q0, p0, h, steps, scheme, degree,
                                indicators, threads, event, lists);
        },
        py::arg("name"), py::arg("values"), py::arg("q0"), py::arg("p0"), py::arg("h"),
        py::arg("steps"), py::arg("scheme"), py::arg("degree"), py::arg("indicators"),
        py::arg("threads"), py::arg("event"), py::arg("lists") = models::lists{});
    m.def(
        "expression_ensemble",
        [](const expression_lagrangian& l, const std::vector<std::string>& force,
           const std::vector<std::string>& constraints,
           py::array_t<double, py::array::c_style> values,
           py::array_t<double, py::array::c_style> q0, py::array_t<double, py::array::c_style> p0,
           double h, long long steps, const std::string& scheme, int degree, bool indicators,
           unsigned threads, const std::string& event) {
            const models::model mod =
                models::expression_model(l, force, constraints); // L built once
            return run_ensemble(mod, values, q0, p0, h, steps, scheme, degree, indicators, threads,
                                event, {});
        },
        py::arg("lagrangian"), py::arg("force"), py::arg("constraints"), py::arg("values"),
        py::arg("q0"), py::arg("p0"), py::arg("h"), py::arg("steps"), py::arg("scheme"),
        py::arg("degree"), py::arg("indicators"), py::arg("threads"), py::arg("event"));
}
