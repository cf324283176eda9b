// varsym/multibody/spatial.hpp: spatial vector algebra in Featherstone's notation (Rigid Body
// Dynamics Algorithms, 2008, ch. 2), in world coordinates: a motion vector is (ω; v_O), the
// angular velocity and the velocity of the body-fixed point at the world origin O; a force
// vector is (n_O; f), the moment about O and the force. Rigid poses, URDF's roll-pitch-yaw,
// and spatial inertias of a body of mass m, centre of mass c and inertia I_c about it.
#pragma once

#include <cmath>
#include <type_traits>

#include <Eigen/Core>

namespace varsym::multibody {

/// The algebra over any scalar S: double, or a dual number for the exact derivatives of the
/// second derivatives (robot_lagrangian::third); the model's data stay double.
template <class S>
using vec3_of = Eigen::Matrix<S, 3, 1>;
template <class S>
using mat3_of = Eigen::Matrix<S, 3, 3>;
template <class S>
using vec6_of = Eigen::Matrix<S, 6, 1>;
template <class S>
using mat6_of = Eigen::Matrix<S, 6, 6>;
template <class S>
using row6_of = Eigen::Matrix<S, 1, 6>;
using vec3 = vec3_of<double>;
using mat3 = mat3_of<double>;
using vec6 = vec6_of<double>;
using mat6 = mat6_of<double>;
using row6 = row6_of<double>;

/// The cross-product matrix: skew(a) b = a × b.
template <class S>
mat3_of<S> skew(const vec3_of<S>& a) {
    mat3_of<S> s;
    s << S(0.0), -a(2), a(1), a(2), S(0.0), -a(0), -a(1), a(0), S(0.0);
    return s;
}

/// Motion cross product m × n (Featherstone eq. 2.31): the rate of change of the motion n
/// moving with velocity m.
template <class S>
vec6_of<S> cross_motion(const vec6_of<S>& m, const vec6_of<S>& n) {
    vec6_of<S> r;
    const vec3_of<S> w = m.template head<3>(), v = m.template tail<3>();
    r.template head<3>() = w.cross(n.template head<3>());
    r.template tail<3>() = w.cross(n.template tail<3>()) + v.cross(n.template head<3>());
    return r;
}

/// Force cross product m ×* f (eq. 2.32): the rate of change of the force f moving with m;
/// m ×* = −(m ×)ᵀ.
template <class S>
vec6_of<S> cross_force(const vec6_of<S>& m, const vec6_of<S>& f) {
    vec6_of<S> r;
    const vec3_of<S> w = m.template head<3>(), v = m.template tail<3>();
    r.template head<3>() = w.cross(f.template head<3>()) + v.cross(f.template tail<3>());
    r.template tail<3>() = w.cross(f.template tail<3>());
    return r;
}

/// A rigid pose: a point x of the frame is at rotation · x + origin in the frame it is given in.
template <class S>
struct basic_pose {
    mat3_of<S> rotation = mat3_of<S>::Identity();
    vec3_of<S> origin = vec3_of<S>::Zero();

    /// This pose followed by `local` (local given in this pose's frame).
    [[nodiscard]] basic_pose operator*(const basic_pose& local) const {
        return {rotation * local.rotation, rotation * local.origin + origin};
    }
    /// The point x of the frame (x in any scalar that converts to S).
    template <class X>
    [[nodiscard]] vec3_of<S> point(const Eigen::MatrixBase<X>& x) const {
        return rotation * x.template cast<S>() + origin;
    }
    /// The same pose over the scalar T.
    template <class T>
    [[nodiscard]] basic_pose<T> cast() const {
        return {rotation.template cast<T>(), origin.template cast<T>()};
    }
};
using pose = basic_pose<double>;

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
template <class S = double>
mat3_of<S> axis_angle(const vec3& a, const S& theta) {
    using std::cos, std::sin;
    S c, s;
    if constexpr (std::is_same_v<S, double>)
        ::sincos(theta, &s, &c); // one call for both (glibc)
    else {
        c = cos(theta);
        s = sin(theta);
    }
    // 1 + s K + (1 − c) K² entry by entry, with K² = a aᵀ − (a·a) 1.
    const S u = S(1.0) - c, aa(a.squaredNorm());
    mat3_of<S> r;
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i)
            r(i, j) = u * S(a(i) * a(j));
    for (int i = 0; i < 3; ++i)
        r(i, i) += S(1.0) - u * aa;
    r(0, 1) -= s * a(2);
    r(1, 0) += s * a(2);
    r(0, 2) += s * a(1);
    r(2, 0) -= s * a(1);
    r(1, 2) -= s * a(0);
    r(2, 1) += s * a(0);
    return r;
}

/// The spatial inertia (eq. 2.63) of mass m with centre of mass c and rotational inertia ic
/// about c, all in one frame: [[ic + m c×c×ᵀ, m c×], [m c×ᵀ, m 1]], written into i.
template <class S>
void set_spatial_inertia(mat6_of<S>& i, double m, const vec3_of<S>& c,
                         const std::type_identity_t<mat3_of<S>>& ic) {
    const mat3_of<S> cx = skew(c);
    const S ms(m);
    // c× c×ᵀ = (c·c) 1 − c cᵀ
    i.template topLeftCorner<3, 3>() = ic - ms * (c * c.transpose());
    i.template topLeftCorner<3, 3>().diagonal().array() += ms * c.squaredNorm();
    i.template topRightCorner<3, 3>() = ms * cx;
    i.template bottomLeftCorner<3, 3>() = ms * cx.transpose();
    i.template bottomRightCorner<3, 3>() = ms * mat3_of<S>::Identity();
}

/// set_spatial_inertia's matrix, returned.
template <class S>
mat6_of<S> spatial_inertia(double m, const vec3_of<S>& c,
                           const std::type_identity_t<mat3_of<S>>& ic) {
    mat6_of<S> i;
    set_spatial_inertia<S>(i, m, c, ic);
    return i;
}

} // namespace varsym::multibody
