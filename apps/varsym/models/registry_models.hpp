// apps/varsym/models/registry_models.hpp: the tool's front end to the models layer: the options of
// every model's parameters, and `varsym run`, `ensemble` and `section` models generated from the
// registry (registry_models.cpp), with the run loop that streams a simulation (simulation_run.cpp).
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "ensemble/ensemble.hpp"
#include "models/models.hpp"
#include "varsym/models/model.hpp"

namespace varsym::cli {

/// The options of the registry models' parameters on one command: one option per name, shared
/// by the models that have it (and with a mechanism's option of the same name).
class parameter_options {
  public:
    /// Adds the options not yet on `cmd` and takes over those already there: those of every
    /// model, or of the models `which` accepts (optimize: those with inputs).
    void add(CLI::App& cmd, const std::function<bool(const models::model&)>& which = {});
    /// Model m's parameter values: its defaults, replaced by the options given.
    [[nodiscard]] std::vector<double> values(const models::model& m) const;
    /// Model m's lists: the values of each list option given, else empty (its default).
    [[nodiscard]] models::lists lists(const models::model& m) const;
    /// Whether the option --NAME was given.
    [[nodiscard]] bool given(const std::string& name) const;
    /// The NAMEs of the options --NAME given.
    [[nodiscard]] std::vector<std::string> given_names() const;

  private:
    std::map<std::string, CLI::Option*> options_;
};

/// The description `varsym models` and the ensemble's help show: the model's text, then its
/// parameters (as options, or as ensemble keys), initial state and default run length.
std::string describe(const models::model& m, bool ensemble);

/// Throws usage_error where --scheme or --degree was given (`given`) to a model with its own
/// integrator (the rigid bodies): the model's note, then `how`, how this command chooses the
/// integrator's order (may be empty).
void refuse_scheme(const models::model& m, bool given, const std::string& how);

/// `varsym run --model NAME` for a model of the registry.
model make_registry_model(const models::model& m, std::shared_ptr<parameter_options> po);
/// Runs model m at these parameter values and lists: `varsym run --model NAME` for a model of
/// the registry (or `lagrangian`). Data the model refuses is a usage_error.
void run_model(const models::model& m, const run_setup& setup, const std::vector<double>& values,
               const models::lists& lists);

/// A model of the registry, which lives as long as the program, as a shared pointer that owns
/// nothing.
inline std::shared_ptr<const models::model> unowned(const models::model& m) {
    return {std::shared_ptr<void>(), &m};
}

/// `varsym ensemble` and `varsym section` for a model of the registry (or `lagrangian`).
ensemble_model make_registry_ensemble(std::shared_ptr<const models::model> m);

/// Streams the rows of a simulation for plan.steps steps: step,t, q, p, then the model's
/// columns; checkpoints, resumes, watches the energy, stops on signals, and turns a failed step
/// into exit code 3, as every run does (run_log).
void stream_simulation(const run_setup& s, const run_plan& plan, models::simulation& sim);

} // namespace varsym::cli
