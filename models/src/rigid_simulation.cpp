// models/src/rigid_simulation.cpp: the simulation of a rigid body on SO(3) by the Lie group
// variational integrator: its steps, rows (quaternion, Ω, the conserved quantities and closed
// forms), saved state (R and Π with their low-order parts) and ensemble members.
#include "rigid_simulation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "step_checks.hpp"
#include "varsym/lie/lgvi.hpp"
#include "varsym/lie/so3.hpp"
#include "varsym/run/ensemble.hpp"

namespace varsym::models::detail {

namespace {

/// R's entries row by row.
std::vector<double> rows_of(const lie::mat3& m) {
    std::vector<double> v;
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k)
            v.push_back(m(i, k));
    return v;
}

lie::mat3 matrix_of(const vec<dynamic>& v) {
    lie::mat3 m;
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k)
            m(i, k) = v(3 * i + k);
    return m;
}

vec<dynamic> vector_of(const std::vector<double>& v) {
    return Eigen::Map<const vec<dynamic>>(v.data(), static_cast<Eigen::Index>(v.size()));
}

/// The angle of the rotation taking a to b [rad].
double angle_between(const lie::mat3& a, const lie::mat3& b) {
    const auto q = so3::quaternion(a.transpose() * b);
    return 2.0 * std::atan2(std::sqrt(q[1] * q[1] + q[2] * q[2] + q[3] * q[3]), q[0]);
}

class rigid_simulation final : public simulation {
  public:
    rigid_simulation(const rigid_setup& r, const step_options& o)
        : r_(r), s_(r.body, o.h, r.order, o.newton), x_(r.x0) {
        const bool gravity = r.body.has_gravity();
        names_ = {"energy"};
        if (!gravity) names_.insert(names_.end(), {"L_x", "L_y", "L_z", "Pi_norm"});
        if (r.free) names_.emplace_back("attitude_error");
        if (gravity) names_.emplace_back("L_z");
        if (gravity && r.body.symmetric_about_e3()) names_.emplace_back("Pi_3");
        if (gravity) names_.emplace_back("theta");
        if (r.nutation) names_.emplace_back("theta_exact");
        names_.emplace_back("orthogonality");
        if (r.matrix)
            for (const char* e : {"11", "12", "13", "21", "22", "23", "31", "32", "33"})
                names_.push_back(std::string("R_") + e);
        update_euler();
    }

    [[nodiscard]] int dim() const override { return 3; }
    [[nodiscard]] double step_size() const override { return s_.step_size(); }
    [[nodiscard]] std::size_t step() const override { return step_; }
    [[nodiscard]] double time() const override {
        return static_cast<double>(step_) * s_.step_size();
    }
    [[nodiscard]] std::span<const double> q() const override { return euler_; }
    [[nodiscard]] std::span<const double> p() const override { return {x_.pi.data(), 3}; }
    [[nodiscard]] std::vector<std::string> state_columns() const override {
        return {"q_w", "q_x", "q_y", "q_z", "Omega_1", "Omega_2", "Omega_3"};
    }
    void state_values(std::span<double> out) const override {
        if (out.size() < 7) throw std::invalid_argument("state_values: room for 7 values needed");
        const auto quat = so3::quaternion(x_.R);
        const lie::vec3 omega = r_.body.omega(x_.pi);
        std::copy(quat.begin(), quat.end(), out.begin());
        for (int i = 0; i < 3; ++i)
            out[4 + static_cast<std::size_t>(i)] = omega(i);
    }
    [[nodiscard]] const std::vector<std::string>& columns() const override { return names_; }
    void values(std::span<double> out) const override {
        if (out.size() < names_.size())
            throw std::invalid_argument("simulation::values: room for " +
                                        std::to_string(names_.size()) + " values needed");
        const lie::rigid_body& b = r_.body;
        const bool gravity = b.has_gravity();
        const lie::vec3 l = lie::rigid_body::spatial_momentum(x_);
        std::size_t k = 0;
        out[k++] = b.energy(x_);
        if (!gravity)
            for (double v : {l(0), l(1), l(2), x_.pi.norm()})
                out[k++] = v;
        if (r_.free) out[k++] = angle_between(r_.free->at(time()).R, x_.R);
        if (gravity) out[k++] = l(2);
        if (gravity && b.symmetric_about_e3()) out[k++] = x_.pi(2);
        if (gravity) out[k++] = std::acos(std::clamp(x_.R(2, 2), -1.0, 1.0));
        if (r_.nutation) out[k++] = r_.nutation->theta(time());
        out[k++] = so3::orthogonality_error(x_.R);
        if (r_.matrix)
            for (double v : rows_of(x_.R))
                out[k++] = v;
    }
    [[nodiscard]] double watched_energy() const override { return r_.body.energy(x_); }
    [[nodiscard]] bool conserves_energy() const override { return true; }
    [[nodiscard]] double highest_frequency() const override {
        return r_.body.highest_frequency(x_);
    }
    [[nodiscard]] const run_summary& stats() const override { return stats_; }

