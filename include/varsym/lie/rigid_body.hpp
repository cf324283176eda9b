// varsym/lie/rigid_body.hpp: a rigid body turning about a fixed point (or its centre of mass),
// free or in uniform gravity: the free rigid body, the heavy top, the 3D pendulum.
//
// Units and conventions (docs/rigid_bodies.md): the attitude R ∈ SO(3) maps body-frame vectors
// to the space frame; e₃ of the space frame points up and gravity pulls along −e₃. J is the
// inertia tensor about the fixed point in the body frame [kg m²], ρ the centre of mass in the
// body frame, measured from the fixed point [m], W = m g the weight [N]. The state is (R, Π),
// Π = JΩ the body angular momentum [kg m²/s], Ω the body angular velocity [rad/s].
//   L(R, Ω) = ½ Ωᵀ J Ω − U(R),   U(R) = W e₃ᵀ R ρ                                      (R1)
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "varsym/lie/so3.hpp"

namespace varsym::lie {

using so3::mat3;
using so3::vec3;

/// A point (R, Π) of T*SO(3) in body coordinates.
struct body_state {
    mat3 R = mat3::Identity();
    vec3 pi = vec3::Zero();
};

class rigid_body {
  public:
    rigid_body() : rigid_body(mat3::Identity()) {}
    /// Refuses (std::invalid_argument) a J that is not symmetric positive definite, whose principal
    /// moments break the triangle inequality I_i ≤ I_j + I_k (no body has them), or a weight that
    /// is negative or not finite.
    explicit rigid_body(const mat3& inertia, const vec3& com = vec3::Zero(), double weight = 0.0)
        : j_(inertia), com_(com), weight_(weight) {
        if (!j_.allFinite() || !com_.allFinite() || !std::isfinite(weight_) || weight_ < 0.0)
            throw std::invalid_argument(
                "the inertia, centre of mass and weight must be finite (weight >= 0)");
        if ((j_ - j_.transpose()).cwiseAbs().maxCoeff() > 1e-12 * j_.cwiseAbs().maxCoeff())
            throw std::invalid_argument("the inertia tensor must be symmetric");
        const Eigen::SelfAdjointEigenSolver<mat3> eig(j_);
        const vec3 m = eig.eigenvalues(); // ascending
        if (!(m(0) > 0.0))
            throw std::invalid_argument("the inertia tensor must be positive definite");
        if (m(2) > (m(0) + m(1)) * (1.0 + 1e-12))
            throw std::invalid_argument(
                "the principal moments of inertia must satisfy the triangle inequality I_max <= "
                "I_1 + I_2 of every rigid body, got " +
                std::to_string(m(0)) + ", " + std::to_string(m(1)) + ", " + std::to_string(m(2)));
        j_inv_ = j_.inverse();
        j_min_ = m(0);
    }

    [[nodiscard]] const mat3& inertia() const { return j_; }
    [[nodiscard]] const vec3& com() const { return com_; }
    [[nodiscard]] double weight() const { return weight_; }
    [[nodiscard]] double smallest_moment() const { return j_min_; }
    [[nodiscard]] bool has_gravity() const { return weight_ != 0.0 && com_.norm() != 0.0; }

    /// Ω = J⁻¹Π.
    [[nodiscard]] vec3 omega(const vec3& pi) const { return j_inv_ * pi; }
    /// U(R) = W e₃ᵀ R ρ: e₃ᵀR is R's third row.                                        (R1)
    [[nodiscard]] double potential(const mat3& r) const { return weight_ * r.row(2).dot(com_); }
    /// The moment of gravity about the fixed point, in the body frame: M = W (Rᵀe₃) × ρ, the
    /// generalized force −∂U/∂η of a variation δR = R η̂.                               (R2)
    [[nodiscard]] vec3 moment(const mat3& r) const {
        return weight_ * vec3(r.row(2).transpose()).cross(com_);
    }
    /// E = ½ Πᵀ J⁻¹ Π + U(R).
    [[nodiscard]] double energy(const body_state& x) const {
        return 0.5 * x.pi.dot(j_inv_ * x.pi) + potential(x.R);
    }
    /// The angular momentum in the space frame, π = RΠ: conserved when there is no gravity, its
    /// vertical component π₃ always (gravity is symmetric about e₃).
    [[nodiscard]] static vec3 spatial_momentum(const body_state& x) { return x.R * x.pi; }

    /// Whether the body is symmetric about its e₃ with the centre of mass on that axis
    /// (J = diag(I₁, I₁, I₃), ρ = (0, 0, ℓ)): then Π₃, the spin, is conserved too.
    [[nodiscard]] bool symmetric_about_e3() const {
        const double tol = 1e-14 * j_.cwiseAbs().maxCoeff();
        const bool diagonal =
            std::abs(j_(0, 1)) <= tol && std::abs(j_(0, 2)) <= tol && std::abs(j_(1, 2)) <= tol;
        return diagonal && j_(0, 0) == j_(1, 1) && com_(0) == 0.0 && com_(1) == 0.0;
    }
    /// The highest frequency of the motion from x: the turning rate |Ω| and the small-swing
    /// frequency sqrt(W|ρ| / I_min), the larger.
    [[nodiscard]] double highest_frequency(const body_state& x) const {
        return std::max(omega(x.pi).norm(), std::sqrt(weight_ * com_.norm() / j_min_));
    }

  private:
    mat3 j_, j_inv_;
    vec3 com_;
    double weight_ = 0.0;
    double j_min_ = 1.0;
};

/// The exact motion of a free body symmetric about its e₃ (J = diag(I₁, I₁, I₃)): with the
/// spatial momentum π = R₀Π₀ and ν = (1/I₃ − 1/I₁) Π₃ (both constant),
///   R(t) = exp(t π̂ / I₁) R₀ exp(t ν ê₃),  Π(t) = R(t)ᵀ π,
/// since Ṙ = R (J⁻¹Π)^ = (π/I₁)^ R + ν R ê₃ (docs/rigid_bodies.md).
class free_symmetric_motion {
  public:
    free_symmetric_motion(const rigid_body& b, const body_state& x0)
        : r0_(x0.R), pi_(x0.R * x0.pi), i1_(b.inertia()(0, 0)),
          nu_((1.0 / b.inertia()(2, 2) - 1.0 / b.inertia()(0, 0)) * x0.pi(2)) {
        if (!b.symmetric_about_e3() || b.has_gravity())
            throw std::invalid_argument(
                "the closed form needs a free body symmetric about its e3 (I1 = I2)");
    }
    [[nodiscard]] body_state at(double t) const {
        body_state x;
        x.R = so3::exp(t / i1_ * pi_) * r0_ * so3::exp(vec3(0.0, 0.0, t * nu_));
        x.pi = x.R.transpose() * pi_;
        return x;
    }
    /// The period of Π(t) in the body frame (2π/|ν|; 0 if Π stands still there).
    [[nodiscard]] double period() const {
        return nu_ == 0.0 ? 0.0 : 2.0 * std::numbers::pi / std::abs(nu_);
    }

  private:
    mat3 r0_;
    vec3 pi_;
    double i1_, nu_;
};

} // namespace varsym::lie
