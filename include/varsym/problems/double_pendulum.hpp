// varsym/problems/double_pendulum.hpp: the planar double pendulum (a two-link arm with point
// masses), with optional joint springs: a configuration-dependent mass matrix M(q).
//
// Units and conventions: q = (θ₁, θ₂) are the angles of the two links from the downward
// vertical [rad]; masses m₁, m₂ [kg] at the ends of massless links of lengths ℓ₁, ℓ₂ [m];
// gravity g [m/s²]; joint springs of stiffness k [N m/rad] pull θ₁ and θ₂ − θ₁ to 0.
//   L = ½(m₁+m₂)ℓ₁²θ̇₁² + ½m₂ℓ₂²θ̇₂² + m₂ℓ₁ℓ₂θ̇₁θ̇₂cos(θ₁−θ₂)
//       + (m₁+m₂)gℓ₁cos θ₁ + m₂gℓ₂cos θ₂ − ½k(θ₁² + (θ₂−θ₁)²)
// p = ∂L/∂q̇ are the angular momenta [kg m²/s]; the energy E = q̇ᵀp − L [J] is conserved.
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>

#include "varsym/systems/lagrangian.hpp"

namespace varsym::double_pendulum {

struct lagrangian {
    static constexpr int dim = 2;
    double m1 = 1.0, m2 = 1.0, l1 = 1.0, l2 = 1.0, g = 9.81, k = 0.0;

    template <class T>
    T operator()(const tvec<T, 2>& q, const tvec<T, 2>& v) const {
        using std::cos;
        const T kinetic = 0.5 * (m1 + m2) * l1 * l1 * v(0) * v(0) +
                          0.5 * m2 * l2 * l2 * v(1) * v(1) +
                          m2 * l1 * l2 * v(0) * v(1) * cos(q(0) - q(1));
        const T d = q(1) - q(0);
        const T potential = -(m1 + m2) * g * l1 * cos(q(0)) - m2 * g * l2 * cos(q(1)) +
                            0.5 * k * (q(0) * q(0) + d * d);
        return kinetic - potential;
    }
};

/// The system, refusing non-positive masses or lengths and negative g or k.
inline lagrangian_system<lagrangian> make_system(const lagrangian& l) {
    auto positive = [](const char* what, double x) {
        if (!(std::isfinite(x) && x > 0.0))
            throw std::invalid_argument(
                std::string(what) + " must be a finite positive number, got " + std::to_string(x));
    };
    positive("m1", l.m1);
    positive("m2", l.m2);
    positive("l1", l.l1);
    positive("l2", l.l2);
    if (!(std::isfinite(l.g) && l.g >= 0.0))
        throw std::invalid_argument("gravity must be finite and >= 0, got " + std::to_string(l.g));
    if (!(std::isfinite(l.k) && l.k >= 0.0))
        throw std::invalid_argument("joint stiffness must be finite and >= 0, got " +
                                    std::to_string(l.k));
    return lagrangian_system<lagrangian>(l);
}

} // namespace varsym::double_pendulum
