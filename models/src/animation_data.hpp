// models/src/animation_data.hpp: what an animation page holds (animation.cpp gathers it,
// animation_shapes.cpp finds the shapes and meshes, animation_page.cpp writes the page).
#pragma once

#include <array>
#include <cstdint>
#include <ostream>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "varsym/models/animation.hpp"

namespace varsym::models::animation_detail {

/// One drawn shape, fixed to a body (−1: the ground) at `offset` in its frame.
struct shape_record {
    int body = -1;
    int page_body = 0; ///< the page's index of its body (0: the ground)
    std::string kind;  ///< box, sphere, cylinder, capsule, mesh
    Eigen::Vector3d size = Eigen::Vector3d::Zero(); ///< as collision_shape; a mesh's scale
    multibody::pose offset;
    std::array<double, 4> rgba{0.7, 0.7, 0.7, -1.0}; ///< a < 0: the mesh's own colours
    int mesh = -1;                                   ///< into scene_shapes::meshes
};

/// A mesh file embedded in the page.
struct mesh_record {
    std::string format; ///< stl, obj, dae
    std::string bytes;
};

struct scene_shapes {
    std::vector<shape_record> shapes;
    std::vector<mesh_record> meshes;
    double extent = 0.0; ///< the largest shape's half size [m], for the camera
};

/// The shapes of robot r: its <visual> shapes with their meshes read, and capsules for each
/// body none of whose shapes can be drawn; what is missing is said in `warnings`.
scene_shapes collect_shapes(const multibody::tree& r, const animation_options& options,
                            std::vector<std::string>& warnings);

struct page_data {
    std::string title;
    std::vector<std::string> names;
    std::size_t bodies = 0;
    std::vector<double> times;
    std::vector<float> poses;  ///< per frame, per drawn body: x, y, z, qx, qy, qz, qw
    std::vector<float> values; ///< per frame, the coordinates
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    double radius = 1.0;
    std::vector<std::string> warnings;
    scene_shapes shapes;
    std::vector<contact::obstacle> world;    ///< drawn
    std::vector<float> touch;                ///< the contact points of every frame: x, y, z
    std::vector<std::uint32_t> touches;      ///< per frame, how many
    double floor = 0.0;                      ///< the grid's height where no plane is in `world`
    std::string note;                        ///< a line under the title (a figure's scale)
    std::vector<float> arrows;               ///< the contact forces of every frame: point, force
    std::vector<std::uint32_t> arrow_counts; ///< per frame, how many (or none at all)
    double arrow_scale = 0.0;                ///< an arrow's length per newton [m/N]
};

/// Throws std::invalid_argument where the motion has no rows, a value that is not finite or
/// times that decrease.
void check_motion(std::span<const double> t, const Eigen::MatrixXd& q);

/// Writes the page to `path` (through PATH.tmp, created exclusively, then renamed; never over
/// the URDF or a mesh directory of `options`) and returns its size; throws animation_error.
std::uintmax_t save_page(const page_data& page, const std::string& path,
                         const animation_options& options, const std::string& three);

/// Writes the HTML page, with three.js and its loaders read from directory `three`.
void write_page(std::ostream& out, const page_data& page, const std::string& three);

} // namespace varsym::models::animation_detail
