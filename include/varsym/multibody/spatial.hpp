// varsym/multibody/spatial.hpp: spatial vector algebra in Featherstone's notation (Rigid Body
// Dynamics Algorithms, 2008, ch. 2), in world coordinates: a motion vector is (ω; v_O), the
// angular velocity and the velocity of the body-fixed point at the world origin O; a force
// vector is (n_O; f), the moment about O and the force. Rigid poses, URDF's roll-pitch-yaw,
// and spatial inertias of a body of mass m, centre of mass c and inertia I_c about it.
#pragma once

#include <cmath>

#include <Eigen/Core>

namespace varsym::multibody {

using vec3 = Eigen::Vector3d;
using mat3 = Eigen::Matrix3d;
using vec6 = Eigen::Matrix<double, 6, 1>;
using mat6 = Eigen::Matrix<double, 6, 6>;
using row6 = Eigen::Matrix<double, 1, 6>;

/// The cross-product matrix: skew(a) b = a × b.
inline mat3 skew(const vec3& a) {
    mat3 s;
    s << 0.0, -a(2), a(1), a(2), 0.0, -a(0), -a(1), a(0), 0.0;
    return s;
}

/// Motion cross product m × n (Featherstone eq. 2.31): the rate of change of the motion n
/// moving with velocity m.
inline vec6 cross_motion(const vec6& m, const vec6& n) {
    vec6 r;
    const vec3 w = m.head<3>(), v = m.tail<3>();
    r.head<3>() = w.cross(n.head<3>());
    r.tail<3>() = w.cross(n.tail<3>()) + v.cross(n.head<3>());
    return r;
}

/// Force cross product m ×* f (eq. 2.32): the rate of change of the force f moving with m;
/// m ×* = −(m ×)ᵀ.
inline vec6 cross_force(const vec6& m, const vec6& f) {
    vec6 r;
    const vec3 w = m.head<3>(), v = m.tail<3>();
    r.head<3>() = w.cross(f.head<3>()) + v.cross(f.tail<3>());
    r.tail<3>() = w.cross(f.tail<3>());
    return r;
}

/// A rigid pose: a point x of the frame is at rotation · x + origin in the frame it is given in.
struct pose {
    mat3 rotation = mat3::Identity();
    vec3 origin = vec3::Zero();

    /// This pose followed by `local` (local given in this pose's frame).
    [[nodiscard]] pose operator*(const pose& local) const {
        return {rotation * local.rotation, rotation * local.origin + origin};
    }
    [[nodiscard]] vec3 point(const vec3& x) const { return rotation * x + origin; }
};

/// URDF's rpy: fixed-axis rotations about x (roll), then y (pitch), then z (yaw):
/// R = R_z(yaw) R_y(pitch) R_x(roll).
inline mat3 roll_pitch_yaw(const vec3& rpy) {
    const double cr = std::cos(rpy(0)), sr = std::sin(rpy(0));
    const double cp = std::cos(rpy(1)), sp = std::sin(rpy(1));
    const double cy = std::cos(rpy(2)), sy = std::sin(rpy(2));
    mat3 r;
    r << cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr, //
        sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr,  //
        -sp, cp * sr, cp * cr;
    return r;
}

/// The rotation by angle θ about the unit axis a (Rodrigues).
inline mat3 axis_angle(const vec3& a, double theta) {
    const double c = std::cos(theta), s = std::sin(theta);
    const mat3 k = skew(a);
    return mat3::Identity() + s * k + (1.0 - c) * k * k;
}

/// The spatial inertia (eq. 2.63) of mass m with centre of mass c and rotational inertia ic
/// about c, all in one frame: [[ic + m c×c×ᵀ, m c×], [m c×ᵀ, m 1]].
inline mat6 spatial_inertia(double m, const vec3& c, const mat3& ic) {
    const mat3 cx = skew(c);
    mat6 i;
    i.topLeftCorner<3, 3>() = ic + m * cx * cx.transpose();
    i.topRightCorner<3, 3>() = m * cx;
    i.bottomLeftCorner<3, 3>() = m * cx.transpose();
    i.bottomRightCorner<3, 3>() = m * mat3::Identity();
    return i;
}

} // namespace varsym::multibody
