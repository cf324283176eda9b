// apps/varsym/ensemble/ensemble_members.hpp: what `varsym ensemble` runs: the models, the members
// (a grid of --grid axes or the rows of a --members CSV file, over initial coordinates q0_i,
// momenta p0_i and model parameters), the event expression, and the heat map of a result.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "ensemble/ensemble.hpp"
#include "models/models.hpp"
#include "options/cli_common.hpp"
#include "options/expression_options.hpp"
#include "options/shared_options.hpp"
#include "output/plot.hpp"

namespace varsym::cli {

class file_roles;

/// The options that say which members run.
struct member_options {
    std::vector<std::string> grid; ///< KEY=FIRST:LAST:COUNT, one per axis
    std::string members_file;      ///< CSV: a header of keys, one row per member
    std::vector<double> q0, p0;    ///< the base initial state (default: the model's)
    std::vector<std::string> set;  ///< NAME=VALUE: model parameters for every member
};
void add_member_options(CLI::App& cmd, member_options& o);

/// What `varsym ensemble` and `varsym section` share: the model, the scheme, each member's run
/// (0: the model's default) and the members.
struct member_run_options {
    std::string model;
    expression_spec expression; ///< --lagrangian etc., for --model lagrangian
    urdf_spec urdf;             ///< --urdf FILE, --torques, for --model urdf
    scheme_options scheme;
    double time = 0.0;
    long long steps = 0;
    member_options members;
};
/// --model (required, unless --lagrangian or --urdf implies it; `models` names the choices),
/// --scheme, --degree, --time, --steps and the member options.
void add_member_run_options(CLI::App& cmd, member_run_options& o, const std::string& models);
/// The files the members are read from (--urdf, --members), as roles no output may take.
void add_member_inputs(file_roles& roles, const member_run_options& o);

/// The members: their keys (grid axes or CSV columns), count, values and data.
struct member_set {
    std::vector<std::string> keys;
    std::size_t size = 0;
    std::vector<grid_axis> axes; ///< a grid's axes (empty for a CSV file)
    std::vector<double> table;   ///< a CSV file's values, size × keys
    std::string identity;        ///< one line naming the members (for the journal)
    member_input base;           ///< the initial state and parameters before the keys apply
    /// Where each key goes: 0 q0, 1 p0, 2 a parameter; and its index there.
    std::vector<std::pair<int, std::size_t>> targets;

    void values(std::size_t m, std::vector<double>& out) const;
    [[nodiscard]] member_input input(const std::vector<double>& keys) const;
};
/// The members of `o` for `model`: the base input (--set parameters; q0 and p0 from --q0/--p0,
/// NaN where not given: each member's default start at its own parameters) and the keys of a
/// grid or a --members file. Where parameters set the model's d (the chain's n), sets model.dim
/// from the --set values, and refuses those parameters as member keys.
member_set make_member_set(const member_options& o, ensemble_model& model);

/// The setup every member shares: the scheme, the steps and h = time/steps (the model's
/// defaults where not given). Refuses members × steps beyond max_run_steps (usage_error).
ensemble_setup make_setup(const member_run_options& o, const ensemble_model& model,
                          std::size_t members);

std::vector<ensemble_model> ensemble_models();
/// Where key `k` goes for `model`: {0, i} for q0_{i+1}, {1, i} for p0_{i+1} (1 ≤ i + 1 ≤ d, not
/// for a model whose start follows from its parameters), {2, j} for parameter j. Throws
/// usage_error naming the model's keys (and the one spelling of q0_01).
std::pair<int, std::size_t> target_of(const std::string& k, const ensemble_model& model);

/// The model of --model (`lagrangian`: made from --lagrangian and its options).
ensemble_model find_ensemble_model(const member_run_options& o);
std::string ensemble_model_names();
std::string ensemble_help();

/// The event's expression compiled over q1 … qd, p1 … pd, t (throws usage_error).
expr::tape compile_event(const std::string& text, int d);

/// The index of column `name` in a CSV header (its first line), or std::string::npos.
std::size_t column_of(const std::string& header, const std::string& name);

/// "q_1,…,q_d,p_1,…,p_d" (also for d = 1, unlike state_columns).
std::string state_columns_of(int d);

/// Refuses --plot unless the members are a grid with two axes of more than one point and the
/// value is a numeric column.
void check_heat_map(const member_set& set, const std::string& value);
/// What the output's rows say as they are written: the count of each status, and the heat
/// map's data (three fields a member) where one is drawn.
class row_digest {
  public:
    /// `value`: the column the heat map draws (usage_error if it is not one), or "" for none.
    row_digest(const member_set& set, const std::string& header, std::string value);
    /// One row, without its '\n'.
    void add(std::string_view row);
    /// The heat map of `value` over the grid.
    [[nodiscard]] figure heat_map(const ensemble_model& model) const;
    /// One line on standard error: how many members completed, met the event, failed, were
    /// invalid.
    void print_summary(std::size_t members) const;

  private:
    const member_set& set_;
    std::string value_, data_;
    std::size_t column_ = 0, rows_ = 0;
    std::size_t counts_[4] = {};
};

} // namespace varsym::cli