    bool advance(std::size_t n, const std::function<bool()>& after_step) override {
        const double h = s_.step_size();
        while (step_ < n) {
            const newton_report rep = s_.step(x_); // x_ unchanged if it fails
            if (!rep.converged) {
                const double t = static_cast<double>(step_ + 1) * h;
                throw step_failure(step_ + 1, t - h, t, rep);
            }
            ++step_;
            ++stats_.steps;
            stats_.newton_iterations += rep.iterations;
            stats_.newton_iterations_max = std::max(stats_.newton_iterations_max, rep.iterations);
            update_euler();
            if (after_step()) return step_ == n;
        }
        return true;
    }

    [[nodiscard]] run_state<dynamic> save() const override {
        run_state<dynamic> out;
        out.x = {vector_of(rows_of(x_.R)), x_.pi};
        out.carry_q = vector_of(rows_of(s_.carry_R()));
        out.carry_p = s_.carry_pi();
        out.step = step_;
        out.stats = stats_;
        return out;
    }
    void restore(const run_state<dynamic>& saved) override {
        if (saved.x.q.size() != 9 || saved.carry_q.size() != 9 || saved.x.p.size() != 3 ||
            saved.carry_p.size() != 3)
            throw std::invalid_argument("a rigid body's saved state has R and its low part (9 "
                                        "values each) and Pi and its low part (3 each)");
        x_.R = matrix_of(saved.x.q);
        x_.pi = saved.x.p;
        s_.restore(x_, matrix_of(saved.carry_q), saved.carry_p);
        step_ = saved.step;
        stats_ = saved.stats;
        update_euler();
    }

    [[nodiscard]] bool has_tangent_map() const override { return false; }
    void tangent_map(Eigen::MatrixXd&) override {
        throw std::logic_error("the rigid bodies' Lie group integrator has no tangent map (no "
                               "Lyapunov exponent or MEGNO)");
    }
    [[nodiscard]] member_result run_member(
        const member_plan& plan,
        const std::function<double(double, std::span<const double>, std::span<const double>)>&
            event) override {
        rigid_simulation m = *this; // a copy steps, so that this run is left as it was
        const double h = s_.step_size(), t0 = time();
        auto g = [&](double t) { return event ? event(t, m.q(), m.p()) : 1.0; };
        member_result r;
        member_watch watch(m.watched_energy(), g(t0));
        long long k = 0;
        for (; k < plan.steps; ++k) {
            if (plan.stopped()) {
                r.status = member_result::outcome::stopped;
                break;
            }
            const newton_report rep = m.s_.step(m.x_);
            if (!rep.converged || !m.x_.R.allFinite() || !m.x_.pi.allFinite()) {
                member_watch::fail(r, rep);
                break;
            }
            m.update_euler();
            const double t = t0 + static_cast<double>(k + 1) * h;
            if (watch.after_step(r, t, h, m.watched_energy(), g(t))) {
                ++k;
                break;
            }
        }
        r.steps = k;
        r.time = t0 + static_cast<double>(k) * h;
        r.q.assign(m.euler_.begin(), m.euler_.end());
        r.p.assign(m.x_.pi.data(), m.x_.pi.data() + 3);
        return r;
    }
    [[nodiscard]] bool has_dense_output() const override { return false; }
    [[nodiscard]] section_result
    section(const section_plane&, long long, long long, const std::atomic<bool>*,
            const std::function<void(const section_result&)>&) override {
        throw std::logic_error("the rigid bodies' Lie group integrator has no dense output for "
                               "sections");
    }

  private:
    void update_euler() { euler_ = so3::euler_angles(x_.R); }

    rigid_setup r_;
    lie::lgvi s_;
    lie::body_state x_;
    std::array<double, 3> euler_{};
    std::size_t step_ = 0;
    run_summary stats_;
    std::vector<std::string> names_;
};

} // namespace

std::unique_ptr<simulation> simulate_rigid(const rigid_setup& r, const step_options& o) {
    refuse_non_newton(o, "the rigid bodies' Lie group integrator solves each step by Newton");
    refuse_non_taylor(o, "the rigid bodies' Lie group integrator starts each step from its own "
                         "prediction");
    return std::make_unique<rigid_simulation>(r, o);
}

own_integrator lgvi_integrator(int order) {
    return {"lgvi-" + std::to_string(order), order, lie::lgvi::step_limit(order)};
}

} // namespace varsym::models::detail
