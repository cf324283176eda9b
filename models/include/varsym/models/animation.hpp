// varsym/models/animation.hpp: a robot's motion as one self-contained HTML page, a 3-D
// animation that opens offline in any browser (three.js from Debian's libjs-three inlined, no
// network, no server). The links are drawn as the URDF's <visual> shapes (boxes, cylinders,
// spheres, and STL, OBJ and COLLADA meshes embedded in the page), placed by forward kinematics at
// each kept row; a link whose mesh cannot be found is drawn as capsules from its joint to its
// children's joints, with a warning on the page and in the result. Playback, camera and the URL
// options of the page: docs/robots.md ("Watching a motion").
#pragma once

#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "varsym/contact/geometry.hpp"
#include "varsym/models/figure.hpp"
#include "varsym/multibody/tree.hpp"

namespace varsym::models {

/// How an animation is made.
struct animation_options {
    /// The robot's URDF file, or empty: mesh filenames relative to it are found beside it, and
    /// `package://PKG/PATH` also in its directory's parents (the checkout of a description
    /// package holds PKG/PATH or PATH).
    std::string urdf;
    /// More directories for meshes, searched first: a `package://PKG/PATH` mesh is DIR/PKG/PATH
    /// or DIR/PATH, a relative one DIR/NAME.
    std::vector<std::string> mesh_path;
    /// Frames kept per second of simulated time: frame n is the first row at or after
    /// t0 + n/fps, and the last row is kept too; 0 keeps every row.
    double fps = 60.0;
    std::string title;    ///< shown on the page (default: the robot's name)
    std::string three_js; ///< three.js's directory (default: find_three_js())
    std::size_t max_mesh_bytes = std::size_t{64} << 20; ///< larger meshes are not embedded
    /// What the robot touches (robot_obstacles): drawn, and each frame's contact points (the
    /// robot's <collision> points within 1e-6 m of an obstacle) shown as red dots.
    std::vector<contact::obstacle> world;
    /// Per row of the motion (or none), the contact forces to draw as arrows from their points:
    /// six numbers each, the point [m] and the force [N] in the world frame. The arrows share one
    /// scale, the largest force a third of the scene's radius, which the page states.
    std::vector<std::vector<double>> forces;
};

/// What write_animation did.
struct animation_report {
    std::size_t frames = 0;            ///< rows kept
    std::uintmax_t bytes = 0;          ///< the page's size
    std::vector<std::string> warnings; ///< missing meshes and the like, also shown on the page
};

/// A page that cannot be made (std::invalid_argument: bad rows; std::runtime_error: three.js
/// missing, a file that cannot be written).
class animation_error : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

/// Writes the motion of robot r through the rows (t[k], q.row(k)) in the model's coordinates
/// (robot_coordinates(r), a free base's quaternion included) to `path` as an HTML page: written
/// to PATH.tmp and renamed, so a failure leaves no partial page. `names` labels q's columns on
/// the page (empty: robot_coordinates). Throws std::invalid_argument for rows of the wrong width,
/// times that decrease or any non-finite value, animation_error where three.js is missing or the
/// page cannot be written.
animation_report write_animation(std::shared_ptr<const multibody::tree> r,
                                 std::span<const double> t, const Eigen::MatrixXd& q,
                                 const std::string& path, const animation_options& options = {},
                                 const std::vector<std::string>& names = {});

/// Writes the motion of a built-in model drawn as figure f (model::drawing) through the rows
/// (t[k], q.row(k)) of its coordinates to `path`, as above; `names` labels q's columns (empty:
/// q1, q2, ...). The options' urdf, mesh_path, world and forces are a robot's and must be empty.
animation_report write_animation(const figure& f, std::span<const double> t,
                                 const Eigen::MatrixXd& q, const std::string& path,
                                 const animation_options& options = {},
                                 const std::vector<std::string>& names = {});

/// The directory holding three.min.js: $VARSYM_THREE_JS, else Debian's libjs-three
/// (/usr/share/javascript/three); throws animation_error saying how to install it.
std::string find_three_js(const std::string& given = "");

/// The row indices write_animation keeps of times t at `fps` frames per second (all at fps 0).
std::vector<std::size_t> animation_rows(std::span<const double> t, double fps);

} // namespace varsym::models
