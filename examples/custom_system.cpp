// examples/custom_system.cpp: your own system in a few lines. A separable Lagrangian
// L = ½ q̇ᵀ M q̇ − V(q) needs only V's value, gradient and Hessian; here the Hénon–Heiles
// potential V = ½(x² + y²) + x²y − y³/3, at an energy of 1/8 (regular motion).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <varsym/varsym.hpp>

struct henon_heiles {
    double value(const varsym::vec<2>& q) const {
        const double x = q(0), y = q(1);
        return 0.5 * (x * x + y * y) + x * x * y - y * y * y / 3.0;
    }
    varsym::vec<2> gradient(const varsym::vec<2>& q) const {
        const double x = q(0), y = q(1);
        return {x + 2 * x * y, y + x * x - y * y};
    }
    varsym::mat<2> hessian(const varsym::vec<2>& q) const {
        const double x = q(0), y = q(1);
        varsym::mat<2> h;
        h << 1 + 2 * y, 2 * x, 2 * x, 1 - 2 * y;
        return h;
    }
};

int main() {
    using namespace varsym;
    const separable_system<2, henon_heiles> system(mat<2>::Identity(), henon_heiles{});
    const phase_state<2> x0{vec<2>{0.0, 0.1}, vec<2>{0.47, 0.0}};
    const double h0 = system.energy(x0);

    // The paper's two schemes and a higher member of the family, all through with_stepper.
    const scheme_spec schemes[] = {scheme_kind::newmark, scheme_kind::simpson,
                                   scheme_spec(scheme_kind::gauss, 3)};
    double worst[3] = {0, 0, 0};
    for (int i = 0; i < 3; ++i) {
        phase_state<2> x = x0;
        with_stepper(schemes[i], system, 0.1, {}, [&](auto& stepper) {
            integrate(stepper, x, 0.0, 100000, [&](std::size_t, double, const phase_state<2>& y) {
                worst[i] = std::max(worst[i], std::abs(system.energy(y) - h0) / h0);
            });
        });
        std::printf("%-8s 10^5 steps of h = 0.1: max relative energy error %.3e\n",
                    schemes[i].label().c_str(), worst[i]);
    }
    // Symplectic schemes keep the energy error bounded: O(h²) for Newmark, O(h⁴) for Simpson,
    // O(h⁶) for gauss-3.
    const bool ok = worst[0] < 1e-2 && worst[1] < 1e-4 && worst[2] < 1e-7;
    std::printf("%s\n", ok ? "OK" : "UNEXPECTED");
    return ok ? 0 : 1;
}
