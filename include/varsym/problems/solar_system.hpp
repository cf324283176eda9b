// varsym/problems/solar_system.hpp: the outer solar system of Hairer, Lubich & Wanner, Geometric
// Numerical Integration, 2nd ed., §I.2.4 (data of their Table 2.1): the Sun, with the masses of
// the inner planets added to it, Jupiter, Saturn, Uranus, Neptune and Pluto, as a 6-body problem
// (d = 18), from their positions and velocities on 5 September 1994 at 0h00 GMT.
//
// Units and conventions: positions in astronomical units (AU), time in Earth days, masses
// relative to the Sun's, so G = 2.95912208286e-4 AU³/(M☉ day²); q = (q_Sun, q_Jupiter, …),
// p_i = m_i q̇_i. Heliocentric initial data (the Sun at rest at the origin): the centre of mass
// drifts uniformly, which the problem keeps as HLW do.
#pragma once

#include <array>
#include <string_view>

#include "varsym/problems/nbody.hpp"

namespace varsym::solar_system {

inline constexpr double gravitational_constant = 2.95912208286e-4; ///< AU³ / (M☉ day²)

struct body {
    std::string_view name;
    double mass;                ///< relative to the Sun
    std::array<double, 3> q, v; ///< AU, AU/day
};

/// HLW Table I.2.1.
inline constexpr std::array<body, 6> bodies{{
    {"Sun", 1.00000597682, {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}},
    {"Jupiter",
     0.000954786104043,
     {-3.5023653, -3.8169847, -1.5507963},
     {0.00565429, -0.00412490, -0.00190589}},
    {"Saturn",
     0.000285583733151,
     {9.0755314, -3.0458353, -1.6483708},
     {0.00168318, 0.00483525, 0.00192462}},
    {"Uranus",
     0.0000437273164546,
     {8.3101420, -16.2901086, -7.2521278},
     {0.00354178, 0.00137102, 0.00055029}},
    {"Neptune",
     0.0000517759138449,
     {11.4707666, -25.7294829, -10.8169456},
     {0.00288930, 0.00114527, 0.00039677}},
    {"Pluto",
     1.0 / 1.3e8,
     {-15.5387357, -25.2225594, -3.1902382},
     {0.00276725, -0.00170702, -0.00136504}},
}};

inline constexpr int dim = 3 * static_cast<int>(bodies.size());

/// Jupiter's orbital period in days (the scale `varsym bench` counts steps per).
inline constexpr double jupiter_period = 4332.59;

using system = separable_system<dim, nbody::gravity<dim>>;

inline std::vector<double> masses() {
    std::vector<double> m;
    for (const body& b : bodies)
        m.push_back(b.mass);
    return m;
}

/// L = ½ Σ m_i |q̇_i|² + G Σ_{i<j} m_i m_j / |q_i − q_j| (mass matrix diag(m_i I₃)).
inline system make_system() {
    vec<dim> diagonal;
    for (int i = 0; i < dim; ++i)
        diagonal(i) = bodies[static_cast<std::size_t>(i / 3)].mass;
    return system(mat<dim>(diagonal.asDiagonal()),
                  nbody::gravity<dim>{masses(), Eigen::Vector3d::Zero(), gravitational_constant});
}

/// (q, p) on 5 September 1994, p_i = m_i v_i.
inline phase_state<dim> initial_state() {
    phase_state<dim> x{vec<dim>::Zero(), vec<dim>::Zero()};
    for (std::size_t b = 0; b < bodies.size(); ++b)
        for (int k = 0; k < 3; ++k) {
            const auto i = static_cast<Eigen::Index>(3 * b) + k;
            x.q(i) = bodies[b].q[static_cast<std::size_t>(k)];
            x.p(i) = bodies[b].mass * bodies[b].v[static_cast<std::size_t>(k)];
        }
    return x;
}

/// The same system as a Lagrangian for automatic derivatives (the general engine's d = 18 case).
inline nbody::gravity_lagrangian<dim> lagrangian() {
    return {masses(), gravitational_constant};
}

} // namespace varsym::solar_system
