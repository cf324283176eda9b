// models/src/simulation_of.hpp: the one implementation of models::simulation, a template over
// the stepper, and the factories a model file calls: simulate_family (the separable systems'
// steppers: newmark, simpson and the family, chosen by the scheme) and simulate_general (the
// general engine, with or without a force). Private to the models layer.
#pragma once

#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "step_checks.hpp"
#include "varsym/diagnostics/chaos.hpp"
#include "varsym/diagnostics/stability.hpp"
#include "varsym/models/model.hpp"
#include "varsym/run/energy.hpp"
#include "varsym/schemes/variational.hpp"
#include "varsym/systems/forcing.hpp"

namespace varsym::models::detail {

/// The model's columns: `fill(t, x, stepper, out)` writes one value per name.
template <class Fill>
struct column_set {
    std::vector<std::string> names;
    Fill fill;
    /// The coordinates' names for the state columns q_NAME, p_NAME (a robot's joints); empty:
    /// q_1 … q_d.
    std::vector<std::string> coordinates = {};
};
template <class Fill>
column_set(std::vector<std::string>, Fill) -> column_set<Fill>;
template <class Fill>
column_set(std::vector<std::string>, Fill, std::vector<std::string>) -> column_set<Fill>;

template <class S, class Fill>
class simulation_of final : public simulation {
    static constexpr int D = S::dim;

  public:
    simulation_of(S stepper, const phase_state<D>& x0, column_set<Fill> cols, double t0 = 0.0)
        : s_(std::move(stepper)), r_(run_state<D>::start(x0, t0)), cols_(std::move(cols)) {}

    [[nodiscard]] int dim() const override { return static_cast<int>(r_.x.q.size()); }
    [[nodiscard]] double step_size() const override { return s_.step_size(); }
    [[nodiscard]] std::size_t step() const override { return r_.step; }
    [[nodiscard]] double time() const override { return r_.time(s_.step_size()); }
    [[nodiscard]] std::span<const double> q() const override {
        return {r_.x.q.data(), static_cast<std::size_t>(r_.x.q.size())};
    }
    [[nodiscard]] std::span<const double> p() const override {
        return {r_.x.p.data(), static_cast<std::size_t>(r_.x.p.size())};
    }
    [[nodiscard]] const std::vector<std::string>& columns() const override { return cols_.names; }
    [[nodiscard]] std::span<const double> contact_impulses() const override {
        if constexpr (requires { s_.last_impulses(); })
            return s_.last_impulses();
        else
            return {};
    }
    [[nodiscard]] std::vector<std::string> state_columns() const override {
        if (cols_.coordinates.empty()) return simulation::state_columns();
        std::vector<std::string> names;
        for (const char* prefix : {"q_", "p_"})
            for (const std::string& c : cols_.coordinates)
                names.push_back(prefix + c);
        return names;
    }
    void values(std::span<double> out) const override {
        if (out.size() < cols_.names.size())
            throw std::invalid_argument("simulation::values: room for " +
                                        std::to_string(cols_.names.size()) + " values needed");
        cols_.fill(time(), r_.x, s_, out.data());
    }
    [[nodiscard]] double watched_energy() const override {
        return varsym::watched_energy(s_, r_.x, time());
    }
    [[nodiscard]] bool conserves_energy() const override {
        return varsym::conserves_energy(s_.system());
    }
    [[nodiscard]] double highest_frequency() const override {
        try {
            if constexpr (timed_system<std::remove_cvref_t<decltype(s_.system())>>)
                return varsym::highest_frequency(s_.system(), r_.x, time());
            else
                return varsym::highest_frequency(s_.system(), r_.x);
        } catch (const std::exception&) { // no estimate at this state
            return std::numeric_limits<double>::quiet_NaN();
        }
    }
    [[nodiscard]] const run_summary& stats() const override { return r_.stats; }

    bool advance(std::size_t n, const std::function<bool()>& after_step) override {
        return integrate_from(s_, r_, n, [&](const run_state<D>&) { return after_step(); });
    }

