// apps/varsym/models/rigid_run.cpp: the run of a rigid-body model: the Lie group integrator's steps,
// the CSV rows and the checkpoints (R and its low-order part row by row, Π and its low part).
#include "rigid_run.hpp"

#include <cmath>
#include <numbers>
#include <optional>

#include "model_run.hpp"
#include "varsym/lie/lgvi.hpp"
#include "varsym/lie/symmetric_top.hpp"

namespace varsym::cli {

namespace {

std::vector<double> rows_of(const lie::mat3& m) {
    std::vector<double> v;
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k)
            v.push_back(m(i, k));
    return v;
}

lie::mat3 matrix_of(const std::vector<double>& v) {
    lie::mat3 m;
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k)
            m(i, k) = v[static_cast<std::size_t>(3 * i + k)];
    return m;
}

saved_state save(const lie::body_state& x, const lie::lgvi& stepper) {
    const auto list = [](const lie::vec3& v) { return std::vector<double>{v(0), v(1), v(2)}; };
    return {rows_of(x.R), list(x.pi), rows_of(stepper.carry_R()), list(stepper.carry_pi()), {}};
}

/// The angle of the rotation taking a to b [rad].
double angle_between(const lie::mat3& a, const lie::mat3& b) {
    const auto q = so3::quaternion(a.transpose() * b);
    return 2.0 * std::atan2(std::sqrt(q[1] * q[1] + q[2] * q[2] + q[3] * q[3]), q[0]);
}

} // namespace

void run_rigid_body(const run_setup& setup, const rigid_run& r, double default_time,
                    long long default_steps) {
    run_setup s = setup;
    s.method = "lgvi-" + std::to_string(r.order);
    s.method_order = r.order;
    s.method_limit = lie::lgvi::step_limit(r.order);
    const lie::rigid_body& b = r.body;
    if (!std::isfinite(b.energy(r.x0)))
        throw usage_error(r.name + ": the energy of the initial state is not a finite number "
                                   "(check --v0/--p0, --inertia, --com and --weight)");
    const bool gravity = b.has_gravity(), symmetric = b.symmetric_about_e3();
    // The closed forms, where they exist, give the period and the exact columns.
    std::optional<lie::free_symmetric_motion> free;
    std::optional<heavy_top::nutation> nutation;
    double period = 0.0;
    if (!gravity && symmetric) {
        free.emplace(b, r.x0);
        period = free->period();
    } else if (gravity && symmetric && b.weight() * b.com()(2) > 0.0) {
        try {
            nutation.emplace(lie::nutation_of(b, r.x0));
            period = nutation->period();
        } catch (const std::invalid_argument&) { // the axis reaches the vertical: no closed form
        }
    }
    const run_plan plan = plan_steps(s, r.name, period, 100, default_time, default_steps);
    std::string header = "step,t,q_w,q_x,q_y,q_z,Omega_1,Omega_2,Omega_3,energy";
    if (!gravity) header += ",L_x,L_y,L_z,Pi_norm";
    if (free) header += ",attitude_error";
    if (gravity) header += symmetric ? ",L_z,Pi_3,theta" : ",L_z,theta";
    if (nutation) header += ",theta_exact";
    header += ",orthogonality";
    if (r.matrix) header += ",R_11,R_12,R_13,R_21,R_22,R_23,R_31,R_32,R_33";
    run_log log(s, plan, 9, header + "\n", 3);

    lie::lgvi stepper(b, plan.h, r.order, s.newton);
    const std::size_t n = plan.steps;
    std::string line;
    auto row = [&](std::size_t j, double t, const lie::body_state& x) {
        if (!log.row_due(j)) return false;
        line = std::to_string(j);
        const auto q = so3::quaternion(x.R);
        const lie::vec3 omega = b.omega(x.pi), l = lie::rigid_body::spatial_momentum(x);
        append_values(line, {t, q[0], q[1], q[2], q[3], omega(0), omega(1), omega(2)});
        append_values(line, {b.energy(x)});
        if (!gravity) append_values(line, {l(0), l(1), l(2), x.pi.norm()});
        if (free) append_values(line, {angle_between(free->at(t).R, x.R)});
        if (gravity) append_values(line, {l(2)});
        if (gravity && symmetric) append_values(line, {x.pi(2)});
        if (gravity) append_values(line, {std::acos(std::clamp(x.R(2, 2), -1.0, 1.0))});
        if (nutation) append_values(line, {nutation->theta(t)});
        append_values(line, {so3::orthogonality_error(x.R)});
        if (r.matrix)
            for (double v : rows_of(x.R))
                append_values(line, {v});
        line += '\n';
        log.write(line);
        return true;
    };

    // The frequency the step must resolve: the start's turning rate or swing, or the orbit's.
    double omega0 = b.highest_frequency(r.x0);
    if (period > 0.0) omega0 = std::max(omega0, 2.0 * std::numbers::pi / period);
    log.set_energy_reference(b.energy(r.x0), omega0,
                             s.max_energy_error >= 0.0
                                 ? s.max_energy_error
                                 : default_energy_bound(r.order, plan.h, omega0));
    lie::body_state x = r.x0;
    std::size_t j0 = 0;
    run_summary stats;
    if (const checkpoint* ck = log.resumed()) {
        x.R = matrix_of(ck->q);
        x.pi = lie::vec3(ck->p[0], ck->p[1], ck->p[2]);
        stepper.restore(x, matrix_of(ck->carry_q),
                        lie::vec3(ck->carry_p[0], ck->carry_p[1], ck->carry_p[2]));
        j0 = ck->step;
        stats.steps = ck->step;
        stats.newton_iterations = ck->newton_iterations;
        stats.newton_iterations_max = ck->newton_iterations_max;
    } else {
        row(0, 0.0, x);
    }
    const double h = plan.h;
    set_signal_polling(true);
    for (std::size_t j = j0 + 1; j <= n; ++j) {
        const double t = static_cast<double>(j) * h;
        const newton_report rep = stepper.step(x);
        if (!rep.converged) {
            set_signal_polling(false);
            log.fail(step_failure(j, t - h, t, rep), save(x, stepper), stats,
                     b.highest_frequency(x));
        }
        ++stats.steps;
        stats.newton_iterations += rep.iterations;
        stats.newton_iterations_max = std::max(stats.newton_iterations_max, rep.iterations);
        log.after_step(
            j, t, row(j, t, x), [&] { return b.energy(x); }, [&] { return save(x, stepper); },
            stats);
    }
    set_signal_polling(false);
    log.finish(save(x, stepper), stats);
}

} // namespace varsym::cli
