// examples/acrobot.cpp: a model of the models layer from C++ (docs/models.md). The acrobot under
// a constant elbow torque of 1 N m, stepped by gauss-2 until link 2 first folds over (|q2| > pi),
// within 20 s.
// With a force, the energy is not conserved but balanced: E − E0 equals the torque's work W up
// to the scheme's error (the discrete Lagrange–d'Alembert principle). Prints OK when it does to
// 1e-6 and the run stopped where asked.
#include <cmath>
#include <cstdio>

#include "varsym/models/model.hpp"

int main() {
    namespace vm = varsym::models;
    const vm::model& m = vm::get("acrobot");
    std::vector<double> values = m.defaults();
    values[static_cast<std::size_t>(m.parameter_index("torque"))] = 1.0; // N m on the elbow
    auto sim = m.prepare(values, {{1.0, 0.0}, {}, {0.0, 0.0}})           // q0 = (1, 0), at rest
                   .simulate({varsym::scheme_spec(varsym::scheme_kind::gauss, 2), {}, 1e-3});
    std::vector<double> columns(sim->columns().size()); // energy, work
    sim->values(columns);
    const double e0 = columns[0];
    double worst = 0.0;
    const bool reached_end = sim->advance(20000, [&] {
        sim->values(columns);
        worst = std::max(worst, std::abs(columns[0] - e0 - columns[1]));
        return std::abs(sim->q()[1]) > std::acos(-1.0); // the elbow folded over
    });
    std::printf("link 2 folded over at t = %.3f s (q = %.4f, %.4f); E - E0 = %.6f J, "
                "W = %.6f J, max |E - E0 - W| = %.2e J\n",
                sim->time(), sim->q()[0], sim->q()[1], columns[0] - e0, columns[1], worst);
    if (!reached_end && worst < 1e-6) std::printf("OK\n");
}
