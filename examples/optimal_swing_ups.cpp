// examples/optimal_swing_ups.cpp: two underactuated swing-ups by discrete mechanics and optimal
// control (docs/optimal_control.md), through the models layer (docs/models.md): the cart-pole
// (a force on the cart only) from the pole hanging to upright with the cart back where it
// started, and the acrobot (a torque at the elbow only) from hanging to upright, both at rest at
// both ends, minimising the effort ∫ ½ u² dt with the Simpson scheme, by the service both front
// ends call (optimal::optimize). Prints OK when both are solved and trusted, end where asked,
// and the general engine's replay of the optimal controls reproduces the optimal motion (the
// closure check) to 1e-8.
#include <cmath>
#include <cstdio>
#include <numbers>
#include <utility>
#include <vector>

#include "varsym/models/model.hpp"
#include "varsym/optimize/model.hpp"

namespace {

bool swing_up(const char* name, const std::vector<double>& from, const std::vector<double>& to,
              double time, int steps) {
    namespace vo = varsym::optimal;
    const varsym::models::model& m = varsym::models::get(name);
    vo::model_request request;
    vo::control_problem& p = request.problem;
    p.time = time; // s
    p.steps = steps;
    p.scheme = varsym::scheme_kind::simpson;
    p.q_start = Eigen::Map<const Eigen::VectorXd>(from.data(), 2);
    p.q_end = Eigen::Map<const Eigen::VectorXd>(to.data(), 2);
    p.v_start = p.v_end = Eigen::VectorXd::Zero(2); // at rest at both ends
    // Solved, unpacked and checked (equations, bounds, the replay) in one call; no list
    // parameters.
    const vo::model_outcome out = vo::optimize(m, m.defaults(), {}, std::move(request));
    const vo::trajectory& path = out.path;
    const double reached = (path.q.col(steps) - out.problem.q_end).cwiseAbs().maxCoeff();
    std::printf("%-9s %s in %d iterations: cost %.6f, max |u| = %.3f, closure %.1e, "
                "end off by %.1e\n",
                name, vo::status_name(out.result.verdict), out.result.iterations, path.cost,
                path.u.cwiseAbs().maxCoeff(), out.check.closure.error, reached);
    return out.verdict == vo::verdict::solved && out.check.closure.error < 1e-8 && reached < 1e-12;
}

} // namespace

int main() {
    const double pi = std::numbers::pi;
    // Cart-pole coordinates (x [m], θ [rad], θ = 0 upright); acrobot (q1, q2 [rad], 0 hanging).
    const bool cart = swing_up("cart-pole", {0.0, pi}, {0.0, 0.0}, 2.0, 40);
    const bool acrobot = swing_up("acrobot", {0.0, 0.0}, {pi, 0.0}, 4.0, 40);
    if (cart && acrobot) std::printf("OK\n");
}
