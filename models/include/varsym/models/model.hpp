// varsym/models/model.hpp: the built-in models, each defined once as data plus a factory: its
// name, summary and description, its parameters (default, unit, meaning, bounds; declared with
// parameters.hpp, which reads their values into the model's own struct by name), its default
// initial state and the rules that complete a given one, its period or time scale, the factory
// that builds its problem (system, initial state, exact solution) and from that a simulation
// (simulation.hpp) of any scheme, and, for a model with inputs, its controlled system, which the
// optimal control layer (varsym/optimize/model.hpp) solves problems of. The command-line tool's
// options and help, its ensembles and sections, and the Python package are all generated from
// this data.
#pragma once

#include <functional>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "varsym/models/figure.hpp"
#include "varsym/models/simulation.hpp"

namespace varsym::optimal {
class controlled_system;
struct control_problem;
} // namespace varsym::optimal

namespace varsym::models {

/// One scalar parameter of a model.
struct parameter {
    std::string name;  ///< its key: ensemble key, Python keyword, config key (snake_case)
    double value = 0.; ///< the default
    std::string unit;  ///< SI unit ("kg", "rad/s"); empty when dimensionless
    std::string doc;   ///< what it is, one phrase
    double lower = -std::numeric_limits<double>::infinity(); ///< allowed range [lower, upper]
    double upper = std::numeric_limits<double>::infinity();
    bool lower_open = false; ///< lower itself is excluded (a positive mass: lower 0, open)
    bool upper_open = false;
    /// Where NaN is an allowed value, what it means (henon-heiles' energy: "use p0 as given").
    std::string nan_means;
    /// The command line's option when it is not the name with '-' for '_' (double-pendulum's g:
    /// "gravity"), or a list option shared by several parameters (its m1 and m2: "masses").
    std::string option;
    int option_index = -1; ///< the parameter's place in a list option (0, 1, …), or −1
    bool integer = false;  ///< a count (the chain's n): only whole numbers are allowed
    /// A switch, 0 (off, the default) or 1: the command line's option is a flag that sets 1
    /// (the constrained mechanisms' `project`).
    bool flag = false;
    /// The parameter sets the number of coordinates (the chain's n): ensembles take it once for
    /// all members, not as a member's key.
    bool sets_dimension = false;

    /// The option's long name without "--".
    [[nodiscard]] std::string option_name() const;
    /// "positive", "0 <= x < 1", …: the bounds in words, for help and messages.
    [[nodiscard]] std::string range() const;
    /// Throws std::invalid_argument naming the parameter when v is outside its range.
    void check(double v) const;
};

/// A parameter of several values: the arm's masses (one per link, their count sets d), the
/// oscillator's mass matrix (1, d or d² values).
struct list_parameter {
    std::string name;          ///< its key: Python keyword, config key (snake_case)
    std::vector<double> value; ///< the default; empty where the model's rule (in `doc`) sets it
    std::string unit;          ///< of each value
    std::string doc;           ///< what it is and how many values, one phrase
    double lower = -std::numeric_limits<double>::infinity(); ///< each value's range
    double upper = std::numeric_limits<double>::infinity();
    bool lower_open = false;
    std::string option; ///< the command line's option where it is not the name with '-' for '_'
    /// The values' count sets the number of coordinates (the arm's masses: one per link).
    bool sets_dimension = false;

