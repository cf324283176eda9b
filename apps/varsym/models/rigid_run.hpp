// apps/varsym/models/rigid_run.hpp: the run of a rigid-body model (model_rigid.cpp): the Lie group
// integrator stepped with the run's output, checkpoints, energy watch and signals (run_log).
#pragma once

#include <string>

#include "models.hpp"
#include "varsym/lie/rigid_body.hpp"

namespace varsym::cli {

struct rigid_run {
    lie::rigid_body body;
    lie::body_state x0;
    int order = 4;       ///< of the Lie group integrator: 2, 4, 6
    bool matrix = false; ///< also write R_11..R_33
    std::string name;    ///< the model's name, for messages
};

/// Streams the CSV of run `r`: step,t,q_w,q_x,q_y,q_z,Omega_1..3,energy, the conserved
/// quantities, the exact values where a closed form exists, orthogonality, and R with --matrix.
/// The step plan comes from the closed form's period where there is one, else from --time and
/// --steps (default_time, default_steps).
void run_rigid_body(const run_setup& s, const rigid_run& r, double default_time,
                    long long default_steps);

} // namespace varsym::cli
