// apps/varsym/options/expression_options.hpp: the options of Lagrangians given as expressions
// (`varsym run`, `ensemble` and `section` with --lagrangian): the model `lagrangian` they make is
// the models layer's (varsym/models/expression.hpp).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "options/cli_common.hpp"
#include "varsym/models/model.hpp"
#include "varsym/systems/expression_constraint.hpp"
#include "varsym/systems/expression_force.hpp"
#include "varsym/systems/expression_lagrangian.hpp"

namespace varsym::cli {

/// "m=1,g=9.81" as parameters; throws usage_error naming the entry that is not NAME=NUMBER.
std::vector<expression_parameter> parse_parameters(const std::string& list);
/// "a, b,c" as its entries, spaces around each dropped; throws usage_error naming `option` on an
/// empty entry, with `example` of a good list.
std::vector<std::string> split_list(const std::string& list, const char* option,
                                    const char* example);
/// The equations of --constraints (`text`), each checked over the coordinates and parameters;
/// none for an empty text. Throws usage_error naming --constraints.
std::vector<std::string> constraints_of(const std::string& text,
                                        const std::vector<std::string>& coordinates,
                                        const std::vector<expression_parameter>& parameters);

/// --lagrangian, --coordinates, --parameters, --force and --constraints as given.
struct expression_spec {
    std::string lagrangian, coordinates = "q", parameters, force, constraints;
};

/// Adds --lagrangian, --coordinates, --parameters, --force and --constraints to cmd.
void add_expression_options(CLI::App& cmd, expression_spec& e);
/// The model `lagrangian` of these options; throws usage_error naming the option at fault.
std::shared_ptr<const models::model> expression_model_of(const expression_spec& e);

} // namespace varsym::cli
