// apps/varsym/expression_run.hpp: Lagrangians given as expressions (`varsym run --lagrangian`),
// and the stepper of the general engine for them, compiled once here and used by the tool and
// by the Python package (python/src/module.cpp).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "varsym/integrate.hpp"
#include "varsym/schemes/scheme_kind.hpp"
#include "varsym/schemes/variational.hpp"
#include "varsym/systems/expression_force.hpp"
#include "varsym/systems/expression_lagrangian.hpp"

namespace varsym::cli {

/// "m=1,g=9.81" as parameters; throws usage_error naming the entry that is not NAME=NUMBER.
std::vector<expression_parameter> parse_parameters(const std::string& list);
/// "a, b,c" as its entries, spaces around each dropped; throws usage_error naming `option` on an
/// empty entry, with `example` of a good list.
std::vector<std::string> split_list(const std::string& list, const char* option,
                                    const char* example);

/// The general engine's steppers for expression Lagrangians, without and with a force: compiled
/// here once for the tool and the Python package. (A zero force through the forced stepper would
/// cost about 20 % per step at d = 2, measured: its Jacobians' zeros at every point.)
using expression_engine = general::stepper<expression_lagrangian>;
using forced_expression_engine = general::stepper<expression_lagrangian, expression_force>;

/// A stepper of the general engine for an expression Lagrangian and force, with the state it
/// advances.
class expression_stepper {
  public:
    /// From (q0, p0) at time t0, steps of size h of scheme `spec`, with force f (of L's
    /// dimension; a zero force takes the unforced stepper).
    expression_stepper(const expression_lagrangian& l, const expression_force& f, double h,
                       const scheme_spec& spec, const newton_options& opt, const vec<dynamic>& q0,
                       const vec<dynamic>& p0, double t0 = 0.0);
    ~expression_stepper();
    expression_stepper(const expression_stepper&) = delete;
    expression_stepper& operator=(const expression_stepper&) = delete;

    /// n steps. Throws step_failure (its what() names the step and the cause), leaving the state
    /// at the last good step.
    void step(std::size_t n = 1);
    /// n steps, recording (t, q, p, E) every `every` steps and after the last, appended to the
    /// vectors (q and p row by row, d per row); the start is recorded first when record_start.
    /// On a failed step the rows recorded so far are kept, and step_failure is thrown.
    void run(std::size_t n, std::size_t every, bool record_start, std::vector<double>& t,
             std::vector<double>& q, std::vector<double>& p, std::vector<double>& energy);

    [[nodiscard]] const vec<dynamic>& q() const;
    [[nodiscard]] const vec<dynamic>& p() const;
    [[nodiscard]] double time() const;
    [[nodiscard]] std::size_t steps() const;
    [[nodiscard]] double step_size() const;
    /// The energy q̇ᵀp − L at the current state and time.
    [[nodiscard]] double energy() const;
    /// The forces' work since the start (0 without a force): E − E0 − work() is the energy
    /// balance's error.
    [[nodiscard]] double work() const;
    /// Newton iterations per step so far.
    [[nodiscard]] double mean_newton_iterations() const;

  private:
    struct impl;
    std::unique_ptr<impl> impl_;
};

} // namespace varsym::cli
