// The installed models layer from a user's program: the cart-pole pushed by u = 0.5 N for 1000
// steps. Its cart coordinate is cyclic, so p_x(t) = p_x(0) + u t exactly (to round-off); prints
// OK when it is.
#include <cmath>
#include <cstdio>

#include <varsym/models/model.hpp>

int main() {
    const varsym::models::model& m = varsym::models::get("cart-pole");
    std::vector<double> values = m.defaults();
    values[static_cast<std::size_t>(m.parameter_index("push"))] = 0.5;
    auto sim =
        m.prepare(values).simulate({varsym::scheme_spec(varsym::scheme_kind::simpson), {}, 1e-3});
    sim->advance(1000);
    const double error = std::abs(sim->p()[0] - 0.5 * sim->time());
    std::printf("p_x = %.15g at t = %g (error %.1e)\n", sim->p()[0], sim->time(), error);
    if (error < 1e-12) std::printf("OK\n");
}
