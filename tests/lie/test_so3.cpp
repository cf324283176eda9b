// tests/lie/test_so3.cpp: the rotation-group helpers against their definitions: the Cayley
// increment is orthogonal and matches (I + f̂)(I − f̂)⁻¹, quaternions and Euler angles round-trip,
// and body_rate is the Ω of Ω̂ = RᵀṘ (by central differences).
#include <numbers>

#include <gtest/gtest.h>

#include "varsym/lie/so3.hpp"

using namespace varsym::so3;

TEST(So3, CayleyIncrementIsTheCayleyTransformAndOrthogonal) {
    for (const vec3& f : {vec3(0.1, -0.2, 0.3), vec3(2.0, 1.0, -3.0), vec3(1e-9, 0.0, 2e-9)}) {
        const mat3 i = mat3::Identity();
        const mat3 direct = (i + hat(f)) * (i - hat(f)).inverse();
        const mat3 g = cayley_increment(f);
        EXPECT_LT((i + g - direct).norm(), 1e-15 * (1.0 + f.squaredNorm())) << f.transpose();
        EXPECT_LT(orthogonality_error(i + g), 4e-16);
        // The increment's own round-off is relative to |G|: (I+G)ᵀ(I+G) − I = G + Gᵀ + GᵀG.
        EXPECT_LT((g + g.transpose() + g.transpose() * g).norm(), 4e-16 * g.norm());
        EXPECT_NEAR((i + g).determinant(), 1.0, 1e-15);
    }
}

TEST(So3, HatIsTheCrossProduct) {
    const vec3 a(0.3, -1.2, 2.0), b(-0.7, 0.4, 1.1);
    EXPECT_LT((hat(a) * b - a.cross(b)).norm(), 1e-15);
    EXPECT_LT((vee_skew(hat(a)) - a).norm(), 1e-15);
}

TEST(So3, QuaternionRoundTripWithNonNegativeScalar) {
    for (const vec3& angles : {vec3(0.3, 1.0, -2.0), vec3(3.1, -2.9, 0.1), vec3(0.0, 0.0, 0.0)}) {
        const mat3 r = from_euler(angles(0), angles(1), angles(2));
        const auto q = quaternion(r);
        EXPECT_GE(q[0], 0.0);
        EXPECT_NEAR(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3], 1.0, 1e-15);
        EXPECT_LT((from_quaternion(q[0], q[1], q[2], q[3]) - r).norm(), 1e-15);
    }
    // A rotation by π/2 about e₃ is (cos π/4, 0, 0, sin π/4) and maps e₁ to e₂.
    const mat3 rz = from_quaternion(std::sqrt(0.5), 0.0, 0.0, std::sqrt(0.5));
    EXPECT_LT((rz * vec3::UnitX() - vec3::UnitY()).norm(), 1e-15);
}

TEST(So3, EulerAnglesRoundTripAndTiltIsTheAngleBetweenThirdAxes) {
    const double theta = 0.8, phi = -1.3, psi = 2.2;
    const mat3 r = from_euler(theta, phi, psi);
    const auto [t, f, s] = euler_angles(r);
    EXPECT_NEAR(t, theta, 1e-14);
    EXPECT_NEAR(f, phi, 1e-14);
    EXPECT_NEAR(s, psi, 1e-14);
    EXPECT_NEAR(vec3::UnitZ().dot(r * vec3::UnitZ()), std::cos(theta), 1e-15);
}

// At θ = 0 and π only φ ± ψ is defined: the angles found give R back, with ψ = 0; the general
// formula (atan2 of two zeros) would not (at the identity it gave φ = π, ψ = 0).
TEST(So3, EulerAnglesAtTheVerticalGiveTheSameRotation) {
    for (const double theta : {0.0, std::numbers::pi})
        for (const double sum : {0.0, 0.7, -2.5}) {
            const mat3 r = from_euler(theta, sum, 0.0);
            const auto [t, f, s] = euler_angles(r);
            EXPECT_EQ(s, 0.0);
            EXPECT_LT((from_euler(t, f, s) - r).norm(), 1e-15) << theta << " " << sum;
        }
    const auto at_identity = euler_angles(mat3::Identity());
    EXPECT_EQ(at_identity[1], 0.0);
}

TEST(So3, BodyRateIsRTransposeTimesRDot) {
    const double theta = 0.8, phi = -1.3, psi = 2.2, td = 0.4, pd = -1.1, sd = 3.0, e = 1e-5;
    auto r_at = [&](double t) { return from_euler(theta + td * t, phi + pd * t, psi + sd * t); };
    const mat3 rdot = (r_at(e) - r_at(-e)) / (2 * e);
    const vec3 omega = vee_skew(r_at(0).transpose() * rdot);
    EXPECT_LT((omega - body_rate(theta, psi, td, pd, sd)).norm(), 1e-9);
}