    [[nodiscard]] run_state<dynamic> save() const override {
        run_state<dynamic> out;
        out.x = {r_.x.q, r_.x.p};
        out.carry_q = r_.carry_q;
        out.carry_p = r_.carry_p;
        out.step = r_.step;
        out.t0 = r_.t0;
        out.stats = r_.stats;
        out.history = r_.history;
        return out;
    }
    void restore(const run_state<dynamic>& saved) override {
        const Eigen::Index d = r_.x.q.size();
        for (const auto* v : {&saved.x.q, &saved.x.p, &saved.carry_q, &saved.carry_p})
            if (v->size() != d)
                throw std::invalid_argument(
                    "a saved state of " + std::to_string(v->size()) +
                    " values cannot continue a simulation of d = " + std::to_string(d));
        r_.x = {saved.x.q, saved.x.p};
        r_.carry_q = saved.carry_q;
        r_.carry_p = saved.carry_p;
        r_.step = saved.step;
        r_.t0 = saved.t0;
        r_.stats = saved.stats;
        r_.history = saved.history;
        varsym::restore(s_, r_);
    }

    void tangent_map(Eigen::MatrixXd& jacobian) override {
        S s = s_; // a copy steps, so that this run is left as it was
        phase_state<D> x = r_.x;
        timed(s, time());
        const newton_report rep = s.step(x);
        if (!rep.converged) throw step_failure(r_.step + 1, time(), time() + s.step_size(), rep);
        s.step_jacobian(r_.x, jacobian);
    }
    [[nodiscard]] member_result run_member(
        const member_plan& plan,
        const std::function<double(double, std::span<const double>, std::span<const double>)>&
            event) override {
        S s = s_;
        timed(s, time());
        member_plan from_here = plan;
        from_here.t0 = time();
        auto g = [&](double t, const phase_state<D>& y) {
            if (!event) return 1.0;
            return event(t, {y.q.data(), static_cast<std::size_t>(y.q.size())},
                         {y.p.data(), static_cast<std::size_t>(y.p.size())});
        };
        // The member's energy error is that of what the run's watch follows: E, or E − W under a
        // force or an L that depends on t, at the stepper's time (after a step: its end).
        return varsym::run_member(
            s, r_.x, from_here,
            [&](const phase_state<D>& y) {
                if constexpr (requires { s.time(); })
                    return varsym::watched_energy(s, y, s.time());
                else
                    return varsym::watched_energy(s, y, 0.0);
            },
            g);
    }
    [[nodiscard]] bool has_dense_output() const override { return dense_stepper<S>; }
    [[nodiscard]] section_result
    section(const section_plane& plane, long long steps, long long crossings,
            const std::atomic<bool>* stop,
            const std::function<void(const section_result&)>& drain) override {
        section_result out;
        if constexpr (dense_stepper<S>) {
            S s = s_;
            timed(s, time());
            phase_state<D> x = r_.x;
            const double h = s.step_size();
            long long found = 0;
            for (long long j = 0; j < steps && found < crossings; ++j) {
                if (stop != nullptr && stop->load(std::memory_order_relaxed)) {
                    out.stopped = true;
                    break;
                }
                const phase_state<D> from = x;
                if (!s.step(x).converged || !x.q.allFinite() || !x.p.allFinite()) {
                    out.failed = true;
                    break;
                }
                const auto c =
                    find_crossing(s, from, x, time() + static_cast<double>(j) * h, plane);
                if (!c) continue;
                ++found;
                out.time.push_back(c->time);
                for (const auto* v : {&c->x.q, &c->x.p})
                    out.states.insert(out.states.end(), v->data(), v->data() + v->size());
                if (drain && out.time.size() >= section_drain_size) {
                    drain(out);
                    out.time.clear();
                    out.states.clear();
                }
            }
            return out;
        } else {
            throw std::logic_error("this model's stepper has no dense output for sections");
        }
    }

