// tests/autodiff/test_jet.cpp: the jet type's first and second derivatives against closed forms
// and against a second implementation, Eigen's AutoDiffScalar nested in itself.
#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/Core> // before Eigen's unsupported AutoDiff, which needs it
#include <unsupported/Eigen/AutoDiff>

#include "varsym/autodiff/jet.hpp"
#include "varsym/problems/double_pendulum.hpp"
#include "varsym/problems/heavy_top.hpp"
#include "varsym/problems/kepler.hpp"
#include "varsym/systems/lagrangian.hpp"

using namespace varsym;

namespace {

/// Value, gradient and Hessian of L(q, v) from Eigen's nested AutoDiffScalar (fixed sizes).
template <class L>
lagrangian_terms<L::dim> eigen_autodiff(const L& l, const vec<L::dim>& q, const vec<L::dim>& v) {
    constexpr int D = L::dim, N = 2 * D;
    using inner = Eigen::AutoDiffScalar<Eigen::Matrix<double, N, 1>>;
    using outer = Eigen::AutoDiffScalar<Eigen::Matrix<inner, N, 1>>;
    tvec<outer, D> qa, va;
    for (int i = 0; i < N; ++i) {
        const double x = i < D ? q(i) : v(i - D);
        outer& o = i < D ? qa(i) : va(i - D);
        o.value() = inner(x, N, i);
        o.derivatives() = Eigen::Matrix<inner, N, 1>::Unit(N, i);
        for (int j = 0; j < N; ++j) o.derivatives()(j).derivatives() = Eigen::Matrix<double, N, 1>::Zero();
    }
    const outer r = l(qa, va);
    lagrangian_terms<D> t;
    t.value = r.value().value();
    Eigen::Matrix<double, N, N> h;
    Eigen::Matrix<double, N, 1> g;
    for (int i = 0; i < N; ++i) {
        g(i) = r.derivatives()(i).value();
        h.row(i) = r.derivatives()(i).derivatives().transpose();
    }
    t.lq = g.template head<D>();
    t.lv = g.template tail<D>();
    t.lqq = h.template topLeftCorner<D, D>();
    t.lqv = h.template topRightCorner<D, D>();
    t.lvv = h.template bottomRightCorner<D, D>();
    return t;
}

template <class L>
void expect_same_terms(const L& l, const vec<L::dim>& q, const vec<L::dim>& v) {
    lagrangian_terms<L::dim> a;
    evaluate(l, q, v, a);
    const auto b = eigen_autodiff(l, q, v);
    const double scale = 1.0 + std::abs(a.value);
    // Two implementations of the same chain rule: they differ only by round-off in the order
    // of the operations, a few ulps of the size of the terms.
    EXPECT_NEAR(a.value, b.value, 1e-14 * scale);
    EXPECT_LT((a.lq - b.lq).norm(), 1e-13 * scale);
    EXPECT_LT((a.lv - b.lv).norm(), 1e-13 * scale);
    EXPECT_LT((a.lqq - b.lqq).norm(), 1e-12 * scale);
    EXPECT_LT((a.lqv - b.lqv).norm(), 1e-12 * scale);
    EXPECT_LT((a.lvv - b.lvv).norm(), 1e-12 * scale);
}

} // namespace

TEST(Jet, ElementaryFunctionsMatchClosedForms) {
    using J = ad::jet<2>;
    const J x = J::variable(0.7, 0), y = J::variable(1.3, 1);
    // f = sin(x) exp(y) / sqrt(x y): check a few entries against hand derivatives.
    const J f = sin(x) * exp(y) / sqrt(x * y);
    const double fx = std::sin(0.7) * std::exp(1.3) / std::sqrt(0.7 * 1.3);
    EXPECT_NEAR(f.v, fx, 1e-15 * fx);
    // ∂f/∂x = f (cot x − 1/(2x)), ∂f/∂y = f (1 − 1/(2y))
    EXPECT_NEAR(f.g(0), fx * (std::cos(0.7) / std::sin(0.7) - 0.5 / 0.7), 1e-14);
    EXPECT_NEAR(f.g(1), fx * (1.0 - 0.5 / 1.3), 1e-14);
    // ∂²f/∂y² = f ((1 − 1/(2y))² + 1/(2y²))
    EXPECT_NEAR(f.h(1, 1), fx * (std::pow(1.0 - 0.5 / 1.3, 2) + 0.5 / (1.3 * 1.3)), 1e-13);
    EXPECT_EQ(f.h(0, 1), f.h(1, 0));
    const J p = pow(x, 2.5), l = log(y), a = atan(x), t = tan(y);
    EXPECT_NEAR(p.h(0, 0), 2.5 * 1.5 * std::pow(0.7, 0.5), 1e-14);
    EXPECT_NEAR(l.h(1, 1), -1.0 / (1.3 * 1.3), 1e-15);
    EXPECT_NEAR(a.g(0), 1.0 / (1.0 + 0.49), 1e-15);
    EXPECT_NEAR(t.g(1), 1.0 / std::pow(std::cos(1.3), 2), 1e-12);
}

TEST(Jet, LagrangiansMatchEigenAutoDiff) {
    expect_same_terms(kepler::lagrangian{}, vec<2>{0.4, -0.3}, vec<2>{0.2, 1.7});
    expect_same_terms(double_pendulum::lagrangian{1.0, 2.0, 1.5, 0.5, 9.81, 3.0}, vec<2>{0.9, -2.1},
                      vec<2>{1.1, 0.4});
    expect_same_terms(heavy_top::lagrangian{1.0, 0.5, 2.0}, vec<3>{0.8, 0.3, -1.2},
                      vec<3>{0.2, 0.7, 8.0});
}

TEST(Jet, MassMatrixOfDoublePendulumIsTheKnownOne) {
    // ∂²L/∂q̇² = [(m₁+m₂)ℓ₁², m₂ℓ₁ℓ₂ cos(θ₁−θ₂); ·, m₂ℓ₂²]
    const double_pendulum::lagrangian l{1.0, 2.0, 1.5, 0.5, 9.81, 0.0};
    lagrangian_terms<2> t;
    evaluate(l, vec<2>{0.9, -0.2}, vec<2>{0.3, 0.1}, t);
    EXPECT_NEAR(t.lvv(0, 0), 3.0 * 2.25, 1e-14);
    EXPECT_NEAR(t.lvv(0, 1), 2.0 * 1.5 * 0.5 * std::cos(1.1), 1e-14);
    EXPECT_NEAR(t.lvv(1, 1), 2.0 * 0.25, 1e-14);
    EXPECT_EQ(t.lvv(0, 1), t.lvv(1, 0));
}
