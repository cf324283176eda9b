// models/src/step_checks.hpp: the refusals of step options that a model's stepper would
// otherwise ignore (an iteration or a predictor it does not have). Private to the models layer.
#pragma once

#include <stdexcept>
#include <string>

#include "varsym/models/simulation.hpp"

namespace varsym::models::detail {

/// Refuses a predictor other than Taylor's (the default): `why` says whose steps start from
/// their own prediction.
inline void refuse_non_taylor(const step_options& o, const std::string& why) {
    if (o.newton.predictor != predictor_kind::taylor)
        throw std::invalid_argument(why + ": use the predictor taylor (the default)");
}

/// The general engine has the Taylor predictor alone: 'previous' and 'forces' are refused.
inline void check_general(const step_options& o) {
    refuse_non_taylor(o, "the predictors 'previous' and 'forces' are for the separable models "
                         "(the family stepper); this model runs the general engine");
}

/// Refuses an iteration other than Newton (`automatic` is Newton here): `why` says who solves
/// its steps by Newton ("a constrained model is solved by Newton"). Not to be confused with
/// constrained_stepper's private newton_only, which sets the iteration rather than refusing.
inline void refuse_non_newton(const step_options& o, const std::string& why) {
    if (o.newton.iteration != iteration_kind::automatic &&
        o.newton.iteration != iteration_kind::newton)
        throw std::invalid_argument(why + ": use the iteration newton (the default)");
}

} // namespace varsym::models::detail
