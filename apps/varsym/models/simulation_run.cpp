// apps/varsym/models/simulation_run.cpp: the run loop of `varsym run` for a simulation of the models
// layer: streams its rows, checkpoints and resumes it, watches its energy and stops on signals
// (run_log), turning a failed step into exit code 3 with the rows kept.
#include <numbers>

#include "model_run.hpp"
#include "registry_models.hpp"

namespace varsym::cli {

void stream_simulation(const run_setup& s, const run_plan& plan, models::simulation& sim) {
    const int d = sim.dim();
    std::string header = "step,t," + state_columns(d);
    for (const std::string& c : sim.columns())
        header += "," + c;
    run_log log(s, plan, d, header + "\n");
    std::vector<double> extra(sim.columns().size());
    std::string line;
    /// Writes the row of step j (the simulation's current state) if it is one to write.
    auto row = [&](std::size_t j) {
        if (!log.row_due(j)) return false;
        line = std::to_string(j);
        line += ',';
        append_number(line, sim.time());
        for (const auto values : {sim.q(), sim.p()})
            for (double v : values) {
                line += ',';
                append_number(line, v);
            }
        sim.values(extra);
        for (double v : extra) {
            line += ',';
            append_number(line, v);
        }
        line += '\n';
        log.write(line);
        return true;
    };
    // The frequency the step must resolve: the highest at the start, and the orbit's.
    double omega0 = sim.highest_frequency();
    if (!(omega0 >= 0.0)) omega0 = 0.0;
    if (plan.period > 0.0) omega0 = std::max(omega0, 2.0 * std::numbers::pi / plan.period);
    // No energy watch where the energy is not conserved (an L that depends on time).
    const double bound = !sim.conserves_energy()         ? 0.0
                         : s.max_energy_error >= 0.0 ? s.max_energy_error
                                                     : default_energy_bound(s.order(), plan.h, omega0);
    log.set_energy_reference(sim.watched_energy(), omega0, bound);
    if (const checkpoint* ck = log.resumed()) {
        auto as_vec = [](const std::vector<double>& v) {
            return vec<dynamic>(Eigen::Map<const vec<dynamic>>(v.data(), std::ssize(v)));
        };
        run_state<dynamic> r;
        r.x = {as_vec(ck->q), as_vec(ck->p)};
        r.carry_q = as_vec(ck->carry_q);
        r.carry_p = as_vec(ck->carry_p);
        r.history = ck->history;
        r.step = ck->step;
        r.stats.steps = ck->step;
        r.stats.newton_iterations = ck->newton_iterations;
        r.stats.newton_iterations_max = ck->newton_iterations_max;
        sim.restore(r);
    } else {
        row(0);
    }
    set_signal_polling(true);
    try {
        sim.advance(plan.steps, [&] {
            const std::size_t j = sim.step();
            log.after_step(
                j, sim.time(), row(j), [&] { return sim.watched_energy(); },
                [&] { return save_state(sim.save()); }, sim.stats());
            return false;
        });
    } catch (const step_failure& e) {
        set_signal_polling(false);
        log.fail(e, save_state(sim.save()), sim.stats(), sim.highest_frequency());
    }
    set_signal_polling(false);
    log.finish(save_state(sim.save()), sim.stats());
}

} // namespace varsym::cli
