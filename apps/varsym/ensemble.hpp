// apps/varsym/ensemble.hpp: the models `varsym ensemble` runs, member by member: each builds its
// system and stepper from one member's initial state and parameters and runs it through
// varsym::run_member (varsym/run/ensemble.hpp).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "varsym/expression/tape.hpp"
#include "varsym/run/ensemble.hpp"
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

/// One member's data: the full initial state and the model's parameters, in the order of
/// ensemble_model::parameters.
struct member_input {
    std::vector<double> q0, p0, parameters;
};

/// A model as `varsym ensemble` knows it.
struct ensemble_model {
    std::string name;
    int dim = 0;
    std::vector<double> q0, p0;                             ///< the default initial state
    std::vector<std::pair<std::string, double>> parameters; ///< names and defaults (NaN: unset)
    std::string help;                                       ///< for --help: what they mean
    double time = 0.0;                                      ///< default run length
    long long steps = 0;                                    ///< default number of steps
    /// Runs one member; throws std::invalid_argument for data the model refuses (the member's
    /// row then says `invalid` and why).
    std::function<member_result(const member_input&, const ensemble_setup&)> run;
};

ensemble_model make_pendulum_ensemble();
ensemble_model make_henon_heiles_ensemble();
ensemble_model make_double_pendulum_ensemble();

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
