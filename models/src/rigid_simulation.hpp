// models/src/rigid_simulation.hpp: the simulation of a rigid body on SO(3) by the Lie group
// variational integrator (varsym/lie/lgvi.hpp), for the models rigid-body, top and pendulum-3d
// (rigid_bodies.cpp). Private to the models layer.
#pragma once

#include <memory>
#include <optional>

#include "varsym/lie/rigid_body.hpp"
#include "varsym/models/simulation.hpp"
#include "varsym/problems/heavy_top.hpp"

namespace varsym::models::detail {

/// A rigid body, its start and what its run shows.
struct rigid_setup {
    lie::rigid_body body;
    lie::body_state x0;
    int order = 4;       ///< of the Lie group integrator: 2, 4 or 6
    bool matrix = false; ///< also show R_11..R_33
    /// The closed forms where they exist: the free symmetric body's motion, the symmetric
    /// heavy top's nutation θ(t).
    std::optional<lie::free_symmetric_motion> free;
    std::optional<heavy_top::nutation> nutation;
};

/// The simulation of `r` with step options o (their scheme is not used: the integrator is lgvi of
/// r.order; Newton's options are). Its q is the z-x-z Euler angles (θ, φ, ψ) of R, p the body
/// angular momentum Π; its rows show the quaternion and Ω; it saves R and Π (9 and 3 values)
/// with their low-order parts. No tangent map, no dense output.
std::unique_ptr<simulation> simulate_rigid(const rigid_setup& r, const step_options& o);

/// The integrator of order `order`: label "lgvi-ORDER", its order and step limit.
own_integrator lgvi_integrator(int order);

} // namespace varsym::models::detail