  private:
    /// A forced or time-dependent step depends on its start time.
    static void timed(S& s, double t) {
        if constexpr (requires { s.set_time(t); }) s.set_time(t);
    }
    S s_;
    run_state<D> r_;
    column_set<Fill> cols_;
};

/// A simulation of a separable system by the scheme's own stepper (newmark, simpson or the
/// family member), from x0 at time t0. Refuses the articulated iteration (robots only), which
/// newmark's and simpson's own steppers would not otherwise see.
template <class System, int D, class Fill>
std::unique_ptr<simulation> simulate_family(const System& sys, const phase_state<D>& x0,
                                            const step_options& o, column_set<Fill> cols,
                                            double t0 = 0.0) {
    if (o.newton.iteration == iteration_kind::articulated)
        throw std::invalid_argument("the articulated iteration is for robots (URDF models); "
                                    "choose newton, simplified or fixed-point");
    return with_stepper(o.spec, sys, o.h, o.newton, [&](auto& s) -> std::unique_ptr<simulation> {
        using S = std::remove_cvref_t<decltype(s)>;
        phase_state<S::dim> x{x0.q, x0.p};
        return std::make_unique<simulation_of<S, Fill>>(std::move(s), x, std::move(cols), t0);
    });
}

/// A simulation of a general Lagrangian system by the general engine (any scheme), refusing the
/// `previous` and `forces` predictors, which are the separable steppers' alone.
template <class Stepper, int D, class Fill>
std::unique_ptr<simulation> simulate_general(Stepper stepper, const phase_state<D>& x0,
                                             column_set<Fill> cols, double t0 = 0.0) {
    return std::make_unique<simulation_of<Stepper, Fill>>(std::move(stepper), x0, std::move(cols),
                                                          t0);
}

/// The parameter `project` every constrained model has (its last).
inline parameter project_parameter() {
    return {.name = "project",
            .value = 0.0,
            .doc = "move initial data onto the constraints (else inconsistent data is refused)",
            .lower = 0.0,
            .upper = 1.0,
            .flag = true};
}

/// The initial state of a general Lagrangian system: q0, and p0 or p = ∂L/∂q̇ at v0 (defaults
/// from the model); refuses a singular mass matrix there.
template <class Sys, int D>
phase_state<D> general_start(const Sys& sys, const start& s, const vec<D>& q0, const vec<D>& v0) {
    auto vector = [&](const std::vector<double>& given, const vec<D>& fallback) -> vec<D> {
        if (given.empty()) return fallback;
        return Eigen::Map<const vec<D>>(given.data(), q0.size());
    };
    const vec<D> q = vector(s.q0, q0);
    const vec<D> v = vector(s.v0, v0);
    sys.check_regular(q, v);
    const vec<D> p = s.p0.empty() ? vec<D>(sys.momentum(q, v)) : vector(s.p0, v0);
    sys.check_regular(q, sys.velocity(q, p));
    return {q, p};
}

/// The problem of a state and period.
template <int D>
problem make_problem(const phase_state<D>& x, double period,
                     std::function<std::unique_ptr<simulation>(const step_options&)> simulate) {
    problem pr;
    pr.q0.assign(x.q.data(), x.q.data() + x.q.size());
    pr.p0.assign(x.p.data(), x.p.data() + x.p.size());
    pr.period = period;
    pr.simulate = std::move(simulate);
    return pr;
}

/// The problem of a general Lagrangian system driven by a constant input u through
/// controlled<F> (the input a generalized force on the coordinates F names), from x0: columns
/// energy and work (E − W is what the energy watch follows).
template <class L, class F>
problem controlled_problem(const lagrangian_system<L>& sys, double u,
                           const phase_state<L::dim>& x0) {
    controlled<F> force;
    force.u(0) = u;
    return make_problem(x0, 0.0, [=](const step_options& o) {
        check_general(o);
        return simulate_general(
            general::stepper<L, controlled<F>>(sys, force, o.h, o.spec, o.newton), x0,
            column_set{{"energy", "work"},
                       [sys](double, const auto& x, const auto& st, double* out) {
                           out[0] = sys.energy(x);
                           out[1] = st.total_work();
                       }});
    });
}

} // namespace varsym::models::detail
