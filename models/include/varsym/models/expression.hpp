// varsym/models/expression.hpp: simulations of Lagrangians typed as expressions (a user's
// L(q, q̇, t) and generalized force, varsym/systems/expression_lagrangian.hpp), by the general
// engine compiled once in the models layer: no compiler is needed to run a new system.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "varsym/models/model.hpp"
#include "varsym/models/simulation.hpp"
#include "varsym/systems/expression_constraint.hpp"
#include "varsym/systems/expression_force.hpp"
#include "varsym/systems/expression_lagrangian.hpp"

namespace varsym::models {

/// A simulation of L with force f from x0 at time t0: by the scheme's separable stepper (the
/// paper's Newmark and Simpson, the family's) where L is ½ q̇ᵀ M q̇ − V(q) with M constant and
/// there is no force (expression_lagrangian::separable()), else by the general engine (a zero
/// force takes its unforced form, about 20 % faster). Its columns: energy E(t) = q̇ᵀp − L, and with
/// a force work (W since the start) and energy_balance (E − E0 − W). Throws std::invalid_argument
/// for a force of another dimension, a state of another size, or a step size that is not positive
/// and finite.
std::unique_ptr<simulation> simulate_expression(const expression_lagrangian& l,
                                                const expression_force& f,
                                                const phase_state<dynamic>& x0,
                                                const step_options& o, double t0 = 0.0);

/// A simulation of L with holonomic constraints c, g(q) = 0, and force f (zero: none) from x0 at
/// time t0, by the constrained general engine (schemes/constrained.hpp; Newton on the
/// saddle-point system). x0 must lie on the constraints with a tangent velocity, else
/// std::invalid_argument; `project` moves it onto them first (the simulation's state at t0 is
/// then the projected one). Columns: energy, work, energy_balance (E − E0 − W),
/// constraint_residual (max |g(q)|), hidden_residual (max |G(q) q̇|), lambda_1..m (the
/// multipliers averaged over the last step). Throws std::invalid_argument as simulate_expression
/// does, and for constraints on other coordinates or an iteration other than Newton.
std::unique_ptr<simulation>
simulate_constrained_expression(const expression_lagrangian& l, const expression_constraint& c,
                                const expression_force& f, const phase_state<dynamic>& x0,
                                const step_options& o, double t0 = 0.0, bool project = false);

/// The initial momenta p = ∂L/∂q̇ at (q, v, t), refusing a singular mass matrix ∂²L/∂q̇² there
/// (std::invalid_argument).
vec<dynamic> expression_momentum(const expression_lagrangian& l, const vec<dynamic>& q,
                                 const vec<dynamic>& v, double t = 0.0);

/// Refuses (std::invalid_argument, with the estimates) a Lagrangian of d coordinates typed in
/// `length` characters whose symbolic second derivatives would take more than a minute or more
/// than 80 % of the machine's memory to build. Both grow as d² times the expression's size:
/// measured on a chain of d masses, 0.7 s and 37 MB at d = 200 (7 200 characters), 4.2 s and
/// 158 MB at d = 400 (16 000), so about 6.6e-10 s and 1 000 bytes per d²·character, d².
void check_expression_size(int d, std::size_t length);

/// The model `lagrangian`: L typed as `text` over `coordinates` (velocities NAME_dot), with the
/// expression's parameters as the model's (each unbounded, its given value the default) and a
/// generalized force, one expression per coordinate (`force` empty: none). Its start: q0
/// (default 0) with v0 (default 0) or p0. No period: 10 s in 10 000 steps by default (an
/// ensemble member 10 s in 1000). Every command and the Python package run it like a built-in
/// model, its ensembles over q0, p0 and the parameters. `constraints` (none: unconstrained),
/// holonomic constraints g(q) = 0 over the same names, one per equation, make it a mechanism
/// run by the constrained engine (simulate_constrained_expression), with the constrained
/// models' flag parameter `project` after L's. Throws expr::parse_error or
/// std::invalid_argument where the expressions do not make a Lagrangian, force and constraints.
model expression_model(const std::string& text, const std::vector<std::string>& coordinates,
                       const std::vector<expression_parameter>& parameters,
                       const std::vector<std::string>& force = {},
                       const std::vector<std::string>& constraints = {});
/// The same model of an L already built (parsed and differentiated): its members at the
/// default parameters copy it instead of differentiating L again (Python's Lagrangian).
model expression_model(const expression_lagrangian& l, const std::vector<std::string>& force = {},
                       const std::vector<std::string>& constraints = {});

/// Gives the model `lagrangian` m (made by expression_model from `text`, `coordinates` and
/// `parameters`, without force or constraints) control inputs: input j is a generalized force on
/// the coordinate named inputs[j] (units of ∂L/∂q there). Sets m.controls and m.control (the
/// controlled system over L's symbolic derivatives at the parameters' values,
/// varsym/optimal/input_system.hpp), under the holonomic constraints g(q) = 0 typed in
/// `constraints` if any (one expression per equation, over the coordinates and parameters). Throws
/// std::invalid_argument for a name that is not a coordinate, or one given twice, and
/// expr::parse_error for a constraint that does not parse.
void add_expression_inputs(model& m, const std::string& text,
                           const std::vector<std::string>& coordinates,
                           const std::vector<expression_parameter>& parameters,
                           const std::vector<std::string>& inputs,
                           const std::vector<std::string>& constraints = {});

} // namespace varsym::models