    [[nodiscard]] std::string option_name() const;
    /// One of its values as a scalar parameter: the list's name and each value's range.
    [[nodiscard]] parameter each() const;
    /// Each value's range in words.
    [[nodiscard]] std::string range() const;
    /// Throws std::invalid_argument naming the parameter when a value is outside its range.
    void check(const std::vector<double>& v) const;
};

/// The values of a model's list parameters, in the order of model::lists; an empty one is its
/// default.
using lists = std::vector<std::vector<double>>;

/// Where a run starts. Each vector is empty (the model's default) or holds d values; p0 and v0
/// (velocities, turned into momenta by the model) exclude each other.
struct start {
    std::vector<double> q0, p0, v0;
};

/// A model with its parameters and initial state set: the complete initial state, the period
/// (0 where the motion has none) and the factory of simulations of any scheme.
struct problem {
    std::vector<double> q0, p0;
    double period = 0.0;
    /// Where a model that usually has a period has none at this state, why (the pendulum on its
    /// separatrix): a run must then be given by time and steps.
    std::string no_period;
    /// The model's own integrator at these parameters (the rigid bodies': lgvi of their
    /// `order`), which step_options' scheme does not choose; empty label: the scheme's.
    own_integrator integrator;
    std::function<std::unique_ptr<simulation>(const step_options&)> simulate;
};

/// A built-in model.
struct model {
    std::string name;        ///< "pendulum", "cart-pole"
    std::string summary;     ///< one line
    std::string description; ///< the Lagrangian, coordinates, units, conserved quantities
    int dim = 0; ///< the number of coordinates d (at the defaults, where `dimension` is set)
    /// Where d follows from the parameters (the chain's n, the arm's masses): d from all
    /// parameters' values (each list empty for its default). Null where d is always `dim`.
    std::function<int(std::span<const double>, const lists&)> dimension;
    std::string coordinates; ///< their names for messages ("th1, th2")
    std::vector<parameter> parameters;
    std::vector<list_parameter> lists; ///< the parameters of several values, if any
    std::vector<double> q0, p0;        ///< the default initial state (with the default parameters)
    /// Non-empty where the model has its own integrator rather than the schemes (the rigid
    /// bodies): why, and how to choose its order; a scheme given then is refused with this.
    std::string integrator_note;
    /// The parameter that chooses the order of that integrator ("order"); its upper bound is
    /// its most accurate member, which `varsym converge` measures against.
    std::string integrator_parameter;
    /// Non-empty where the initial state follows from the parameters alone (kepler: at
    /// pericentre): then q0, p0 and v0 are refused with this advice.
    std::string fixed_start;
    bool velocities = true; ///< whether v0 may be given instead of p0
    /// Sizes besides d that q0 and v0 may have, the model completing the rest (the four-bar's
    /// crank angle alone: 1), and what such a short vector holds ("th1 alone").
    std::vector<int> short_start;
    std::string short_start_doc;
    /// Run length: steps per period where the motion has a period, else time and steps.
    long long steps_per_period = 0;
    double time = 0.0;
    long long steps = 0;
    double ensemble_time = 0.0; ///< an ensemble member's default length and steps
    long long ensemble_steps = 0;
    std::string ensemble_note; ///< for the ensemble's help: a typical section or event
    /// Builds the problem from all parameters' values (in the order of `parameters`, already
    /// checked against their ranges), the lists (one per list parameter, each empty for its
    /// default, the values checked) and the start; throws std::invalid_argument for data the
    /// model refuses (a state outside the energy surface, a singular mass matrix, a list of
    /// the wrong length).
    std::function<problem(std::span<const double>, const start&, const models::lists&)> make;
    /// Where the model has control inputs (the acrobot's elbow torque): their names with units
    /// ("u [N m], torque at the elbow"; one line may stand for one input per coordinate, as the
    /// arm's). Empty where it has none.
    std::vector<std::string> controls;
    /// The parameters and lists (by name) that only a simulation uses: the one that holds the
    /// input constant (the cart-pole's push, the acrobot's torque), which an optimisation
    /// computes instead, and a controller's gains and target. An optimisation refuses them.
    std::vector<std::string> simulation_only;
    /// The controlled system at the parameters' values and lists (empty: the defaults): L with
    /// its input matrix and damping (varsym/optimal/input_system.hpp), which the optimal control
    /// layer (varsym::optimal, varsym/optimize/model.hpp) transcribes and solves. Null where
    /// the model has no inputs.
    std::function<std::shared_ptr<const optimal::controlled_system>(std::span<const double>,
                                                                    const models::lists&)>
        control;
    /// The model's own bounds for an optimal control problem at the parameters' values (a URDF
    /// robot's joint position, velocity and torque limits), put into the problem's position,
    /// velocity and control bounds where those are unbounded. Null: none.
    std::function<void(std::span<const double>, const models::lists&, optimal::control_problem&)>
        limits;
    /// Where the model is a linkage to draw (the pictures of `varsym optimize`): the polyline
    /// of its joints at q, as x0, y0, x1, y1, … [m], at the parameters' values. May be null.
    std::function<std::vector<double>(std::span<const double>, const models::lists&,
                                      std::span<const double>)>
        pose;
    /// Where the model is a body or linkage to watch in 3-D (`varsym run --animate`, Python's
    /// Trajectory.animate): its figure at the parameters' values (models/figure.hpp). May be
    /// null.
    std::function<figure(std::span<const double>, const models::lists&)> drawing;

    /// Whether the model has control inputs (`controls` declared): an optimisation applies.
    [[nodiscard]] bool has_inputs() const { return !controls.empty(); }
    /// The parameters' defaults, in order.
    [[nodiscard]] std::vector<double> defaults() const;
    /// The number of coordinates d at these parameters' values.
    [[nodiscard]] int dimension_at(std::span<const double> values,
                                   const models::lists& l = {}) const {
        return dimension ? dimension(values, l.empty() ? models::lists(lists.size()) : l) : dim;
    }
    /// The index of parameter `key`, or −1.
    [[nodiscard]] int parameter_index(std::string_view key) const;
    /// Checks values and lists against the ranges and the start against d and `fixed_start`,
    /// then makes the problem. `l` holds one list per list parameter (or none: all defaults).
    /// Throws std::invalid_argument with a message that names the model.
    [[nodiscard]] problem prepare(std::span<const double> values, const start& s = {},
                                  const models::lists& l = {}) const;
};

/// Every built-in model of the layer, in the order `varsym models` lists them.
const std::vector<model>& registry();
/// The model named `name`, or nullptr.
const model* find(std::string_view name);
/// The model named `name`; throws std::invalid_argument naming the closest names otherwise.
const model& get(std::string_view name);

/// The names among `candidates` closest to `word` (by edit distance, at most a third of the
/// word's length plus one), best first: for "did you mean" messages.
std::vector<std::string> closest(std::string_view word, const std::vector<std::string>& candidates);

} // namespace varsym::models
