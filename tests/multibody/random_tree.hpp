// tests/multibody/random_tree.hpp: a random branched tree of revolute and prismatic joints,
// with random placements, axes, masses, centres of mass and full inertia tensors, for the
// multibody tests.
#pragma once

#include <random>
#include <string>

#include "varsym/multibody/spatial.hpp"
#include "varsym/multibody/tree.hpp"

namespace varsym::test {

/// A random positive definite inertia about the centre of mass that meets the triangle
/// inequality: principal moments from random (a, b, c) ≥ 0 as (b + c, a + c, a + b), rotated.
inline multibody::mat3 random_inertia(std::mt19937& g) {
    std::uniform_real_distribution<double> u(0.05, 1.0);
    const double a = u(g), b = u(g), c = u(g);
    const multibody::mat3 r =
        multibody::roll_pitch_yaw(multibody::vec3(3.0 * u(g), 3.0 * u(g), 3.0 * u(g)));
    return r * multibody::vec3(b + c, a + c, a + b).asDiagonal() * r.transpose();
}

/// Seven bodies: a branched tree (0 ← 1 ← 2, 1 ← 3 ← 4, 0 ← 5 ← 6), bodies 2 and 5 on prismatic
/// joints, every placement, axis, mass and centre of mass random.
inline multibody::tree random_tree(unsigned seed) {
    std::mt19937 g(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    multibody::tree m;
    const int parents[] = {-1, 0, 1, 1, 3, 0, 5};
    for (int i = 0; i < 7; ++i) {
        multibody::body b;
        b.name = "j" + std::to_string(i);
        b.link = "l" + std::to_string(i);
        b.kind =
            (i == 2 || i == 5) ? multibody::joint_kind::prismatic : multibody::joint_kind::revolute;
        b.placement.rotation =
            multibody::roll_pitch_yaw(multibody::vec3(3 * u(g), 3 * u(g), 3 * u(g)));
        b.placement.origin = multibody::vec3(u(g), u(g), u(g)) * 0.5;
        b.axis = multibody::vec3(u(g), u(g), u(g)).normalized();
        b.mass = 1.0 + u(g) * 0.5;
        b.com = multibody::vec3(u(g), u(g), u(g)) * 0.3;
        b.inertia = random_inertia(g);
        m.add_body(parents[i], b);
    }
    m.gravity = multibody::vec3(0.3, -0.2, -9.81);
    return m;
}

/// random_tree with three mimic joints (model.hpp) after its seven coordinates: body 7, a
/// revolute joint on body 4 following the prismatic q_2 (θ = −0.7 q_2 + 0.2); body 8, a
/// prismatic joint on body 7 following q_0 (1.3 q_0 − 0.1); body 9, a revolute joint on body 6
/// following q_6 (0.5 q_6). `coupled` false: the same ten bodies, all coordinates.
inline multibody::tree mimic_tree(bool coupled) {
    multibody::tree m = random_tree(9);
    std::mt19937 g(21);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const int parents[] = {4, 7, 6};
    for (int k = 0; k < 3; ++k) {
        multibody::body b = m.bodies[static_cast<std::size_t>(k + 1)]; // its mass properties
        b.name = "mimic" + std::to_string(k);
        b.parent = parents[k];
        b.kind = k == 1 ? multibody::joint_kind::prismatic : multibody::joint_kind::revolute;
        b.placement.origin = multibody::vec3(u(g), u(g), u(g)) * 0.5;
        b.axis = multibody::vec3(u(g), u(g), u(g)).normalized();
        m.bodies.push_back(b);
    }
    if (coupled) m.mimics = {{2, -0.7, 0.2}, {0, 1.3, -0.1}, {6, 0.5, 0.0}};
    return m;
}

} // namespace varsym::test
