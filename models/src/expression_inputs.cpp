// models/src/expression_inputs.cpp: optimal control of a Lagrangian typed as an expression (the
// model `lagrangian`): its inputs are generalized forces on named coordinates, under typed
// holonomic constraints if any: the controlled system (varsym/optimal/input_system.hpp) over the
// typed L's and constraints' symbolic derivatives, which the optimal control layer transcribes.
#include <algorithm>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>

#include "varsym/models/expression.hpp"
#include "varsym/optimal/input_system.hpp"
#include "varsym/systems/expression_constraint.hpp"

namespace varsym::models {

void add_expression_inputs(model& m, const std::string& text,
                           const std::vector<std::string>& coordinates,
                           const std::vector<expression_parameter>& parameters,
                           const std::vector<std::string>& inputs,
                           const std::vector<std::string>& constraints) {
    if (inputs.empty()) return;
    if (!constraints.empty()) // parsed once here, so that a bad one is refused at once
        (void)expression_constraint(constraints, coordinates, parameters);
    const auto d = static_cast<Eigen::Index>(coordinates.size());
    optimal::matrix b = optimal::matrix::Zero(d, static_cast<Eigen::Index>(inputs.size()));
    std::set<std::string> seen;
    m.controls.clear();
    for (std::size_t j = 0; j < inputs.size(); ++j) {
        const auto at = std::find(coordinates.begin(), coordinates.end(), inputs[j]);
        if (at == coordinates.end()) {
            std::string names;
            for (const auto& c : coordinates)
                names += (names.empty() ? "" : ", ") + c;
            throw std::invalid_argument("the input '" + inputs[j] +
                                        "' is not a coordinate; the coordinates: " + names);
        }
        if (!seen.insert(inputs[j]).second)
            throw std::invalid_argument("the input '" + inputs[j] + "' is given twice");
        b(at - coordinates.begin(), static_cast<Eigen::Index>(j)) = 1.0;
        // Appended, not `"u" + std::to_string(j + 1) + …`: GCC 12 at -O3 reports a false
        // -Wstringop-overflow on that sum when this file is compiled alone.
        std::string control = "u";
        control += std::to_string(j + 1);
        control += ": the generalized force on " + inputs[j] + " (units of dL/d" + inputs[j] + ")";
        m.controls.push_back(std::move(control));
    }
    // The controlled system at the parameters' values, in the order of `parameters`.
    m.control = [=](std::span<const double> values,
                    const lists&) -> std::shared_ptr<const optimal::controlled_system> {
        std::vector<expression_parameter> given = parameters;
        for (std::size_t i = 0; i < given.size(); ++i)
            given[i].value = values[i];
        expression_lagrangian l(text, coordinates, given);
        if (constraints.empty())
            return std::make_shared<const optimal::input_system<expression_lagrangian>>(
                std::move(l), b);
        return std::make_shared<
            const optimal::input_system<expression_lagrangian, expression_constraint>>(
            std::move(l), b, optimal::matrix{},
            expression_constraint(constraints, coordinates, given));
    };
}

} // namespace varsym::models
