// optimal/src/model_optimize.cpp: optimize(model, parameters, request), the one sequence both
// front ends run: parameters → limits → transcription → solve (refined) → unpack → check →
// verdict (varsym/optimize/model.hpp).
#include "varsym/optimize/model.hpp"

#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <utility>

namespace varsym::optimal {

std::unique_ptr<transcription> transcribe(const models::model& m, std::span<const double> values,
                                          const models::lists& lists,
                                          const control_problem& problem) {
    if (!m.control)
        throw std::invalid_argument("model " + m.name + " has no control input to optimise");
    return transcribe(m.control(values, lists), problem);
}

hessian_kind hessian_of(std::string_view word) {
    if (word == "automatic") return hessian_kind::automatic;
    if (word == "exact") return hessian_kind::exact;
    if (word == "limited-memory") return hessian_kind::limited_memory;
    throw std::invalid_argument("the Hessian must be automatic, exact or limited-memory, got '" +
                                std::string(word) + "'");
}

namespace {

/// Refuses a parameter or list only a simulation uses (a controller's gains, the constant
/// input) set away from its default: the optimisation computes the inputs and would drop it.
void refuse_simulation_only(const models::model& m, std::span<const double> values,
                            const models::lists& lists) {
    auto refuse = [&](const std::string& name) {
        const bool contact = name == "contact" || name == "friction" || name == "ground_height" ||
                             name == "ground_slope" || name == "boxes";
        throw std::invalid_argument(
            name + " is a simulation's parameter of " + m.name +
            (contact ? ": optimal control has no contact (its transcription keeps to motions in "
                       "free space)"
                     : "; optimize computes the inputs (bound them with max_control)"));
    };
    for (const std::string& only : m.simulation_only) {
        for (std::size_t i = 0; i < m.parameters.size() && i < values.size(); ++i)
            if (m.parameters[i].name == only && values[i] != m.parameters[i].value) refuse(only);
        for (std::size_t i = 0; i < m.lists.size() && i < lists.size(); ++i)
            if (m.lists[i].name == only && !lists[i].empty()) refuse(only);
    }
}

/// The verdict of a converged or stopped solve, with its line.
void judge(model_outcome& out) {
    const nlp_result& r = out.result;
    if (r.verdict == status::interrupted) {
        out.verdict = verdict::interrupted;
        out.message = "stopped: the last iterate is kept";
        return;
    }
    if (!r.converged()) {
        out.verdict = verdict::not_solved;
        // A pose target met to round-off while the motion's equations are not: not an
        // unreachable target but a degenerate one (the pose constraint's Jacobian loses rank
        // where the arm is fully stretched, a singular configuration).
        if (out.reach_miss && out.reach_miss->distance < 1e-9 && out.reach_miss->angle < 1e-9) {
            char violation[32];
            std::snprintf(violation, sizeof violation, "%.1e", r.constraint_violation);
            out.message = std::string(status_name(r.verdict)) + ": " + out.reach_frame +
                          " reaches its target, but the equations of motion are not met (max |g| " +
                          violation +
                          "): the target pose is likely at a singular configuration (an arm "
                          "fully stretched), where the pose constraint is degenerate; move the "
                          "target slightly inside the workspace, or make it a terminal cost "
                          "with a reach weight W > 0";
        } else {
            out.message = std::string(status_name(r.verdict)) + ": " + r.message;
        }
        return;
    }
    if (!out.check.ok()) {
        out.verdict = verdict::not_trusted;
        out.message = "not trusted: " + out.check.advice();
        return;
    }
    // A free horizon stopped at its lower bound, T = time / 1000 (the bound that keeps the
    // steps positive), is that bound's answer, not the minimum: the guess was too long.
    const control_problem& p = out.problem;
    if (p.free_time) {
        const double lower = p.time_lower > 0.0 ? p.time_lower : 1e-3 * p.time;
        const double t_end = out.path.node_times(out.path.node_times.size() - 1);
        if (t_end <= lower * (1.0 + 1e-9)) {
            out.verdict = verdict::time_bound;
            out.message = "the horizon T = " + std::to_string(t_end) +
                          " stopped at its lower bound (time / 1000): the minimum time may be "
                          "shorter; start from a shorter time";
            return;
        }
    }
    out.verdict = verdict::solved;
}

} // namespace

model_outcome optimize(const models::model& m, std::span<const double> values,
                       const models::lists& lists, model_request request) {
    if (!m.control)
        throw std::invalid_argument("model " + m.name + " has no control input to optimise");
    refuse_simulation_only(m, values, lists);
    if (request.threads < 0 || request.threads > 4096)
        throw std::invalid_argument("threads: 0 (one per CPU), 1 (none) to 4096, not " +
                                    std::to_string(request.threads));
    const auto transcribe_threaded = [&](const control_problem& q) {
        auto t = transcribe(m, values, lists, q);
        if (auto* dmoc = dynamic_cast<dmoc_transcription*>(t.get()))
            dmoc->set_threads(request.threads);
        return t;
    };
    model_outcome out;
    control_problem& p = out.problem;
    p = std::move(request.problem);
    std::unique_ptr<transcription> tr;
    try {
        (void)m.prepare(values, {}, lists); // the parameters' ranges
        if (request.limits && m.limits) m.limits(values, lists, p);
        if (request.reach) {
            const reach_request& r = *request.reach;
            p.end_target = models::frame_target(r.robot, r.frame, r.position, r.rotation);
            p.end_target_weight = r.weight;
        }
        // Minimum time over unbounded inputs has no minimum (the model's limits, applied above,
        // may bound them: a robot's URDF efforts).
        if (p.free_time && (p.control_lower.size() == 0 || p.control_upper.size() == 0 ||
                            !p.control_lower.allFinite() || !p.control_upper.allFinite()))
            throw std::invalid_argument("a cost on the time needs bounded inputs: with unbounded "
                                        "inputs the motion can be made as fast as one likes");
        tr = transcribe_threaded(p);
    } catch (const std::invalid_argument& e) { // named once: prepare's own messages name it
        const std::string what = e.what();
        throw std::invalid_argument(what.starts_with(m.name + ": ") ? what : m.name + ": " + what);
    }
    if (request.solver.hessian == hessian_kind::exact && !tr->has_hessian())
        throw std::invalid_argument("the exact Hessian: the invariant cost has none (it would need "
                                    "L's fourth derivatives); use automatic or limited-memory");
    if (request.ready) request.ready();
    const auto started = std::chrono::steady_clock::now();
    if (request.refine > 0) {
        auto refined = solve_refined(
            [&](int n) {
                auto q = p;
                q.steps = n;
                auto t = transcribe_threaded(q);
                if (request.level) request.level(n);
                return t;
            },
            p.steps, request.refine, request.solver);
        out.result = std::move(refined.result);
        tr = std::move(refined.problem);
    } else {
        out.result = solve(*tr, request.solver);
    }
    if (request.solved) request.solved();
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    out.path = tr->unpack(out.result);
    if (const auto* dmoc = dynamic_cast<const dmoc_transcription*>(tr.get()))
        out.threads = dmoc->evaluation_threads();
    // Our own check, whatever the solver says: the equations, bounds and boundary values, and
    // the replay (an IPOPT options file can loosen IPOPT's tolerances under "solved").
    if (out.result.converged()) out.check = check_solution(*tr, out.result, out.path);
    if (request.reach) {
        const reach_request& r = *request.reach;
        out.reach_frame = r.frame;
        out.reach_miss = models::frame_target_miss(
            *r.robot, r.frame, out.path.q.col(out.path.q.cols() - 1), r.position, r.rotation);
    }
    judge(out);
    return out;
}

} // namespace varsym::optimal
