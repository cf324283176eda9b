// The installed models layer and optimal control solver from a user's program: the cart-pole
// pushed by u = 0.5 N for 1000 steps (its cart coordinate is cyclic, so p_x(t) = p_x(0) + u t
// exactly, to round-off); and the cart moved by 1 m in 2 s at least effort, pole hanging at both
// ends, by the model's own transcription and IPOPT, replayed by the simulator. Prints OK when
// both hold.
#include <cmath>
#include <cstdio>
#include <numbers>

#include <varsym/models/model.hpp>
#include <varsym/optimize/model.hpp>
#include <varsym/optimize/solve.hpp>

int main() {
    const varsym::models::model& m = varsym::models::get("cart-pole");
    std::vector<double> values = m.defaults();
    values[static_cast<std::size_t>(m.parameter_index("push"))] = 0.5;
    auto sim =
        m.prepare(values).simulate({varsym::scheme_spec(varsym::scheme_kind::simpson), {}, 1e-3});
    sim->advance(1000);
    const double error = std::abs(sim->p()[0] - 0.5 * sim->time());
    std::printf("p_x = %.15g at t = %g (error %.1e)\n", sim->p()[0], sim->time(), error);

    varsym::optimal::control_problem p;
    p.time = 2.0;
    p.steps = 20;
    p.q_start = Eigen::Vector2d(0.0, std::numbers::pi);
    p.q_end = Eigen::Vector2d(1.0, std::numbers::pi);
    p.v_start = p.v_end = Eigen::VectorXd::Zero(2);
    const auto tr = varsym::optimal::transcribe(m, m.defaults(), {}, p);
    const auto r = varsym::optimal::solve(*tr);
    const auto path = tr->unpack(r);
    const auto closure = varsym::optimal::check_closure(*tr, path);
    std::printf("optimal push: %s, cost %.9g, closure %.1e\n",
                varsym::optimal::status_name(r.verdict), r.cost, closure.error);
    if (error < 1e-12 && r.converged() && closure.ok()) std::printf("OK\n");
}
