// varsym/models/figure.hpp: how a built-in model looks in 3-D (model::figure), for its animation
// page (models/animation.hpp): solid parts fixed to the model's bodies, and the bodies' poses at
// each state. Frames are right-handed with z up; lengths are in metres. A model whose lengths are
// not among its parameters (the heavy top's mgl) is drawn at a stated scale.
#pragma once

#include <array>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "varsym/multibody/spatial.hpp"

namespace varsym::models {

/// One solid of a figure, fixed to body `body` (−1: the ground) at `offset` in its frame. kind:
/// "box" (size: the sides), "sphere" (size(0): the radius), "cylinder" or "capsule" (size(0):
/// the radius, size(1): the length along the part's z; a capsule's between its end spheres'
/// centres), as multibody::collision_shape.
struct figure_part {
    std::string kind;
    int body = 0;
    multibody::vec3 size = multibody::vec3::Zero();
    multibody::pose offset;
    std::array<double, 4> rgba{0.7, 0.7, 0.7, 1.0}; ///< r, g, b, a in [0, 1]
};

/// A model drawn in 3-D: its parts and the poses of its `bodies` bodies at a state q (the model's
/// coordinates, as simulation::q gives them: a rigid body's z-x-z Euler angles).
struct figure {
    std::vector<figure_part> parts;
    int bodies = 1;
    int coordinates = 0; ///< q's size
    /// Writes each body's pose at q into `poses` (`bodies` of them).
    std::function<void(std::span<const double> q, std::span<multibody::pose> poses)> place;
    double floor = 0.0; ///< the height of the page's ground grid [m], below the figure's reach
    std::string scale;  ///< where the drawing's size is a choice, what it is (shown on the page)
};

/// Colours the built-in figures share.
namespace figure_colour {
inline constexpr std::array<double, 4> body{0.9, 0.5, 0.15, 1.0};  ///< a body or link
inline constexpr std::array<double, 4> rod{0.55, 0.58, 0.62, 1.0}; ///< a massless rod, a pivot
inline constexpr std::array<double, 4> red{0.85, 0.15, 0.15, 1.0};
inline constexpr std::array<double, 4> green{0.15, 0.65, 0.25, 1.0};
inline constexpr std::array<double, 4> blue{0.15, 0.35, 0.85, 1.0};
} // namespace figure_colour

/// A part of kind `kind` on body `body` at `at` in its frame, its z along `axis` (a nonzero
/// vector).
figure_part figure_solid(std::string kind, int body, const multibody::vec3& size,
                         const multibody::vec3& at, const std::array<double, 4>& rgba,
                         const multibody::vec3& axis = multibody::vec3::UnitZ());

/// A rigid body turning about a fixed point, drawn as a rod from the pivot to the centre of mass
/// c and a disc there across c (|c| > 0, with a blue mark on its rim to show the spin), or as the
/// box of uniform density with inertia J about the centre of mass (c = 0; coloured marks on its
/// faces along the principal axes 1, 2, 3: red, green, blue). Its one body's pose at q (z-x-z
/// Euler angles θ, φ, ψ) is R_z(φ) R_x(θ) R_z(ψ) at the origin.
figure rigid_figure(const multibody::mat3& inertia, const multibody::vec3& com);

/// A planar chain of n links in the x-z plane hanging from the origin: link i of length
/// lengths[i] at absolute angle q_i from the downward vertical, with a ball at its end whose
/// volume follows masses[i] (a massless end: none).
figure planar_links_figure(const std::vector<double>& lengths, const std::vector<double>& masses);

} // namespace varsym::models
