// apps/varsym/models/simulation_run.cpp: the run loop of `varsym run` for a simulation of the
// models layer: streams its rows, checkpoints and resumes it, watches its energy and stops on
// signals (run_log), turning a failed step into exit code 3 with the rows kept.
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
    const double omega0 = resolved_frequency(sim.highest_frequency(), plan.period);
    log.set_energy_reference(sim.watched_energy(), omega0,
                             energy_watch_bound(s, sim.conserves_energy(), plan.h, omega0));
    if (const checkpoint* ck = log.resumed()) {
        sim.restore(ck->state());
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
