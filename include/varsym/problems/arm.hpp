// varsym/problems/arm.hpp: an n-link planar serial robot arm: the linked pendulum
// (problems/linked_pendulum.hpp, absolute link angles θ from the downward vertical, any n at run
// time) driven at its joints by a PD controller that tracks a minimum-jerk move of the joint
// angles to a target (optionally with gravity compensation), with viscous joint damping.
//
// Joint angles φ = Bθ (φ_0 = θ_0, φ_i = θ_i − θ_{i−1}); a joint torque τ_i acts between links
// i−1 and i, so the generalized force on θ is Bᵀτ (the virtual work τ·δφ = Bᵀτ·δθ). With
// joint gains K_p, K_d and damping C (diagonal, per joint),
//   f(θ, θ̇, t) = Bᵀ[K_p (r(t) − Bθ) + K_d (ṙ(t) − Bθ̇) − C Bθ̇] + τ_g(θ),
// i.e. the library's pd_controller with gains BᵀK B tracking B⁻¹r, and rayleigh_damping BᵀCB
// (systems/forcing.hpp). τ_g(θ) = −∂L/∂θ(θ, 0) holds the arm still against gravity.
// Units: N·m/rad (K_p), N·m·s/rad (K_d, C), rad, s. The energy balance E(t) − E(0) = W(t), the
// work of damping and controller, is what a run checks.
#pragma once

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "varsym/problems/linked_pendulum.hpp"
#include "varsym/systems/forcing.hpp"

namespace varsym::arm {

using lagrangian = linked_pendulum::lagrangian<dynamic>;
using force = force_sum<rayleigh_damping<dynamic>, pd_controller<dynamic>>;

/// φ = Bθ: the joint angles of the absolute link angles.
inline mat<dynamic> joint_map(int n) {
    mat<dynamic> b = mat<dynamic>::Identity(n, n);
    for (int i = 1; i < n; ++i)
        b(i, i - 1) = -1.0;
    return b;
}

/// The minimum-jerk move from `from` to `to` over `duration` seconds (then held):
/// r = from + (to − from) σ(t/T), σ(s) = 10s³ − 15s⁴ + 6s⁵ (zero velocity and acceleration at
/// both ends; Flash & Hogan 1985).
struct minimum_jerk {
    vec<dynamic> from, to;
    double duration = 1.0;
    void operator()(double t, vec<dynamic>& r, vec<dynamic>& rate) const {
        const double s = std::clamp(t / duration, 0.0, 1.0);
        const double sigma = s * s * s * (10.0 - 15.0 * s + 6.0 * s * s);
        const double dsigma =
            (s <= 0.0 || s >= 1.0) ? 0.0 : 30.0 * s * s * (1.0 - s) * (1.0 - s) / duration;
        r = from + (to - from) * sigma;
        rate = (to - from) * dsigma;
    }
};

/// The controller and damping of an arm: per-joint gains and damping (n each, ≥ 0), the joint
/// reference (in joint angles), and whether to compensate gravity.
struct control {
    std::vector<double> kp, kd, damping;
    minimum_jerk reference;
    bool gravity_compensation = true;
};

/// The arm's force (damping + PD on the joints) for the Lagrangian l.
inline force make_force(const lagrangian& l, const control& c) {
    const int n = l.dimension();
    auto diagonal = [n](const std::vector<double>& x, const char* what) {
        if (static_cast<int>(x.size()) != n)
            throw std::invalid_argument(std::string("give one ") + what + " per joint (" +
                                        std::to_string(n) + "), got " + std::to_string(x.size()));
        for (double v : x)
            if (!(std::isfinite(v) && v >= 0.0))
                throw std::invalid_argument(std::string(what) + " must be finite and >= 0");
        return vec<dynamic>(Eigen::Map<const vec<dynamic>>(x.data(), n));
    };
    const mat<dynamic> b = joint_map(n);
    const mat<dynamic> bt = b.transpose();
    pd_controller<dynamic> pd;
    pd.kp = bt * diagonal(c.kp, "proportional gain").asDiagonal() * b;
    pd.kd = bt * diagonal(c.kd, "derivative gain").asDiagonal() * b;
    if (c.reference.from.size() != n || c.reference.to.size() != n)
        throw std::invalid_argument("the reference needs " + std::to_string(n) + " joint angles");
    if (!(std::isfinite(c.reference.duration) && c.reference.duration > 0.0))
        throw std::invalid_argument("the move's duration must be positive");
    // r̃ = B⁻¹r (B⁻¹: cumulative sums), ṙ̃ likewise: K̃_p(r̃ − θ) = BᵀK_p(r − Bθ).
    pd.reference = [ref = c.reference](double t, vec<dynamic>& r, vec<dynamic>& rate) {
        ref(t, r, rate);
        for (Eigen::Index i = 1; i < r.size(); ++i) {
            r(i) += r(i - 1);
            rate(i) += rate(i - 1);
        }
    };
    if (c.gravity_compensation) pd.compensate(l);
    const rayleigh_damping<dynamic> damping(
        mat<dynamic>(bt * diagonal(c.damping, "damping coefficient").asDiagonal() * b));
    return force(damping, std::move(pd));
}

} // namespace varsym::arm
