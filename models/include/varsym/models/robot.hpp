// varsym/models/robot.hpp: robots read from URDF files into a multibody model
// (varsym/multibody/tree.hpp), and the model of the models layer that simulates one by the
// general engine with the recursive derivatives: every command, ensembles and Python run it like
// a built-in model. What is read and what is refused: docs/robots.md.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "varsym/contact/geometry.hpp"
#include "varsym/models/model.hpp"
#include "varsym/multibody/tree.hpp"
#include "varsym/optimal/end_function.hpp"

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
/// urdf_error for a missing or malformed file and for what docs/robots.md lists as refused,
/// and for anything but a regular file of at most max_urdf_bytes (a directory, a FIFO, a device).
/// With a floating `base` (tree::with_base) the root link moves too, and a robot of one link
/// without joints is taken (a free rigid body); its root link must carry mass.
std::shared_ptr<const multibody::tree>
load_urdf(const std::string& path, multibody::base_kind base = multibody::base_kind::fixed);
/// The longest URDF file load_urdf reads: 256 MiB (a 100 000-link chain takes about 50 MB).
inline constexpr std::uint64_t max_urdf_bytes = std::uint64_t{256} << 20;
/// The same from the XML text; `source` names it in messages.
std::shared_ptr<const multibody::tree>
parse_urdf(std::string_view xml, const std::string& source = "<urdf>",
           multibody::base_kind base = multibody::base_kind::fixed);
/// The base named by `word`: fixed, free or planar; throws std::invalid_argument otherwise.
multibody::base_kind base_of(const std::string& word);

/// The model `urdf` of the robot r: its parameters gravity (magnitude along −z, m/s²),
/// no_damping (leave the URDF's joint damping out), move_time and no_gravity_compensation of the
/// PD controller; lists kp, kd (per joint; none: no controller), target (joint positions; none:
/// hold the start) and torque (constant joint torques). `torques` (empty: none): joint torques
/// typed as expressions in t, the joints' names and their velocities NAME_dot, one per joint
/// [N m or N] (throws expr::parse_error or std::invalid_argument for a bad one, or for both
/// these and the list torque given). Start: q0 (0) and v0 (0) or p0, in the joints' order.
/// Columns: energy, work, energy_balance, limit_violations (the joints outside their position
/// limits at that row).
model robot_model(std::shared_ptr<const multibody::tree> r,
                  const std::vector<std::string>& torques = {});

/// The names of the coordinates of robot r's model: its joints (depth first from the root
/// link; not the mimic joints), after a planar base's base_x, base_z, base_ry or a free base's
/// base_x, base_y, base_z, base_qw, base_qx, base_qy, base_qz (a unit quaternion).
std::vector<std::string> robot_coordinates(const multibody::tree& r);

/// The actuated joints of a robot (their indices in q): those whose URDF effort is positive.
/// robot_model's optimal control has one input per actuated joint, its torque (force),
/// bounded by the effort; its `limits` are the joints' position limits, velocity limits (a
/// URDF velocity of 0: none) and efforts.
std::vector<int> actuated_joints(const multibody::tree& r);

/// The pose in the world of robot r's link (frame) `frame` at joint positions q; throws
/// std::invalid_argument for an unknown link (the message lists the links) or a q of wrong size.
multibody::pose frame_pose_at(const multibody::tree& r, const std::string& frame,
                              const Eigen::VectorXd& q);

/// A target for link `frame` of robot r at the end of an optimal motion
/// (optimal::control_problem::end_target): its origin at `position` [m, world frame] and, if
/// given, its orientation `rotation` (world from link). φ(q) = (o(q) − position; 2 sin(θ/2) n),
/// 3 or 6 rows: the origin's miss [m] and, for the rotation by θ about n between the target
/// orientation and the link's, 2 sin(θ/2) n (≈ θ n [rad] near the target, zero at θ = 0 only;
/// models/src/robot_target.cpp). Throws
/// std::invalid_argument for an unknown link, one fixed to the ground, a
/// non-finite position or a rotation that is not one.
std::shared_ptr<const optimal::end_function>
frame_target(std::shared_ptr<const multibody::tree> r, const std::string& frame,
             const Eigen::Vector3d& position,
             const std::optional<Eigen::Matrix3d>& rotation = std::nullopt);

/// How far link `frame` at q is from a target pose: the distance [m] between the origins and
/// the rotation angle [rad] between the orientations (0 without a target orientation).
struct frame_miss {
    double distance = 0.0, angle = 0.0;
};
frame_miss frame_target_miss(const multibody::tree& r, const std::string& frame,
                             const Eigen::VectorXd& q, const Eigen::Vector3d& position,
                             const std::optional<Eigen::Matrix3d>& rotation = std::nullopt);

/// What robot r touches in robot_model's simulation at parameter `values` and `given` lists
/// (in robot_model(r).parameters' and lists' order): the ground and the static boxes, or none
/// without contact; for drawing them (animation_options::world). q0: a state of the motion (the
/// model's coordinates), checked as the simulation checks its start. Throws
/// std::invalid_argument as the simulation would.
std::vector<contact::obstacle> robot_obstacles(std::shared_ptr<const multibody::tree> r,
                                               std::span<const double> values, const lists& given,
                                               const Eigen::VectorXd& q0);

/// The parameters and lists that robot_model gives every robot (a one-joint robot's model), for
/// a front end that declares its options before it reads a URDF file.
const model& robot_options();

} // namespace varsym::models
