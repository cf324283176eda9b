// apps/varsym/commands/cmd_ensemble.cpp: `varsym ensemble`, one model run from many initial states
// or parameter sets (a grid or a CSV file), on every core and, built with MPI, across processes:
// one CSV row per member in member order, resumable after a kill, and a heat map.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <unistd.h>

#include "commands/commands.hpp"
#include "ensemble/ensemble.hpp"
#include "ensemble/ensemble_journal.hpp"
#include "ensemble/ensemble_members.hpp"
#include "ensemble/ensemble_processes.hpp"
#include "ensemble/ensemble_writer.hpp"
#include "models/models.hpp"
#include "options/shared_options.hpp"
#include "output/files.hpp"
#include "output/plot.hpp"
#include "output/progress.hpp"
#include "output/signals.hpp"

namespace varsym::cli {

namespace {

struct ensemble_options {
    member_run_options run;
    std::string event;
    bool no_indicators = false;
    unsigned threads = 0;
    std::string output;
    std::vector<std::string> plot;
    std::string plot_value = "mean_megno";
};

/// The row of member m: its number, its values along the member keys, and what its run found.
std::string member_row(std::size_t m, const std::vector<double>& keys, const member_result& r,
                       bool invalid, int d) {
    std::string row = std::to_string(m);
    for (double v : keys) {
        row += ',';
        append_number(row, v);
    }
    using o = member_result::outcome;
    row += invalid                 ? ",invalid"
           : r.status == o::failed ? ",failed"
           : r.status == o::event  ? ",event"
                                   : ",completed";
    row += ',' + std::to_string(r.steps);
    const double nan = std::nan("");
    std::vector<double> values{invalid ? nan : r.time};
    for (int i = 0; i < d; ++i)
        values.push_back(invalid ? nan : r.q[static_cast<std::size_t>(i)]);
    for (int i = 0; i < d; ++i)
        values.push_back(invalid ? nan : r.p[static_cast<std::size_t>(i)]);
    for (double v : {invalid ? nan : r.max_energy_error, r.lyapunov, r.mean_megno, r.event_time})
        values.push_back(v);
    for (double v : values) {
        row += ',';
        append_number(row, v);
    }
    std::string cause = r.cause;
    for (char& c : cause)
        if (c == ',' || c == '\n' || c == '\r' || c == '"') c = ';';
    return row + ',' + cause + '\n';
}

std::string header_of(const member_set& set, int d) {
    std::string h = "member";
    for (const auto& k : set.keys)
        h += ',' + k;
    h += ",status,steps,t," + state_columns_of(d) +
         ",max_energy_error,lyapunov,mean_megno,event_time,cause\n";
    return h;
}

void run_members(const ensemble_options& o, const ensemble_model& model, const member_set& set,
                 const ensemble_setup& setup, const process_group& group);

void run_ensemble(const ensemble_options& o) {
    ensemble_model model = find_ensemble_model(o.run);
    const member_set set = make_member_set(o.run.members, model);
    ensemble_setup setup = make_setup(o.run, model, set.size);
    setup.plan.indicators = !o.no_indicators;
    // A contact step has no tangent map (its impulses switch on and off): the indicators are
    // refused for the whole ensemble, before any member runs.
    bool contact = std::find(set.keys.begin(), set.keys.end(), "contact") != set.keys.end();
    for (const std::string& s : o.run.members.set)
        if (s.rfind("contact=", 0) == 0) contact = contact || std::atof(s.c_str() + 8) != 0.0;
    if (contact && !o.no_indicators)
        throw usage_error("with contact a step has no tangent map for lyapunov and mean_megno: "
                          "give --no-indicators");
    // Ctrl-C: the members in flight stop after their current step (member_plan::stop), are
    // not written, and run again on resume.
    setup.plan.stop = &stop_flag();
    if (!o.event.empty()) setup.event = compile_event(o.event, model.dim);
    if (o.output.empty() || o.output == "-")
        throw usage_error("--output FILE is required: the ensemble's rows are kept in "
                          "FILE.journal while it runs, so that a stopped ensemble resumes");
    file_roles roles;
    roles.add("--output", o.output);
    roles.add("journal", o.output + ".journal");
    add_member_inputs(roles, o.run);
    if (!o.plot.empty()) {
        check_pictures(o.plot);
        check_heat_map(set, o.plot_value);
        add_figure_files(roles, {".grid.csv"}, o.plot);
    }
    roles.check();
    if (kind_of(o.output) != file_kind::absent && kind_of(o.output) != file_kind::regular)
        throw usage_error("--output must be a regular file (it is written at the end)");

    const process_group group;
    try {
        run_members(o, model, set, setup, group);
    } catch (const std::exception& e) {
        // One rank's failure ends every rank (the others would wait at a barrier forever),
        // with the code a single process would exit with: 2, 128 + the signal (130, 143), or
        // 1. (Open MPI's mpirun, itself signalled, exits 1 whatever its ranks give.)
        if (group.size() > 1) {
            const auto* stop = dynamic_cast<const interrupted*>(&e);
            std::fprintf(stderr, "varsym: %s(MPI rank %d) %s\n",
                         stop ? "" : "error: ", group.rank(), e.what());
            group.abort(dynamic_cast<const usage_error*>(&e) != nullptr ? exit_usage
                        : stop != nullptr                               ? 128 + stop->signal
                                                                        : exit_failure);
        }
        throw;
    }
}

void run_members(const ensemble_options& o, const ensemble_model& model, const member_set& set,
                 const ensemble_setup& setup, const process_group& group) {
    const int d = model.dim;
    const std::string header = header_of(set, d);
    const std::size_t fields =
        static_cast<std::size_t>(std::count(header.begin(), header.end(), ',')) + 1;
    // Everything a member's row depends on, numbers to 17 digits and the event in full, so
    // that a journal is continued only by the very same ensemble.
    std::string identity = "model=" + model.identity + " scheme=" + setup.spec.label() +
                           " steps=" + std::to_string(setup.plan.steps) + " h=";
    append_number(identity, setup.h);
    identity += std::string(" indicators=") + (setup.plan.indicators ? "on" : "off") + " event=[";
    for (const char c : o.event)
        identity += c == '\n' || c == '\r' ? ' ' : c;
    identity += "] " + set.identity;
    ensemble_journal journal(o.output, identity, set.size, fields);
    // OUTPUT.journal's lock, taken by the plain process or rank 0 before anything is read, is
    // the ensemble's: no other ensemble of this output, plain or MPI, runs meanwhile.
    if (group.rank() == 0) journal.lock(".journal");
    group.barrier();
    if (group.rank() != 0) journal.lock(".journal." + std::to_string(group.rank()));
    journal.read();
    // A FILE.part left by this ensemble's final write (killed then) is redone; any other
    // is refused now, before the work.
    if (group.rank() == 0) claim_partial(o.output, journal.found());
    if (journal.rejected() > 0 && group.rank() == 0)
        std::fprintf(stderr,
                     "varsym ensemble: %zu damaged journal rows ignored (their members "
                     "are computed again)\n",
                     journal.rejected());
    group.barrier(); // every rank read the journals before any rank writes its own
    journal.start();

    // This process's members, m ≡ rank (mod size): its k-th is rank + k·size; those found in a
    // journal are skipped as they come (no list of members is made).
    const auto rank = static_cast<std::size_t>(group.rank());
    const auto ranks = static_cast<std::size_t>(group.size());
    const std::size_t mine = set.size > rank ? (set.size - rank + ranks - 1) / ranks : 0;
    if (journal.done_count() > 0 && rank == 0)
        std::fprintf(stderr, "varsym ensemble: resuming, %zu of %zu members already done\n",
                     journal.done_count(), set.size);

    // At most 4096 rows wait behind a slow member (then they start a new run of the journal).
    ordered_writer writer([&journal](const std::string& rows) { journal.append(rows); }, 4096);
    std::atomic<std::size_t> done{journal.done_count()};
    std::mutex progress_mutex;
    progress_line progress("varsym ensemble", "members", set.size, journal.done_count());
    set_signal_polling(true, "the members in flight finish their current step");
    try {
        const unsigned threads = o.threads > 0 ? o.threads : group.default_threads();
        for_each_member(mine, threads, [&](std::size_t k) {
            const std::size_t m = rank + k * ranks;
            if (journal.done(m)) return writer.done(k, {});
            if (const int sig = pending_signal(); sig != 0)
                throw interrupted(sig, "stopped by signal " + std::to_string(sig) +
                                           "; the members done are in " + o.output +
                                           ".journal*: run the same command again to continue");
            std::vector<double> keys;
            set.values(m, keys);
            member_result r;
            bool invalid = false;
            try {
                r = model.run(set.input(keys), setup);
            } catch (const std::exception& e) {
                invalid = true;
                r.cause = e.what();
            }
            if (r.status == member_result::outcome::stopped) {
                const int sig = pending_signal() != 0 ? pending_signal() : SIGINT;
                throw interrupted(sig, "stopped by signal " + std::to_string(sig) +
                                           "; the members done are in " + o.output +
                                           ".journal*: run the same command again to continue");
            }
            writer.done(k, member_row(m, keys, r, invalid, d));
            const std::size_t now = ++done;
            const std::lock_guard lock(progress_mutex);
            progress.update(now * ranks);
        });
    } catch (...) {
        writer.flush_all();
        set_signal_polling(false);
        throw;
    }
    writer.flush_all();
    set_signal_polling(false);
    progress.update(set.size, true);
    group.barrier();
    if (rank != 0) return;
    // The output streamed from the journals, in member order; the summary and the heat map's
    // data taken on the way.
    row_digest digest(set, header, o.plot.empty() ? "" : o.plot_value);
    output_file out(o.output);
    out.write(header);
    std::string chunk;
    journal.merge([&](std::string_view row) {
        digest.add(row);
        chunk.append(row).push_back('\n');
        if (chunk.size() > (std::size_t{1} << 16)) {
            out.write(chunk);
            chunk.clear();
        }
    });
    out.write(chunk);
    file_roles others;
    others.add("--output", o.output);
    if (!o.plot.empty()) render_figure(digest.heat_map(model), o.plot, others);
    out.commit();
    journal.remove_all();
    digest.print_summary(set.size);
}

} // namespace

void add_ensemble_command(CLI::App& app, action& todo) {
    auto o = std::make_shared<ensemble_options>();
    auto* cmd = app.add_subcommand(
        "ensemble", "Run a model from many initial states or parameters: maps of MEGNO, Lyapunov "
                    "exponents, events");
    cmd->footer(ensemble_help());
    add_member_run_options(*cmd, o->run, ensemble_model_names());
    cmd->add_option("--event", o->event,
                    "Stop a member where this expression in q1.., p1.., t changes sign and "
                    "report the time, e.g. 'q2^2 - pi^2' (a flip), 'q1^2 + q2^2 - 1' (an escape)");
    cmd->add_flag("--no-indicators", o->no_indicators,
                  "Skip the tangent map (lyapunov, mean_megno: nan), about halving the cost");
    cmd->add_option("--threads", o->threads,
                    "Threads per process, at most 4096 (default 0: every CPU this process may use, "
                    "shared among the MPI ranks on one machine)")
        ->transform(non_negative_integer)
        ->check(CLI::Range(0, 4096));
    cmd->add_option("--output,-o", o->output, "CSV file, one row per member in member order")
        ->required();
    cmd->add_option("--plot", o->plot,
                    "Heat map over a 2-D grid, .png or .svg (data and gnuplot script kept "
                    "beside it); repeat for both formats");
    cmd->add_option("--plot-value", o->plot_value,
                    "Column drawn by --plot: mean_megno, lyapunov, max_energy_error, "
                    "event_time, t, steps, or a q_/p_ column")
        ->capture_default_str();
    cmd->callback([o, &todo] { todo = [o] { run_ensemble(*o); }; });
}

} // namespace varsym::cli
