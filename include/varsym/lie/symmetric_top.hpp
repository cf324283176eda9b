// varsym/lie/symmetric_top.hpp: the rigid-body state (R, Π) of a top in the Euler-angle
// coordinates of problems/heavy_top.hpp, and through them the closed-form nutation of the
// symmetric heavy top (Lagrange top) for the Lie group integrator.
#pragma once

#include <stdexcept>

#include "varsym/lie/rigid_body.hpp"
#include "varsym/problems/heavy_top.hpp"

namespace varsym::lie {

/// (θ, φ, ψ; p_θ, p_φ, p_ψ) of (R, Π), with the z-x-z angles of so3::euler_angles. The momenta
/// conjugate to the angles are Π · ∂Ω/∂(θ̇, φ̇, ψ̇) (so3::body_rate):
///   p_θ = Π₁ cos ψ − Π₂ sin ψ,  p_φ = Π · Rᵀe₃ = e₃ · RΠ,  p_ψ = Π₃.
inline phase_state<3> euler_state(const body_state& x) {
    const auto [theta, phi, psi] = so3::euler_angles(x.R);
    const vec3& p = x.pi;
    return {vec<3>{theta, phi, psi},
            vec<3>{p(0) * std::cos(psi) - p(1) * std::sin(psi), x.R.row(2).dot(p), p(2)}};
}

/// The Euler-angle Lagrangian of a body symmetric about its e₃ with its centre of mass on it:
/// I₁ = J₁₁, I₃ = J₃₃, mgl = W ρ₃.
inline heavy_top::lagrangian euler_lagrangian(const rigid_body& b) {
    if (!b.symmetric_about_e3())
        throw std::invalid_argument(
            "the Euler-angle top needs a body symmetric about its e3 with the centre of mass on "
            "that axis");
    return {b.inertia()(0, 0), b.inertia()(2, 2), b.weight() * b.com()(2)};
}

/// The closed-form θ(t) of a symmetric top started at x (heavy_top::nutation): needs mgl > 0
/// and an axis that does not reach the vertical.
inline heavy_top::nutation nutation_of(const rigid_body& b, const body_state& x) {
    if (!(b.weight() * b.com()(2) > 0.0))
        throw std::invalid_argument("the closed-form nutation needs the centre of mass above the "
                                    "fixed point on the axis (W rho_3 > 0)");
    const phase_state<3> e = euler_state(x);
    const double theta_dot = e.p(0) / b.inertia()(0, 0); // p_θ = I₁ θ̇
    return {euler_lagrangian(b), b.energy(x), e.p(1), e.p(2), e.q(0), theta_dot};
}

} // namespace varsym::lie
