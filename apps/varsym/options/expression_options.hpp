// apps/varsym/options/expression_options.hpp: the options of Lagrangians given as expressions (`varsym run
// --lagrangian`); their stepper is the models layer's (varsym/models/expression.hpp).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "varsym/systems/expression_force.hpp"
#include "varsym/systems/expression_lagrangian.hpp"

namespace varsym::cli {

/// "m=1,g=9.81" as parameters; throws usage_error naming the entry that is not NAME=NUMBER.
std::vector<expression_parameter> parse_parameters(const std::string& list);
/// "a, b,c" as its entries, spaces around each dropped; throws usage_error naming `option` on an
/// empty entry, with `example` of a good list.
std::vector<std::string> split_list(const std::string& list, const char* option,
                                    const char* example);

} // namespace varsym::cli
