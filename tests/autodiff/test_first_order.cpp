// tests/autodiff/test_first_order.cpp: first derivatives alone, by forward mode
// (ad::first_order) and by reverse mode (autodiff/reverse.hpp), against closed forms derived by
// hand and against the second-order path (ad::second_order, tested in test_second_order.cpp);
// the hand derivatives of the linked pendulum against automatic ones; the reverse tape's growth
// and its independence between threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <thread>
#include <vector>

#include "varsym/autodiff/reverse.hpp"
#include "varsym/optimal/third_order.hpp"
#include "varsym/problems/double_pendulum.hpp"
#include "varsym/problems/heavy_top.hpp"
#include "varsym/problems/kepler.hpp"
#include "varsym/problems/linked_pendulum.hpp"
#include "varsym/systems/lagrangian.hpp"

using namespace varsym;

namespace {

/// f'(x) by reverse mode for a function of one variable.
template <class F>
double reverse_derivative(F f, double x) {
    ad::tape& t = ad::tape::local();
    t.clear();
    const ad::reverse v = ad::reverse::variable(x);
    const ad::reverse y = f(v);
    t.sweep(y.index());
    return t.adjoint(v.index());
}

} // namespace

TEST(FirstOrder, ReverseModeOfEveryElementaryFunction) {
    // Each rule against its derivative written by hand; relative agreement to a few ulps.
    const double x = 0.37;
    // scale: the size of the terms the exact value sums (|exact| unless they cancel).
    auto check = [x](const char* name, auto f, double exact, double scale = 0.0) {
        const double got = reverse_derivative(f, x);
        EXPECT_NEAR(got, exact, 4e-16 * std::max(scale, std::abs(exact))) << name;
        EXPECT_NE(exact, 0.0) << name; // a zero would not test the rule
    };
    check(
        "sin",
        [](auto v) {
            using std::sin;
            return sin(v);
        },
        std::cos(x));
    check(
        "cos",
        [](auto v) {
            using std::cos;
            return cos(v);
        },
        -std::sin(x));
    check(
        "tan",
        [](auto v) {
            using std::tan;
            return tan(v);
        },
        1.0 / (std::cos(x) * std::cos(x)));
    check(
        "exp",
        [](auto v) {
            using std::exp;
            return exp(v);
        },
        std::exp(x));
    check(
        "log",
        [](auto v) {
            using std::log;
            return log(v);
        },
        1.0 / x);
    check(
        "sqrt",
        [](auto v) {
            using std::sqrt;
            return sqrt(v);
        },
        0.5 / std::sqrt(x));
    check(
        "abs",
        [](auto v) {
            using std::abs;
            return abs(-3.0 * v);
        },
        3.0);
    check(
        "sinh",
        [](auto v) {
            using std::sinh;
            return sinh(v);
        },
        std::cosh(x));
    check(
        "cosh",
        [](auto v) {
            using std::cosh;
            return cosh(v);
        },
        std::sinh(x));
    check(
        "tanh",
        [](auto v) {
            using std::tanh;
            return tanh(v);
        },
        1.0 / (std::cosh(x) * std::cosh(x)));
    check(
        "asin",
        [](auto v) {
            using std::asin;
            return asin(v);
        },
        1.0 / std::sqrt(1.0 - x * x));
    check(
        "acos",
        [](auto v) {
            using std::acos;
            return acos(v);
        },
        -1.0 / std::sqrt(1.0 - x * x));
    check(
        "atan",
        [](auto v) {
            using std::atan;
            return atan(v);
        },
        1.0 / (1.0 + x * x));
    check(
        "atan2(y, x)",
        [](auto v) {
            using std::atan2;
            return atan2(v, 0.8 + 0.0 * v);
        },
        0.8 / (0.64 + x * x));
    check(
        "atan2(y, x) in x",
        [](auto v) {
            using std::atan2;
            return atan2(0.5 + 0.0 * v, v);
        },
        -0.5 / (0.25 + x * x));
    check(
        "pow(x, 2.5)",
        [](auto v) {
            using std::pow;
            return pow(v, 2.5);
        },
        2.5 * std::pow(x, 1.5));
    check(
        "pow(x, x)",
        [](auto v) {
            using std::pow;
            return pow(v, v);
        },
        std::pow(x, x) * (std::log(x) + 1.0), std::pow(x, x) * (1.0 - std::log(x)));
    check(
        "quotient", [](auto v) { return (1.0 + v) / (2.0 - v * v); },
        ((2.0 - x * x) + 2.0 * x * (1.0 + x)) / ((2.0 - x * x) * (2.0 - x * x)));
    check(
        "x·x (one node, both operands)", [](auto v) { return v * v - v; }, 2.0 * x - 1.0);
}

