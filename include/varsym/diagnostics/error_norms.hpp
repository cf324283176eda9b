// varsym/diagnostics/error_norms.hpp: max-norm errors of a run against an exact solution, and
// the relative energy error, as in the paper's Table 1.
#pragma once

#include <algorithm>
#include <cmath>

#include "varsym/integrate.hpp"

namespace varsym {

/// Max over all steps j = 0 … n of |p_j − p(t_j)|, |q_j − q(t_j)| (max norm over components)
/// and |H_j − H_0| / |H_0| (absolute if H_0 = 0): the three rows of the paper's Table 1.
struct error_norms {
    double momentum = 0.0;
    double state = 0.0;
    double energy = 0.0;
    run_summary run;
};

/// Integrates n steps from x0 at t = 0 and measures error_norms against exact(t) -> phase_state.
template <class Stepper, class Exact>
error_norms measure_errors(Stepper& stepper, phase_state<Stepper::dim> x0, std::size_t n,
                           const Exact& exact) {
    const auto& sys = stepper.system();
    const double h0 = sys.energy(x0);
    const double scale = h0 != 0.0 ? std::abs(h0) : 1.0;
    error_norms e;
    e.run = integrate(stepper, x0, 0.0, n, [&](std::size_t, double t, const auto& x) {
        const auto ref = exact(t);
        e.momentum = std::max(e.momentum, (x.p - ref.p).template lpNorm<Eigen::Infinity>());
        e.state = std::max(e.state, (x.q - ref.q).template lpNorm<Eigen::Infinity>());
        e.energy = std::max(e.energy, std::abs(sys.energy(x) - h0) / scale);
    });
    return e;
}

} // namespace varsym
