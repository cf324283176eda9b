// varsym/diagnostics/convergence.hpp: observed order of convergence from errors at several
// step counts.
#pragma once

#include <cmath>
#include <cstddef>
#include <span>
#include <stdexcept>

namespace varsym {

/// Least-squares slope p of log(error) = c − p log(steps): the observed order of convergence.
inline double fitted_order(std::span<const double> steps, std::span<const double> errors) {
    if (steps.size() != errors.size() || steps.size() < 2)
        throw std::invalid_argument("fitted_order needs at least two (steps, error) pairs");
    const auto n = static_cast<double>(steps.size());
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (std::size_t i = 0; i < steps.size(); ++i) {
        const double x = std::log(steps[i]);
        const double y = std::log(errors[i]);
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
    }
    return -(n * sxy - sx * sy) / (n * sxx - sx * sx);
}

} // namespace varsym
