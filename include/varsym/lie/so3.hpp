// varsym/lie/so3.hpp: the rotation group SO(3): the hat map, the Cayley chart in which the Lie
// group variational integrator solves its step, unit quaternions and Euler angles.
//
// Conventions (docs/rigid_bodies.md): a rotation R maps body-frame vectors to the space frame,
// x_space = R x_body. Quaternions are (w, x, y, z), scalar first, of the same rotation, with
// w ≥ 0. Euler angles are (θ, φ, ψ) of the z-x-z convention, R = R_z(φ) R_x(θ) R_z(ψ), as the
// Euler-angle model `heavy-top` uses them: θ is the tilt of the body's e₃ from the space e₃.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <Eigen/Dense>
#include <Eigen/Geometry>

namespace varsym::so3 {

using vec3 = Eigen::Vector3d;
using mat3 = Eigen::Matrix3d;

/// The hat map: hat(a) b = a × b (in any scalar type).
template <class T>
Eigen::Matrix<T, 3, 3> hat(const Eigen::Matrix<T, 3, 1>& a) {
    Eigen::Matrix<T, 3, 3> m;
    m << T(0), -a(2), a(1), a(2), T(0), -a(0), -a(1), a(0), T(0);
    return m;
}

/// The inverse of the hat map on the skew-symmetric part: vee(A − Aᵀ) for any A, halved.
inline vec3 vee_skew(const mat3& a) {
    return 0.5 * vec3(a(2, 1) - a(1, 2), a(0, 2) - a(2, 0), a(1, 0) - a(0, 1));
}

/// The Cayley chart, as an increment: cay(f) = (I + f̂)(I − f̂)⁻¹ = I + G with
///   G = 2/(1 + fᵀf) (f̂ + f̂²),  f̂² = f fᵀ − (fᵀf) I.
/// I + G is orthogonal for every f, and G is computed with relative round-off ε|G|, so adding it
/// to I loses nothing: the orthogonality error of R·cay(f) is that of R plus O(ε|f|).
/// The Lie group integrator evaluates it in extended precision (T = long double).
template <class T>
Eigen::Matrix<T, 3, 3> cayley_increment(const Eigen::Matrix<T, 3, 1>& f) {
    const T ff = f.squaredNorm();
    Eigen::Matrix<T, 3, 3> sq = f * f.transpose();
    sq.diagonal().array() -= ff;
    return (T(2) / (T(1) + ff)) * (hat(f) + sq);
}

/// ‖RᵀR − I‖ in the Frobenius norm: how far R is from SO(3).
inline double orthogonality_error(const mat3& r) {
    return (r.transpose() * r - mat3::Identity()).norm();
}

/// The unit quaternion (w, x, y, z) of a rotation matrix, with w ≥ 0.
inline std::array<double, 4> quaternion(const mat3& r) {
    Eigen::Quaterniond q(r); // Shepperd's method (Eigen/Geometry)
    const double s = q.w() < 0.0 ? -1.0 : 1.0;
    return {s * q.w(), s * q.x(), s * q.y(), s * q.z()};
}

/// The rotation matrix of the unit quaternion (w, x, y, z).
inline mat3 from_quaternion(double w, double x, double y, double z) {
    return Eigen::Quaterniond(w, x, y, z).toRotationMatrix();
}

/// R = R_z(φ) R_x(θ) R_z(ψ) of the z-x-z Euler angles (θ, φ, ψ).
inline mat3 from_euler(double theta, double phi, double psi) {
    using Eigen::AngleAxisd;
    return (AngleAxisd(phi, vec3::UnitZ()) * AngleAxisd(theta, vec3::UnitX()) *
            AngleAxisd(psi, vec3::UnitZ()))
        .toRotationMatrix();
}

/// The z-x-z Euler angles (θ, φ, ψ) of R. Where θ = 0 or π only φ ± ψ is defined: there
/// (sin θ = 0 to round-off) ψ = 0 and φ is the angle of R's first column, so that
/// from_euler(θ, φ, ψ) is R again.
inline std::array<double, 3> euler_angles(const mat3& r) {
    const double theta = std::acos(std::clamp(r(2, 2), -1.0, 1.0));
    if (std::hypot(r(0, 2), r(1, 2)) <= 4.0 * std::numeric_limits<double>::epsilon())
        return {theta, std::atan2(r(1, 0), r(0, 0)), 0.0};
    return {theta, std::atan2(r(0, 2), -r(1, 2)), std::atan2(r(2, 0), r(2, 1))};
}

/// The body angular velocity Ω of z-x-z Euler angles (θ, φ, ψ) moving at rates (θ̇, φ̇, ψ̇).
inline vec3 body_rate(double theta, double psi, double theta_dot, double phi_dot, double psi_dot) {
    const double st = std::sin(theta), ct = std::cos(theta);
    const double sp = std::sin(psi), cp = std::cos(psi);
    return {phi_dot * st * sp + theta_dot * cp, phi_dot * st * cp - theta_dot * sp,
            phi_dot * ct + psi_dot};
}

/// exp(â) for a rotation vector a (angle |a| about a/|a|).
inline mat3 exp(const vec3& a) {
    const double angle = a.norm();
    if (angle == 0.0) return mat3::Identity();
    return Eigen::AngleAxisd(angle, a / angle).toRotationMatrix();
}

} // namespace varsym::so3
