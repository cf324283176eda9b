// apps/varsym/ensemble/ensemble_output.cpp: the help of `varsym ensemble`, its heat map and its
// summary.
#include <algorithm>
#include <cstdio>
#include <string_view>

#include "ensemble/ensemble_members.hpp"

namespace varsym::cli {

namespace {

bool numeric_column(const std::string& v) {
    return v == "mean_megno" || v == "lyapunov" || v == "max_energy_error" || v == "event_time" ||
           v == "t" || v == "steps" || v.starts_with("q_") || v.starts_with("p_");
}

} // namespace

std::size_t column_of(const std::string& header, const std::string& name) {
    std::size_t col = 0, at = 0;
    for (;;) {
        const std::size_t end = header.find_first_of(",\n", at);
        if (header.compare(at, end - at, name) == 0) return col;
        if (end == std::string::npos || header[end] == '\n') return std::string::npos;
        at = end + 1;
        ++col;
    }
}

std::string ensemble_help() {
    std::string h =
        "Members: --grid KEY=FIRST:LAST:COUNT (one per axis; members numbered with the last\n"
        "axis fastest) or --members FILE.csv (a header of keys, then one row per member). A\n"
        "key is an initial coordinate q0_I, an initial momentum p0_I (I from 1), or a model\n"
        "parameter; --q0, --p0 and --set NAME=VALUE give every member's other values.\n\n"
        "Each member runs --steps steps of --time / --steps with --scheme, carrying the step's\n"
        "tangent map (unless --no-indicators) for the maximal Lyapunov exponent lambda and the\n"
        "mean MEGNO <Y> (about 2 on a torus with shear, 0 for isochronous motion, growing like\n"
        "lambda t / 2 when chaotic; docs/ensembles.md). A member stops at its --event.\n\n"
        "Output (--output, CSV, one row per member in member order): member, the keys, status\n"
        "(completed, event, failed: Newton did not converge, invalid: the model refused the\n"
        "data; with the reason in `cause`), steps, t, q_1.., p_1.. (the last state),\n"
        "max_energy_error (max |E - E0|/|E0|; E - W under a force or an L(t)), lyapunov\n"
        "[1/time], mean_megno, event_time.\n"
        "The file is the same for any --threads and any number of MPI ranks. While running, rows\n"
        "go to OUTPUT.journal (OUTPUT.journal.R for MPI rank R > 0), each with its CRC-32: after\n"
        "a kill, the same command again skips the members done. OUTPUT.journal is locked while\n"
        "the ensemble runs. A progress line is shown when stderr is a terminal.\n"
        "Exit 0 when every member has its row (failed members included), 2 on bad input,\n"
        "130/143 when stopped by SIGINT/SIGTERM (the journal kept).\n\n"
        "Models:\n";
    for (const auto& m : ensemble_models())
        h += m.name + "\n" + m.help + "\n";
    h += "lagrangian\n  your own L: --lagrangian EXPR with --coordinates, --parameters and --force "
         "as\n"
         "  for 'varsym run'. Keys: q0_I, p0_I and the names of --parameters. Default member\n"
         "  run: 10 s in 1000 steps.\n";
    h += "\nExamples:\n"
         "  varsym ensemble --model henon-heiles --set energy=0.125 --grid q0_2=-0.45:0.65:200 \\\n"
         "      --grid p0_2=-0.5:0.5:200 --output hh.csv --plot hh.png   # a MEGNO map\n"
         "  varsym ensemble --model double-pendulum --grid q0_1=-3:3:300 --grid q0_2=-3:3:300 \\\n"
         "      --event 'q2^2 - pi^2' --no-indicators --output flip.csv --plot flip.png \\\n"
         "      --plot-value event_time                                  # flip-time map\n"
         "  mpirun -np 4 varsym ensemble ...   (a build with MPI; docs/ensembles.md)\n";
    return h;
}

void check_heat_map(const member_set& set, const std::string& value) {
    std::size_t wide = 0;
    for (const auto& a : set.axes)
        wide += a.count > 1 ? 1 : 0;
    if (set.axes.size() != 2 || wide != 2)
        throw usage_error("--plot draws a heat map over a grid of two --grid axes of more than "
                          "one point each");
    if (!numeric_column(value))
        throw usage_error("--plot-value " + shown(value) +
                          " is not a numeric column (mean_megno, lyapunov, max_energy_error, "
                          "event_time, t, steps, q_I, p_I)");
}

row_digest::row_digest(const member_set& set, const std::string& header, std::string value)
    : set_(set), value_(std::move(value)) {
    if (value_.empty()) return;
    column_ = column_of(header, value_);
    if (column_ == std::string::npos)
        throw usage_error("--plot-value " + shown(value_) + " is not a column of this ensemble");
    // x: the second (fastest) axis, y: the first; a blank line after each row of the grid.
    data_ = "# " + set.keys[1] + "," + set.keys[0] + "," + value_ + "\n";
}

void row_digest::add(std::string_view line) {
    static constexpr std::string_view names[4] = {",completed,", ",event,", ",failed,",
                                                  ",invalid,"};
    for (int k = 0; k < 4; ++k)
        if (line.find(names[k]) != std::string_view::npos) ++counts_[k];
    ++rows_;
    if (value_.empty()) return;
    std::size_t c = 0, f = 0;
    std::string_view fields[3];
    for (std::size_t i = 0; i <= line.size(); ++i)
        if (i == line.size() || line[i] == ',') {
            const std::string_view field = line.substr(f, i - f);
            if (c == 1) fields[1] = field;
            if (c == 2) fields[0] = field;
            if (c == column_) fields[2] = field;
            ++c;
            f = i + 1;
        }
    data_.append(fields[0]).append(",").append(fields[1]).append(",").append(fields[2]);
    data_ += '\n';
    if (rows_ % set_.axes[1].count == 0) data_ += '\n';
}

figure row_digest::heat_map(const ensemble_model& model) const {
    const bool megno = value_ == "mean_megno";
    std::string script = script_preamble(820, 700) + "set xlabel '" + set_.keys[1] +
                         "' noenhanced\nset ylabel '" + set_.keys[0] +
                         "' noenhanced\nset title \"" + model.name + ": " + value_ +
                         (megno ? " (clipped to [0, 8]; 2: regular, > 2: chaotic)" : "") +
                         "\" font ',14' noenhanced\n"
                         "set autoscale xfix\nset autoscale yfix\nset grid front\n"
                         "set palette defined (0 '#000004', 1 '#3b0f70', 2 '#8c2981', "
                         "3 '#de4968', 4 '#fe9f6d', 5 '#fcfdbf')\n";
    if (megno) script += "set cbrange [0:8]\n";
    script += "set cblabel '" + value_ +
              "' noenhanced\n"
              "plot stem.'.grid.csv' using 1:2:(" +
              std::string(megno ? "$3 > 8 ? 8 : $3" : "$3") + ") with image notitle\n";
    return {{{".grid.csv", data_}}, script};
}

void row_digest::print_summary(std::size_t members) const {
    std::fprintf(stderr,
                 "varsym ensemble: %zu members: %zu completed, %zu met the event, %zu failed, "
                 "%zu invalid\n",
                 members, counts_[0], counts_[1], counts_[2], counts_[3]);
}

} // namespace varsym::cli
