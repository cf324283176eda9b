// tests/lie/lie_support.hpp: the bodies and starts the rigid-body tests share.
#pragma once

#include <algorithm>
#include <cstddef>

#include "varsym/lie/lgvi.hpp"

namespace varsym::test {

using lie::body_state;
using lie::mat3;
using lie::rigid_body;
using lie::vec3;

inline mat3 diag(double a, double b, double c) {
    return vec3(a, b, c).asDiagonal().toDenseMatrix();
}

/// The `heavy-top` model's default top as a rigid body: I₁ = I₂ = 1, I₃ = 0.5 kg m², centre of
/// mass 1 m up the axis, weight 1 N (mgl = 1 J).
inline rigid_body symmetric_top() {
    return rigid_body(diag(1.0, 1.0, 0.5), vec3(0, 0, 1), 1.0);
}

/// The state of Euler angles (θ, φ, ψ) moving at rates (θ̇, φ̇, ψ̇).
inline body_state euler_start(const rigid_body& b, double theta, double phi, double psi,
                              double theta_dot, double phi_dot, double psi_dot) {
    body_state x;
    x.R = so3::from_euler(theta, phi, psi);
    x.pi = b.inertia() * so3::body_rate(theta, psi, theta_dot, phi_dot, psi_dot);
    return x;
}

/// The `heavy-top` default start: tilted 1 rad, φ̇ = 0.5, ψ̇ = 8 rad/s.
inline body_state top_start(const rigid_body& b) {
    return euler_start(b, 1.0, 0, 0, 0, 0.5, 8.0);
}

/// x after n steps of order `order` with h = t/n.
inline body_state run_body(const rigid_body& b, body_state x, double t, std::size_t n, int order) {
    lie::lgvi s(b, t / static_cast<double>(n), order);
    for (std::size_t k = 0; k < n; ++k)
        if (!s.step(x).converged) throw std::runtime_error("a rigid-body step did not converge");
    return x;
}

/// max(max |ΔR|, max |ΔΠ| / |Π|): the error of a state against a reference.
inline double state_error(const body_state& x, const body_state& ref) {
    return std::max((x.R - ref.R).cwiseAbs().maxCoeff(),
                    (x.pi - ref.pi).cwiseAbs().maxCoeff() / std::max(ref.pi.norm(), 1e-300));
}

} // namespace varsym::test