TEST(FirstOrder, BothModesAgreeWithTheSecondOrderPath) {
    // evaluate_gradient (forward mode at these d) and detail::differentiate_reverse against the
    // gradient that evaluate() computes with the Hessian.
    auto compare = [](const auto& l, const auto& q, const auto& v) {
        constexpr int D = std::decay_t<decltype(l)>::dim;
        lagrangian_terms<D> full, forward, reverse;
        evaluate(l, q, v, full);
        evaluate_gradient(l, q, v, forward);
        detail::differentiate_reverse(l, q, v, reverse);
        ASSERT_GT(full.lq.norm() + full.lv.norm(), 0.1);
        for (const auto* t : {&forward, &reverse}) {
            EXPECT_NEAR(t->value, full.value, 1e-14 * std::abs(full.value));
            EXPECT_LE((t->lq - full.lq).norm(), 1e-14 * full.lq.norm());
            EXPECT_LE((t->lv - full.lv).norm(), 1e-14 * full.lv.norm());
        }
    };
    compare(kepler::lagrangian{}, vec<2>{0.4, -0.3}, vec<2>{0.2, 1.7});
    compare(double_pendulum::lagrangian{1.0, 2.0, 1.5, 0.5, 9.81, 0.3}, vec<2>{0.9, -0.2},
            vec<2>{0.3, 0.1});
    compare(heavy_top::lagrangian{1.0, 0.5, 2.0}, vec<3>{0.8, 0.3, -1.2}, vec<3>{0.2, 0.7, 8.0});
    const linked_pendulum::lagrangian<4> arm({1.0, 2.0, 0.5, 1.5}, {1.0, 0.5, 0.8, 0.3}, 9.81);
    compare(linked_pendulum::automatic<4>{arm}, vec<4>{0.3, -1.1, 2.0, 0.4},
            vec<4>{0.5, -0.2, 0.9, 1.3});
}

TEST(FirstOrder, LinkedPendulumHandDerivatives) {
    // gradient() and derivatives() by hand (problems/linked_pendulum.hpp) against second-order
    // AD of the same L; and at two links, against the double pendulum written independently.
    const linked_pendulum::lagrangian<4> arm({1.0, 2.0, 0.5, 1.5}, {1.0, 0.5, 0.8, 0.3}, 9.81);
    const vec<4> q{0.3, -1.1, 2.0, 0.4}, v{0.5, -0.2, 0.9, 1.3};
    lagrangian_terms<4> hand, grad, ad;
    arm.derivatives(q, v, hand);
    arm.gradient(q, v, grad);
    evaluate(linked_pendulum::automatic<4>{arm}, q, v, ad);
    const double tol = 1e-13;
    EXPECT_NEAR(hand.value, ad.value, tol * std::abs(ad.value));
    for (auto [a, b] :
         {std::pair{&hand.lq, &ad.lq}, {&hand.lv, &ad.lv}, {&grad.lq, &ad.lq}, {&grad.lv, &ad.lv}})
        EXPECT_LE((*a - *b).norm(), tol * b->norm());
    for (auto [a, b] : {std::pair{&hand.lqq, &ad.lqq}, {&hand.lqv, &ad.lqv}, {&hand.lvv, &ad.lvv}})
        EXPECT_LE((*a - *b).norm(), tol * b->norm());
    EXPECT_GT(ad.lqv.norm(), 0.1); // L_qv ≠ 0: the mass matrix depends on q

    const double_pendulum::lagrangian two{1.0, 2.0, 1.5, 0.5, 9.81, 0.0};
    const linked_pendulum::lagrangian<2> same({1.0, 2.0}, {1.5, 0.5}, 9.81);
    lagrangian_terms<2> a, b;
    evaluate(two, vec<2>{0.9, -0.2}, vec<2>{0.3, 0.1}, a);
    same.derivatives(vec<2>{0.9, -0.2}, vec<2>{0.3, 0.1}, b);
    EXPECT_NEAR(a.value, b.value, 1e-14);
    EXPECT_LE((a.lq - b.lq).norm() + (a.lv - b.lv).norm(), 1e-13);
    EXPECT_LE((a.lqq - b.lqq).norm() + (a.lqv - b.lqv).norm() + (a.lvv - b.lvv).norm(), 1e-13);
}

