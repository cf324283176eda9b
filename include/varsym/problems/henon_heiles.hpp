// varsym/problems/henon_heiles.hpp: the Hénon–Heiles system (M. Hénon and C. Heiles, "The
// applicability of the third integral of motion: some numerical experiments", Astron. J. 69,
// 73–79, 1964), the classic two-degree-of-freedom Hamiltonian with ordered and chaotic orbits.
//
// Units and conventions: dimensionless, as in the paper. q = (x, y), unit mass, L = ½|q̇|² − V,
//   V(x, y) = ½ (x² + y²) + x² y − y³/3,   H = ½ (p_x² + p_y²) + V,
// so p = q̇. Orbits with H < 1/6 that start inside the triangle bounded by the saddles stay
// bounded; at H = 1/12 most of the section is regular, at H = 1/8 about half is chaotic, near
// H = 1/6 most is. The usual surface of section is x = 0 crossed with p_x > 0, drawn in (y, p_y).
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>

#include "varsym/systems/separable.hpp"

namespace varsym::henon_heiles {

/// The energy of the saddles, above which orbits can escape.
inline constexpr double escape_energy = 1.0 / 6.0;

/// V(x, y) = ½ (x² + y²) + x² y − y³/3.
struct potential {
    [[nodiscard]] double value(const vec<2>& q) const {
        const double x = q(0), y = q(1);
        return 0.5 * (x * x + y * y) + x * x * y - y * y * y / 3.0;
    }
    /// ∇V = (x + 2 x y, y + x² − y²)
    [[nodiscard]] vec<2> gradient(const vec<2>& q) const {
        const double x = q(0), y = q(1);
        return {x + 2.0 * x * y, y + x * x - y * y};
    }
    /// ∇²V = [[1 + 2y, 2x], [2x, 1 − 2y]]
    [[nodiscard]] mat<2> hessian(const vec<2>& q) const {
        const double x = q(0), y = q(1);
        mat<2> h;
        h << 1.0 + 2.0 * y, 2.0 * x, 2.0 * x, 1.0 - 2.0 * y;
        return h;
    }
};

using system = separable_system<2, potential>;

inline system make_system() {
    return system(mat<2>::Identity(), potential{});
}

/// The state on the section x = 0 at (y, p_y) with energy E, moving with p_x > 0:
/// p_x = sqrt(2E − p_y² − y² + 2y³/3). Throws std::invalid_argument where (y, p_y) lies outside
/// that energy's section (p_x² < 0).
inline phase_state<2> on_section(double energy, double y, double p_y) {
    const double px2 = 2.0 * energy - p_y * p_y - y * y + 2.0 * y * y * y / 3.0;
    if (!(px2 >= 0.0))
        throw std::invalid_argument("(y, p_y) = (" + std::to_string(y) + ", " +
                                    std::to_string(p_y) + ") is outside the section of energy " +
                                    std::to_string(energy));
    phase_state<2> x;
    x.q << 0.0, y;
    x.p << std::sqrt(px2), p_y;
    return x;
}

} // namespace varsym::henon_heiles
