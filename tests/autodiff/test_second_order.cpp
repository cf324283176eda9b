// tests/autodiff/test_second_order.cpp: derivatives of Lagrangians by automatic differentiation
// against closed forms written by hand (an independent derivation of the same quantities).
#include <gtest/gtest.h>

#include <cmath>

#include "varsym/problems/double_pendulum.hpp"
#include "varsym/problems/heavy_top.hpp"
#include "varsym/problems/kepler.hpp"
#include "varsym/systems/lagrangian.hpp"

using namespace varsym;

// Kepler: the separable system's hand derivatives (−∇V, M v, −∇²V, 0, M = I) against AD of
// L = ½|v|² + μ/|q|. Same formulas evaluated in a different order: agreement to a few ulps.
TEST(AutoDiff, KeplerMatchesHandDerivatives) {
    const vec<2> q{0.4, -0.3}, v{0.2, 1.7};
    lagrangian_terms<2> a, b;
    evaluate(kepler::lagrangian{}, q, v, a);
    evaluate(separable_lagrangian<kepler::system>{kepler::make_system()}, q, v, b);
    EXPECT_NEAR(a.value, b.value, 1e-14);
    EXPECT_LT((a.lq - b.lq).norm(), 1e-13);
    EXPECT_LT((a.lv - b.lv).norm(), 1e-15);
    EXPECT_LT((a.lqq - b.lqq).norm(), 1e-12);
    EXPECT_EQ(a.lqv.norm(), 0.0);
    EXPECT_LT((a.lvv - b.lvv).norm(), 1e-15);
}

TEST(AutoDiff, DoublePendulumMassMatrix) {
    // ∂²L/∂q̇² = [(m₁+m₂)ℓ₁², m₂ℓ₁ℓ₂ cos(θ₁−θ₂); ·, m₂ℓ₂²]
    const double_pendulum::lagrangian l{1.0, 2.0, 1.5, 0.5, 9.81, 0.0};
    lagrangian_terms<2> t;
    evaluate(l, vec<2>{0.9, -0.2}, vec<2>{0.3, 0.1}, t);
    EXPECT_NEAR(t.lvv(0, 0), 3.0 * 2.25, 1e-14);
    EXPECT_NEAR(t.lvv(0, 1), 2.0 * 1.5 * 0.5 * std::cos(1.1), 1e-14);
    EXPECT_NEAR(t.lvv(1, 1), 2.0 * 0.25, 1e-14);
    EXPECT_EQ(t.lvv(0, 1), t.lvv(1, 0));
    // ∂L/∂θ₂ = m₂ℓ₁ℓ₂θ̇₁θ̇₂ sin(θ₁−θ₂) − m₂gℓ₂ sin θ₂
    EXPECT_NEAR(t.lq(1),
                2.0 * 1.5 * 0.5 * 0.3 * 0.1 * std::sin(1.1) - 2.0 * 9.81 * 0.5 * std::sin(-0.2),
                1e-13);
}

TEST(AutoDiff, HeavyTopClosedForms) {
    const heavy_top::lagrangian l{1.0, 0.5, 2.0};
    const double th = 0.8, phid = 0.7, psid = 8.0, s = std::sin(th), c = std::cos(th);
    lagrangian_terms<3> t;
    evaluate(l, vec<3>{th, 0.3, -1.2}, vec<3>{0.2, phid, psid}, t);
    // ∂²L/∂q̇² = [[I₁, 0, 0], [0, I₁s² + I₃c², I₃c], [0, I₃c, I₃]]
    EXPECT_NEAR(t.lvv(0, 0), 1.0, 1e-15);
    EXPECT_NEAR(t.lvv(1, 1), s * s + 0.5 * c * c, 1e-15);
    EXPECT_NEAR(t.lvv(1, 2), 0.5 * c, 1e-15);
    EXPECT_NEAR(t.lvv(2, 2), 0.5, 1e-15);
    // ∂L/∂θ = I₁φ̇² s c − I₃(ψ̇ + φ̇c) φ̇ s + mgl s; φ and ψ cyclic: exactly zero
    EXPECT_NEAR(t.lq(0), phid * phid * s * c - 0.5 * (psid + phid * c) * phid * s + 2.0 * s, 1e-13);
    EXPECT_EQ(t.lq(1), 0.0);
    EXPECT_EQ(t.lq(2), 0.0);
    EXPECT_EQ(t.lqq.col(1).norm() + t.lqq.col(2).norm(), 0.0);
}

// Second derivatives against central differences of the AD gradient (error ~ δ² ~ 1e-8).
TEST(AutoDiff, HessianMatchesDifferencesOfGradient) {
    const heavy_top::lagrangian l{1.0, 0.5, 2.0};
    const vec<3> q{0.8, 0.3, -1.2}, v{0.2, 0.7, 8.0};
    lagrangian_terms<3> t, a, b;
    evaluate(l, q, v, t);
    const double d = 1e-5;
    for (int j = 0; j < 3; ++j) {
        const vec<3> e = vec<3>::Unit(j) * d;
        evaluate(l, q + e, v, a);
        evaluate(l, q - e, v, b);
        EXPECT_LT(((a.lq - b.lq) / (2 * d) - t.lqq.col(j)).norm(), 1e-7) << j;
        EXPECT_LT(((a.lv - b.lv) / (2 * d) - t.lqv.row(j).transpose()).norm(), 1e-7) << j;
        evaluate(l, q, v + e, a);
        evaluate(l, q, v - e, b);
        EXPECT_LT(((a.lv - b.lv) / (2 * d) - t.lvv.col(j)).norm(), 1e-7) << j;
    }
}