TEST(FirstOrder, LinkedPendulumHandThirdDerivatives) {
    // third() by hand (the rates of the second derivatives along a direction, which the arm's
    // optimal control Hessian uses) against nested forward-mode AD of the same L
    // (optimal::contracted_third), at a fixed and at a run-time dimension: round-off, 1e-13.
    const std::vector<double> masses{1.0, 2.0, 0.5, 1.5}, lengths{1.0, 0.5, 0.8, 0.3};
    const linked_pendulum::lagrangian<4> arm(masses, lengths, 9.81);
    const linked_pendulum::lagrangian<dynamic> same(masses, lengths, 9.81);
    const vec<4> q{0.3, -1.1, 2.0, 0.4}, v{0.5, -0.2, 0.9, 1.3}, a{0.7, 0.2, -0.4, 1.1},
        b{-0.3, 0.8, 0.5, -1.2};
    const mat<8> expected =
        optimal::contracted_third(linked_pendulum::automatic<4>{arm}, q, v, 0.0, a, b);
    mat<dynamic> fixed, run_time;
    arm.third(q, v, a, b, fixed);
    same.third(q, v, a, b, run_time);
    const double scale = expected.cwiseAbs().maxCoeff();
    EXPECT_GT(scale, 1.0);
    EXPECT_LE((fixed - expected).cwiseAbs().maxCoeff(), 1e-13 * scale);
    EXPECT_LE((run_time - expected).cwiseAbs().maxCoeff(), 1e-13 * scale);
    arm.third(q, v, b, a, fixed); // negative control: the direction matters
    EXPECT_GT((fixed - expected).cwiseAbs().maxCoeff(), 1e-2 * scale);
}

TEST(FirstOrder, ReverseTapeGrowsAndIsPerThread) {
    // f(x) = Σ_{i<j} x_i x_j over 120 variables: 7140 products and sums, past the tape's first
    // 4096 nodes; ∂f/∂x_k = Σ_{i≠k} x_i = S − x_k.
    constexpr int n = 120;
    auto gradient_ok = [](double shift) {
        std::vector<double> x(n);
        double sum = 0.0;
        for (int i = 0; i < n; ++i)
            sum += x[i] = std::sin(i + shift);
        ad::tape& t = ad::tape::local();
        bool ok = true;
        for (int repeat = 0; repeat < 20; ++repeat) {
            t.clear();
            std::vector<ad::reverse> v(n);
            for (int i = 0; i < n; ++i)
                v[i] = ad::reverse::variable(x[i]);
            ad::reverse f(0.0);
            for (int i = 0; i < n; ++i)
                for (int j = i + 1; j < n; ++j)
                    f += v[i] * v[j];
            t.sweep(f.index());
            for (int k = 0; k < n; ++k)
                ok = ok && std::abs(t.adjoint(v[k].index()) - (sum - x[k])) <= 1e-12;
        }
        return ok;
    };
    EXPECT_TRUE(gradient_ok(0.0));
    // Two threads recording and sweeping at once, each on its own tape.
    bool ok1 = false, ok2 = false;
    std::thread a([&] { ok1 = gradient_ok(1.0); }), b([&] { ok2 = gradient_ok(2.0); });
    a.join();
    b.join();
    EXPECT_TRUE(ok1);
    EXPECT_TRUE(ok2);
}
