// examples/optimal_swing_ups.cpp: two underactuated swing-ups by discrete mechanics and optimal
// control (docs/optimal_control.md), through the models layer (docs/models.md): the cart-pole
// (a force on the cart only) from the pole hanging to upright with the cart back where it
// started, and the acrobot (a torque at the elbow only) from hanging to upright, both at rest at
// both ends, minimising the effort ∫ ½ u² dt with the Simpson scheme. Prints OK when both are
// solved, end where asked, and the general engine's replay of the optimal controls reproduces
// the optimal motion (the closure check) to 1e-8.
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "varsym/models/model.hpp"
#include "varsym/optimal/solve.hpp"

namespace {

bool swing_up(const char* name, const std::vector<double>& from, const std::vector<double>& to,
              double time, int steps) {
    namespace vo = varsym::optimal;
    const varsym::models::model& m = varsym::models::get(name);
    const std::vector<double> values = m.defaults();
    vo::control_problem p;
    p.time = time; // s
    p.steps = steps;
    p.scheme = varsym::scheme_kind::simpson;
    p.q_start = Eigen::Map<const Eigen::VectorXd>(from.data(), 2);
    p.q_end = Eigen::Map<const Eigen::VectorXd>(to.data(), 2);
    p.v_start = p.v_end = Eigen::VectorXd::Zero(2); // at rest at both ends
    const auto tr = m.optimal(values, {}, p); // no list parameters
    const vo::nlp_result r = vo::solve(*tr);
    const vo::trajectory path = tr->unpack(r);
    const vo::closure_check closure = vo::check_closure(*tr, path);
    const double reached = (path.q.col(steps) - p.q_end).cwiseAbs().maxCoeff();
    std::printf("%-9s %s in %d iterations: cost %.6f, max |u| = %.3f, closure %.1e, "
                "end off by %.1e\n",
                name, vo::status_name(r.verdict), r.iterations, path.cost,
                path.u.cwiseAbs().maxCoeff(), closure.error, reached);
    return r.verdict == vo::status::solved && closure.ok() && closure.error < 1e-8 &&
           reached < 1e-12;
}

} // namespace

int main() {
    const double pi = std::numbers::pi;
    // Cart-pole coordinates (x [m], θ [rad], θ = 0 upright); acrobot (q1, q2 [rad], 0 hanging).
    const bool cart = swing_up("cart-pole", {0.0, pi}, {0.0, 0.0}, 2.0, 40);
    const bool acrobot = swing_up("acrobot", {0.0, 0.0}, {pi, 0.0}, 4.0, 40);
    if (cart && acrobot) std::printf("OK\n");
}
