// tests/multibody/reference_lagrangian.hpp: a second implementation of a multibody model's
// Lagrangian that shares no code with varsym/multibody/algorithms.hpp: classical vectors
// (angular velocity, point velocities, rotation matrices, no spatial algebra),
//   L = Σ_i ½ m_i |v_{c,i}|² + ½ ω_iᵀ (R_i I_i R_iᵀ) ω_i + m_i g·c_i,
// written once for any scalar, so that varsym's forward-mode AD gives its exact first and
// second derivatives (at a compile-time dimension D).
#pragma once

#include <cmath>

#include <Eigen/Dense>

#include "varsym/multibody/tree.hpp"
#include "varsym/systems/lagrangian.hpp"

namespace varsym::test {

template <int D>
struct reference_lagrangian {
    static constexpr int dim = D;
    const multibody::tree* m = nullptr;

    template <class T>
    T operator()(const tvec<T, D>& q, const tvec<T, D>& qd) const {
        using std::cos;
        using std::sin;
        using m3 = Eigen::Matrix<T, 3, 3>;
        using v3 = Eigen::Matrix<T, 3, 1>;
        auto cross = [](const v3& a, const v3& b) {
            return v3(a(1) * b(2) - a(2) * b(1), a(2) * b(0) - a(0) * b(2),
                      a(0) * b(1) - a(1) * b(0));
        };
        const std::size_t n = m->bodies.size(); // D coordinates, and any mimic joints
        std::vector<m3> rot(n);
        std::vector<v3> origin(n), omega(n), vel(n); // body origin, ω, origin's velocity
        T l(0.0);
        for (int i = 0; i < static_cast<int>(n); ++i) {
            // θ_i and θ̇_i: q_i, or multiplier · q_master + offset (model.hpp).
            const T th = m->joint_position(q, i), thd = m->joint_rate(qd, i);
            const auto& b = m->bodies[static_cast<std::size_t>(i)];
            m3 rp = m3::Identity();
            v3 pp = v3::Zero(), wp = v3::Zero(), vp = v3::Zero();
            if (b.parent >= 0) {
                const auto p = static_cast<std::size_t>(b.parent);
                rp = rot[p];
                pp = origin[p];
                wp = omega[p];
                vp = vel[p];
            }
            const m3 rj = rp * b.placement.rotation.cast<T>();
            const v3 pj = rp * b.placement.origin.cast<T>() + pp;
            const v3 a = rj * b.axis.cast<T>();
            v3 pi = pj;
            if (b.kind == multibody::joint_kind::revolute) {
                // Rotation about the joint axis: R(θ) = cos θ 1 + sin θ [a]× + (1 − cos θ) a aᵀ.
                const Eigen::Vector3d a0 = b.axis;
                m3 k;
                k << T(0.0), T(-a0(2)), T(a0(1)), T(a0(2)), T(0.0), T(-a0(0)), T(-a0(1)), T(a0(0)),
                    T(0.0);
                const m3 aa = (a0 * a0.transpose()).cast<T>();
                const m3 r = m3::Identity() * cos(th) + k * sin(th) + aa * (1.0 - cos(th));
                rot[static_cast<std::size_t>(i)] = rj * r;
                omega[static_cast<std::size_t>(i)] = wp + a * thd;
                vel[static_cast<std::size_t>(i)] = vp + cross(wp, pj - pp);
            } else {
                rot[static_cast<std::size_t>(i)] = rj;
                pi = pj + a * th;
                omega[static_cast<std::size_t>(i)] = wp;
                vel[static_cast<std::size_t>(i)] = vp + cross(wp, pi - pp) + a * thd;
            }
            origin[static_cast<std::size_t>(i)] = pi;
            const m3& r = rot[static_cast<std::size_t>(i)];
            const v3& w = omega[static_cast<std::size_t>(i)];
            const v3 c = r * b.com.cast<T>() + pi;
            const v3 vc = vel[static_cast<std::size_t>(i)] + cross(w, c - pi);
            const v3 iw = r * (b.inertia.cast<T>() * (r.transpose() * w));
            l += 0.5 * b.mass * vc.dot(vc) + 0.5 * w.dot(iw) + b.mass * m->gravity.cast<T>().dot(c);
        }
        return l;
    }
};

} // namespace varsym::test
