// apps/varsym/models/simulation_run.cpp: the run loop of `varsym run` for a simulation of the
// models layer (every model, the rigid bodies too): streams its rows, checkpoints and resumes it,
// watches its energy and stops on signals (run_log), turning a failed step into exit code 3 with
// the rows kept.
#include <atomic>
#include <numbers>

#include "models/model_run.hpp"
#include "models/registry_models.hpp"

namespace varsym::cli {

void stream_simulation(const run_setup& s, const run_plan& plan, models::simulation& sim) {
    std::string header = "step,t";
    const std::vector<std::string> state = sim.state_columns();
    for (const auto* names : {&state, &sim.columns()})
        for (const std::string& c : *names)
            header += "," + c;
    // A checkpoint keeps the state as the simulation saves it (a rigid body: R and Π, 9 and 3).
    const run_state<dynamic> start = sim.save();
    run_log log(s, plan, static_cast<int>(start.x.q.size()), header + "\n",
                static_cast<int>(start.x.p.size()));
    std::vector<double> extra(state.size() + sim.columns().size());
    std::string line;
    /// Writes the row of step j (the simulation's current state) if it is one to write.
    auto row = [&](std::size_t j) {
        if (!log.row_due(j)) return false;
        line = std::to_string(j);
        line += ',';
        append_number(line, sim.time());
        models::evaluated(sim, [&] {
            sim.state_values(extra);
            sim.values(std::span<double>(extra).subspan(state.size()));
        });
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
    /// Keeps the current state as a frame of the animation, if one is due (--animate).
    auto frame = [&](bool last) {
        frame_recorder* f = s.frames.get();
        if (f == nullptr || !(last ? f->t.back() < sim.time() : f->due(sim.time()))) return;
        if (f->coordinates) {
            f->add(sim.time(), sim.q());
            return;
        }
        models::evaluated(sim,
                          [&] { sim.state_values(std::span<double>(extra).first(state.size())); });
        f->add(sim.time(), extra);
        const std::span<const double> kicks = sim.contact_impulses();
        std::vector<double>& forces = f->forces.emplace_back(kicks.begin(), kicks.end());
        for (std::size_t i = 0; i < forces.size(); i += 6)
            for (std::size_t j = 3; j < 6; ++j)
                forces[i + j] /= sim.step_size(); // the impulse over the step: its mean force
    };
    if (const checkpoint* ck = log.resumed()) {
        sim.restore(ck->state());
    } else {
        row(0);
    }
    frame(false);
    set_signal_polling(true);
    const std::atomic<bool>& stop = stop_flag();
    const bool animated = s.frames != nullptr;
    std::size_t j = sim.step(); // counted here: sim.step() is a virtual call per step
    try {
        sim.advance(plan.steps, [&] {
            ++j;
            if (!animated && log.idle(j) && !stop.load(std::memory_order_relaxed)) return false;
            frame(false); // before a signal or the energy watch can stop the run
            log.after_step(
                j, sim.time(), row(j),
                [&] { return models::evaluated(sim, [&] { return sim.watched_energy(); }); },
                [&] { return save_state(sim.save()); }, sim.stats());
            return false;
        });
    } catch (const step_failure& e) {
        set_signal_polling(false);
        frame(true); // the last good state
        log.fail(e, save_state(sim.save()), sim.stats(), sim.highest_frequency());
    }
    set_signal_polling(false);
    frame(true);
    log.finish(save_state(sim.save()), sim.stats());
}

} // namespace varsym::cli
