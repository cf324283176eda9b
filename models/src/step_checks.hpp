// models/src/step_checks.hpp: the refusals of step options that a model's stepper would
// otherwise ignore (an iteration or a predictor it does not have). Private to the models layer.
#pragma once

#include <stdexcept>
#include <string>

#include "varsym/models/simulation.hpp"

namespace varsym::models::detail {

/// The general engine has the Taylor predictor alone: 'previous' and 'forces' are refused.
inline void check_general(const step_options& o) {
    if (o.newton.predictor != predictor_kind::taylor)
        throw std::invalid_argument("the predictors 'previous' and 'forces' are for the separable "
                                    "models (the family stepper); this model runs the general "
                                    "engine: use the predictor taylor");
}

/// Refuses an iteration other than Newton (`automatic` is Newton here): `why` says who solves
/// its steps by Newton ("a constrained model is solved by Newton").
inline void newton_only(const step_options& o, const std::string& why) {
    if (o.newton.iteration != iteration_kind::automatic &&
        o.newton.iteration != iteration_kind::newton)
        throw std::invalid_argument(why + ": use the iteration newton (the default)");
}

} // namespace varsym::models::detail
