// examples/optimal_minimum_time.cpp: minimum time with a bounded input (docs/optimal_control.md),
// through the models layer's pendulum (docs/models.md; L = m q̇²/2 − m ω² (1 − cos q) with m = 1
// kg m² and ω² = 9.81 s⁻², a unit pendulum under g = 9.81). It is swung from hanging to upright,
// at rest at both ends, as fast as a torque |u| ≤ 5 N m at the pivot allows: half the torque that
// would hold it horizontal, so it must pump.
// The horizon is an unknown (its first guess 3 s, within [0.2, 20] s); gauss-2, 80 steps, mesh
// refinement from 20. The optimum is bang-bang: the torque on one bound or the other, switching
// to pump and then to brake. Prints OK when it is solved, ends where asked, the torque sits on a
// bound (to 1e-6) at 95 % of the controls or more (the rest are the steps a switch falls in),
// it switches, and the closure check passes. (The double integrator's exact T* = 2 s is checked
// in tests/optimal/test_minimum_time.cpp.)
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <vector>

#include "varsym/models/model.hpp"
#include "varsym/optimize/model.hpp"
#include "varsym/optimize/solve.hpp"

int main() {
    namespace vo = varsym::optimal;
    const double bound = 5.0, pi = std::numbers::pi; // N m
    const varsym::models::model& m = varsym::models::get("pendulum");
    const std::vector<double> values{1.0, std::sqrt(9.81)}; // mass [kg m²], ω [rad/s]
    const auto make = [&](int steps) -> std::unique_ptr<vo::transcription> {
        vo::control_problem p;
        p.time = 3.0;
        p.free_time = true;
        p.time_lower = 0.2;
        p.time_upper = 20.0;
        p.cost = {.effort = 0.0, .time = 1.0};
        p.steps = steps;
        p.scheme = {varsym::scheme_kind::gauss, 2};
        p.q_start = p.v_start = p.v_end = Eigen::VectorXd::Zero(1);
        p.q_end = Eigen::VectorXd::Constant(1, pi);
        p.control_lower = Eigen::VectorXd::Constant(1, -bound);
        p.control_upper = Eigen::VectorXd::Constant(1, bound);
        return vo::transcribe(m, values, {}, p);
    };
    const vo::refined run = vo::solve_refined(make, 80, 2);
    const vo::trajectory path = run.problem->unpack(run.result);
    const double horizon = path.node_times(path.node_times.size() - 1);
    int on_bound = 0, switches = 0;
    for (Eigen::Index c = 0; c < path.u.cols(); ++c) {
        on_bound += std::abs(std::abs(path.u(0, c)) - bound) < 1e-6;
        switches += c > 0 && path.u(0, c) * path.u(0, c - 1) < 0;
    }
    const double share = on_bound / static_cast<double>(path.u.cols());
    const vo::closure_check closure = vo::check_closure(*run.problem, path);
    const double reached = std::abs(path.q(0, path.q.cols() - 1) - pi);
    std::printf("pendulum swing-up in minimum time with |u| <= %.0f N m: %s, T = %.6f s, torque "
                "on a bound at %.1f %% of the controls, %d switches, closure %.1e\n",
                bound, vo::status_name(run.result.verdict), horizon, 100 * share, switches,
                closure.error);
    if (run.result.verdict == vo::status::solved && reached < 1e-12 && share >= 0.95 &&
        switches >= 1 && closure.ok())
        std::printf("OK\n");
}
