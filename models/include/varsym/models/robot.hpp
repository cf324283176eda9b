// varsym/models/robot.hpp: robots read from URDF files into a multibody model
// (varsym/multibody/model.hpp), and the model of the models layer that simulates one by the
// general engine with the recursive derivatives: every command, ensembles and Python run it like
// a built-in model. What is read and what is refused: docs/robots.md.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "varsym/models/model.hpp"
#include "varsym/multibody/model.hpp"

namespace varsym::models {

/// A URDF file (or text) that cannot be read as a robot varsym simulates: one line naming the
/// file, the element (and its line) and what is wrong.
class urdf_error : public std::invalid_argument {
  public:
    using std::invalid_argument::invalid_argument;
};

/// Reads a URDF robot: revolute, continuous and prismatic joints become the coordinates, in
/// depth-first order from the root link (children in file order); fixed joints merge their
/// child's mass properties into the parent exactly; gravity (0, 0, −9.81) m/s². Throws
/// urdf_error for a missing or malformed file and for what docs/robots.md lists as refused.
std::shared_ptr<const multibody::model> load_urdf(const std::string& path);
/// The same from the XML text; `source` names it in messages.
std::shared_ptr<const multibody::model> parse_urdf(std::string_view xml,
                                                   const std::string& source = "<urdf>");

/// The model `urdf` of the robot r: its parameters gravity (magnitude along −z, m/s²),
/// no_damping (leave the URDF's joint damping out), move_time and no_gravity_compensation of the
/// PD controller; lists kp, kd (per joint; none: no controller), target (joint positions; none:
/// hold the start) and torque (constant joint torques). `torques` (empty: none): joint torques
/// typed as expressions in t, the joints' names and their velocities NAME_dot, one per joint
/// [N m or N] (throws expr::parse_error or std::invalid_argument for a bad one, or for both
/// these and the list torque given). Start: q0 (0) and v0 (0) or p0, in the joints' order.
/// Columns: energy, work, energy_balance, limit_violations (the joints outside their position
/// limits at that row).
model robot_model(std::shared_ptr<const multibody::model> r,
                  const std::vector<std::string>& torques = {});

/// The actuated joints of a robot (their indices in q): those whose URDF effort is positive.
/// robot_model's optimal control has one input per actuated joint, its torque (force),
/// bounded by the effort; its `limits` are the joints' position limits and efforts.
std::vector<int> actuated_joints(const multibody::model& r);

/// The parameters and lists that robot_model gives every robot (a one-joint robot's model), for
/// a front end that declares its options before it reads a URDF file.
const model& robot_options();

} // namespace varsym::models
