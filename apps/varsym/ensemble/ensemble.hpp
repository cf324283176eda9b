// apps/varsym/ensemble/ensemble.hpp: the models `varsym ensemble` runs, member by member: each
// builds its system and stepper from one member's initial state and parameters and runs it through
// varsym::run_member (varsym/run/ensemble.hpp).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "options/cli_common.hpp"
#include "varsym/expression/tape.hpp"
#include "varsym/run/ensemble.hpp"
#include "varsym/run/section.hpp"
#include "varsym/schemes/scheme_kind.hpp"

namespace varsym::cli {

/// What every member of one ensemble shares.
struct ensemble_setup {
    scheme_spec spec;
    newton_options newton;
    double h = 0.0;
    member_plan plan;
    /// The event's expression in q_1 … q_d, p_1 … p_d, t (inputs in that order), if any.
    std::optional<expr::tape> event;
};

/// One member's data: the initial state and the model's parameters, in the order of
/// ensemble_model::parameters. A NaN in q0 or p0 was not given: the model's default start at the
/// member's parameters takes its place.
struct member_input {
    std::vector<double> q0, p0, parameters;
};

/// A model as `varsym ensemble` knows it.
struct ensemble_model {
    std::string name;
    /// What the journal's first line says of the model: its name, and for `lagrangian` its
    /// expressions (one line).
    std::string identity;
    int dim = 0;
    /// The coordinates' names where each is a plain name (a robot's joints, the cart-pole's x
    /// and theta): the keys q0_NAME and p0_NAME then stand for q0_I and p0_I. Else empty.
    std::vector<std::string> coordinates;
    std::vector<std::pair<std::string, double>> parameters; ///< names and defaults (NaN: unset)
    /// Throws std::invalid_argument naming the parameter where `value` is outside its range
    /// (what a parameter set for every member by --set must meet); null: no ranges.
    std::function<void(std::size_t parameter, double value)> check_parameter;
    std::string help;         ///< for --help: what they mean
    bool fixed_start = false; ///< the initial state follows from the parameters (no q0, p0)
    /// Where parameters set d (the chain's n): d from the parameters' values, and the names of
    /// those parameters, which --set gives for all members and no member key may vary.
    std::function<int(const std::vector<double>&)> dimension;
    std::vector<std::string> dimension_keys;
    double time = 0.0;   ///< default run length
    long long steps = 0; ///< default number of steps
    /// Runs one member; throws std::invalid_argument for data the model refuses (the member's
    /// row then says `invalid` and why).
    std::function<member_result(const member_input&, const ensemble_setup&)> run;
    /// The member's crossings of a plane (`varsym section`), at most `crossings`, handed to
    /// `emit` as they are found, a few thousand at a time: CSV rows "t,q..,p..\n", then the row
    /// "failed\n" if a step failed. Empty for a model whose steppers have no dense output.
    std::function<void(const member_input&, const ensemble_setup&, const section_plane&,
                       long long crossings, const std::function<void(std::string)>& emit)>
        section;
};

/// Runs one member of s from x with the setup's plan and event (a copy of the tape per call,
/// so that members run concurrently).
template <class S, class Energy>
member_result run_ensemble_member(S& s, const phase_state<S::dim>& x, const ensemble_setup& e,
                                  Energy&& energy) {
    std::optional<expr::tape> tape = e.event;
    std::vector<double> in(static_cast<std::size_t>(2 * x.q.size() + 1));
    auto event = [&](double t, const phase_state<S::dim>& y) {
        if (!tape) return 1.0;
        const auto d = static_cast<std::size_t>(y.q.size());
        for (std::size_t i = 0; i < d; ++i) {
            in[i] = y.q(static_cast<Eigen::Index>(i));
            in[d + i] = y.p(static_cast<Eigen::Index>(i));
        }
        in[2 * d] = t;
        tape->run(in);
        return tape->output(0);
    };
    return run_member(s, x, e.plan, energy, event);
}

} // namespace varsym::cli
