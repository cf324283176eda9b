// Expression Lagrangians (expression/*.hpp, systems/expression_lagrangian.hpp): the parser's
// precedence and its error positions, the symbolic derivatives against automatic differentiation
// and against finite differences, and the general engine driven by an expression against the
// pendulum's exact solution.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "varsym/integrate.hpp"
#include "varsym/optimal/third_order.hpp"
#include "varsym/problems/double_pendulum.hpp"
#include "varsym/problems/pendulum.hpp"
#include "varsym/schemes/variational.hpp"
#include "varsym/systems/expression_force.hpp"
#include "varsym/systems/expression_lagrangian.hpp"

namespace varsym {
namespace {

/// The value of `text` over the one coordinate x (x_dot = 0).
double value_of(const std::string& text, double x) {
    const expression_lagrangian l(text, {"x"});
    return l(vec<dynamic>::Constant(1, x), vec<dynamic>::Zero(1), 0.0);
}

TEST(ExpressionParse, PrecedenceAsInPython) {
    // Expected values: Python's own evaluation of the same text at x = 1.5.
    const double x = 1.5;
    EXPECT_DOUBLE_EQ(value_of("-x**2", x), -(x * x));
    EXPECT_DOUBLE_EQ(value_of("2**3**2", x), 512.0);
    EXPECT_DOUBLE_EQ(value_of("x**-2", x), 1.0 / (x * x));
    EXPECT_DOUBLE_EQ(value_of("1 - x - 2", x), 1.0 - x - 2.0);
    EXPECT_DOUBLE_EQ(value_of("8/x/2", x), 8.0 / x / 2.0);
    EXPECT_DOUBLE_EQ(value_of("2*x^2 + 3*x", x), 2.0 * x * x + 3.0 * x); // ^ is **
    EXPECT_DOUBLE_EQ(value_of("(1 + x)*(1 - x)", x), (1.0 + x) * (1.0 - x));
    EXPECT_DOUBLE_EQ(value_of("x**2.5", x), std::pow(x, 2.5));
    EXPECT_DOUBLE_EQ(value_of("1.5e-3*x + 2E2", x), 1.5e-3 * x + 2e2);
    EXPECT_DOUBLE_EQ(value_of("atan(x) + sqrt(x) + pi*E", x),
                     std::atan(x) + std::sqrt(x) + M_PI * M_E);
    // Negative control: a different text gives a different value.
    EXPECT_NE(value_of("(-x)**2", x), value_of("-x**2", x));
}

TEST(ExpressionParse, ErrorsNameWhatAndWhere) {
    struct bad {
        const char* text;
        std::size_t position;
        const char* says;
    };
    for (const bad& b :
         {bad{"0.5*x_dot**2 + * x", 15, "unexpected '*'"},
          bad{"0.5*m*x_dot**2", 4, "unknown name 'm'"}, bad{"cos(x", 5, "expected ')'"},
          bad{"foo(x)", 0, "unknown function 'foo'"}, bad{"x_dot**2 x", 9, "unexpected 'x'"},
          bad{"", 0, "expression ended"}, bad{"1.2.3*x", 0, "malformed number"},
          bad{"sin + x", 0, "needs '('"}}) {
        try {
            const expression_lagrangian l(b.text, {"x"});
            ADD_FAILURE() << "accepted: " << b.text;
        } catch (const expr::parse_error& e) {
            EXPECT_EQ(e.position(), b.position) << b.text << ": " << e.what();
            EXPECT_NE(std::string(e.what()).find(b.says), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("column " + std::to_string(b.position + 1)),
                      std::string::npos)
                << e.what();
        }
    }
    EXPECT_THROW(expression_lagrangian("x_dot", {"x", "x"}), std::invalid_argument);
    EXPECT_THROW(expression_lagrangian("x_dot", {"sin"}), std::invalid_argument);
    EXPECT_THROW(expression_lagrangian("x_dot", {"x"}, {{"x_dot", 1.0}}), std::invalid_argument);
    EXPECT_THROW(expression_lagrangian("1", {}), std::invalid_argument);
}

TEST(ExpressionParse, DeepOrLongExpressionsDoNotExhaustTheStack) {
    // Nesting is bounded (expr::max_depth) and refused with a message, not a stack overflow.
    const std::string deep = std::string(300, '(') + "x_dot" + std::string(300, ')');
    EXPECT_THROW(expression_lagrangian(deep, {"x"}), expr::parse_error);
    const std::string nested = std::string(200, '(') + "x_dot" + std::string(200, ')') + "**2";
    EXPECT_DOUBLE_EQ(expression_lagrangian(nested, {"x"})(vec<dynamic>::Zero(1),
                                                          vec<dynamic>::Constant(1, 3.0), 0.0),
                     9.0);
    // A sum of 50 000 terms is a chain 50 000 nodes deep: differentiated without recursion.
    std::string sum = "0.5*x_dot**2";
    for (int k = 0; k < 50000; ++k)
        sum += " + 1e-9*sin(x)";
    const expression_lagrangian l(sum, {"x"});
    lagrangian_terms<dynamic> d;
    l.derivatives(vec<dynamic>::Constant(1, 0.5), vec<dynamic>::Constant(1, 2.0), 0.0, d);
    EXPECT_NEAR(d.lq(0), 5e-5 * std::cos(0.5), 1e-15);
    EXPECT_NEAR(d.lqq(0, 0), -5e-5 * std::sin(0.5), 1e-15);
    EXPECT_EQ(d.lvv(0, 0), 1.0);
}

constexpr const char* double_pendulum_text =
    "0.5*(m1+m2)*l1**2*th1_dot**2 + 0.5*m2*l2**2*th2_dot**2"
    " + m2*l1*l2*th1_dot*th2_dot*cos(th1-th2) + (m1+m2)*g*l1*cos(th1) + m2*g*l2*cos(th2)"
    " - 0.5*k*(th1**2 + (th2-th1)**2)";

expression_lagrangian double_pendulum_expression(const double_pendulum::lagrangian& p) {
    return {double_pendulum_text,
            {"th1", "th2"},
            {{"m1", p.m1}, {"m2", p.m2}, {"l1", p.l1}, {"l2", p.l2}, {"g", p.g}, {"k", p.k}}};
}

TEST(ExpressionDerivatives, MatchAutomaticDifferentiation) {
    // Reference: the built-in double pendulum, differentiated by forward-mode AD.
    const double_pendulum::lagrangian ad{1.3, 0.7, 1.1, 0.9, 9.81, 0.4};
    const expression_lagrangian ex = double_pendulum_expression(ad);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-3.0, 3.0);
    for (int trial = 0; trial < 20; ++trial) {
        const vec<2> q{u(rng), u(rng)}, v{u(rng), u(rng)};
        lagrangian_terms<2> a;
        evaluate(ad, q, v, a);
        lagrangian_terms<dynamic> b;
        ex.derivatives(q, v, 0.0, b);
        const double tol = 1e-13 * (1.0 + a.lvv.norm() + a.lqq.norm());
        EXPECT_NEAR(a.value, b.value, tol);
        EXPECT_LE((a.lq - b.lq).norm(), tol);
        EXPECT_LE((a.lv - b.lv).norm(), tol);
        EXPECT_LE((a.lqq - b.lqq).norm(), tol);
        EXPECT_LE((a.lqv - b.lqv).norm(), tol);
        EXPECT_LE((a.lvv - b.lvv).norm(), tol);
        lagrangian_terms<dynamic> g;
        ex.gradient(q, v, 0.0, g);
        EXPECT_EQ(g.lq, b.lq);
        EXPECT_EQ(g.lv, b.lv);
    }
    // Negative control: another parameter value is detected.
    double_pendulum::lagrangian other = ad;
    other.k = 0.5;
    lagrangian_terms<dynamic> b, c;
    const vec<dynamic> q = vec<2>{0.3, -0.2}, v = vec<2>{0.1, 0.4};
    ex.derivatives(q, v, 0.0, b);
    double_pendulum_expression(other).derivatives(q, v, 0.0, c);
    EXPECT_GT((b.lqq - c.lqq).norm(), 0.05);
}

/// Every function the parser knows, a power with a moving exponent and t, in one L over (x, y);
/// `every_function` is the same L in C++, the functions past <cmath>'s basic ones written by
/// identities (sinh = (eˣ − e⁻ˣ)/2, atan z = atan2(z, 1), aᵇ = e^{b log a}, …), so that the
/// two share no derivative rule.
const char* const every_function_text =
    "0.5*(2 + sin(x)**2)*x_dot**2 + 0.5*y_dot**2*exp(0.3*y) + x_dot*y_dot*cos(x - y)/(2 + "
    "tanh(y)) + sqrt(1.5 + x**2)*atan(y_dot) + log(2 + cosh(x*y)) + sinh(0.2*x)*tan(0.3*y) + "
    "asin(0.2*x_dot) + acos(0.1*y) + (1.5 + y**2)**(0.5 + 0.1*x) + x**3/(2 + y**2)**2 - t*x*y_dot";

struct every_function {
    static constexpr int dim = 2;
    template <class T>
    T operator()(const tvec<T, 2>& q, const tvec<T, 2>& v, double t) const {
        using std::atan2, std::cos, std::exp, std::log, std::sin, std::sqrt, std::tan;
        const T x = q(0), y = q(1), xd = v(0), yd = v(1);
        const auto sinh = [](const T& z) { return T(0.5) * (exp(z) - exp(-z)); };
        const auto cosh = [](const T& z) { return T(0.5) * (exp(z) + exp(-z)); };
        const auto asin = [](const T& z) { return atan2(z, sqrt(T(1.0) - z * z)); };
        const auto acos = [](const T& z) { return atan2(sqrt(T(1.0) - z * z), z); };
        const T s = sin(x), w = T(2.0) + y * y;
        return T(0.5) * (T(2.0) + s * s) * xd * xd + T(0.5) * yd * yd * exp(T(0.3) * y) +
               xd * yd * cos(x - y) / (T(2.0) + sinh(y) / cosh(y)) +
               sqrt(T(1.5) + x * x) * atan2(yd, T(1.0)) + log(T(2.0) + cosh(x * y)) +
               sinh(T(0.2) * x) * tan(T(0.3) * y) + asin(T(0.2) * xd) + acos(T(0.1) * y) +
               exp((T(0.5) + T(0.1) * x) * log(T(1.5) + y * y)) + x * x * x / (w * w) -
               T(t) * x * yd;
    }
};

TEST(ExpressionDerivatives, ThirdDerivativesMatchNestedAutomaticDifferentiation) {
    // expression_lagrangian::third (the symbolic second derivatives' code run forward along a
    // direction: every operation's rate rule) against optimal::contracted_third of the same L
    // in C++ (nested forward-mode AD). Both exact: they agree to round-off, 1e-12 relative.
    const expression_lagrangian ex(every_function_text, {"x", "y"});
    const every_function cpp;
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1.5, 1.5);
    for (int trial = 0; trial < 10; ++trial) {
        const vec<2> q{u(rng), u(rng)}, v{u(rng), u(rng)}, a{u(rng), u(rng)}, b{u(rng), u(rng)};
        const double t = u(rng);
        const mat<4> expected = optimal::contracted_third(cpp, q, v, t, a, b);
        mat<dynamic> got;
        ex.third(q, v, t, a, b, got);
        const double scale = std::max(1.0, expected.cwiseAbs().maxCoeff());
        EXPECT_LT((got - expected).cwiseAbs().maxCoeff(), 1e-12 * scale) << "trial " << trial;
        // Negative control: the direction matters.
        ex.third(q, v, t, b, a, got);
        EXPECT_GT((got - expected).cwiseAbs().maxCoeff(), 1e-3 * scale);
    }
}

// Time dependence is ∂L/∂t not identically zero once simplified, not the name t in the text:
// the energy watch is on for an autonomous L however it is written. No name may hide t.
TEST(ExpressionLagrangian, DependsOnTimeWhereDLdtIsNotZero) {
    for (const char* autonomous : {"0.5*x_dot**2 - x**2", "0.5*x_dot**2 + 0*t", "x_dot**2 + t - t"})
        EXPECT_FALSE(expression_lagrangian(autonomous, {"x"}).depends_on_time()) << autonomous;
    for (const char* timed : {"0.5*x_dot**2*exp(t)", "0.5*x_dot**2 + t*x", "x_dot**2 + t**2"})
        EXPECT_TRUE(expression_lagrangian(timed, {"x"}).depends_on_time()) << timed;
    EXPECT_THROW(expression_lagrangian("0.5*t_dot**2", {"t"}), std::invalid_argument);
    EXPECT_THROW(expression_lagrangian("0.5*x_dot**2*t", {"x"}, {{"t", 2.0}}),
                 std::invalid_argument);
}

TEST(ExpressionDerivatives, EveryFunctionAgainstFiniteDifferences) {
    // Reference: central differences of the value (first derivatives) and of the symbolic
    // gradient (second), step 1e-5: truncation ~1e-10 times the third derivatives.
    const expression_lagrangian l(
        "0.5*(1 + 0.1*sin(x)*cos(y))*x_dot**2 + 0.5*exp(0.2*x)*y_dot**2 + tan(0.3*x*y)"
        " + log(2 + x**2) + sqrt(3 + y**2)*x_dot*y_dot + sinh(0.2*x) + cosh(0.1*y)"
        " + tanh(x*y_dot) + asin(0.3*x/(1 + x**2)) + acos(0.2*y/(1 + y**2)) + atan(x - y)"
        " + (1.5 + x**2)**(0.5*y) - 1/(3 + x**2)**3 + t*x",
        {"x", "y"});
    EXPECT_TRUE(l.depends_on_time());
    const vec<dynamic> q = vec<2>{0.4, -0.7}, v = vec<2>{0.9, 0.3};
    const double t = 0.8, e = 1e-5;
    lagrangian_terms<dynamic> d;
    l.derivatives(q, v, t, d);
    for (int k = 0; k < 4; ++k) {
        vec<dynamic> qp = q, qm = q, vp = v, vm = v;
        (k < 2 ? qp : vp)(k % 2) += e;
        (k < 2 ? qm : vm)(k % 2) -= e;
        const double fd = (l(qp, vp, t) - l(qm, vm, t)) / (2 * e);
        EXPECT_NEAR(k < 2 ? d.lq(k) : d.lv(k - 2), fd, 1e-7) << k;
        lagrangian_terms<dynamic> gp, gm;
        l.gradient(qp, vp, t, gp);
        l.gradient(qm, vm, t, gm);
        const vec<dynamic> dlq = (gp.lq - gm.lq) / (2 * e), dlv = (gp.lv - gm.lv) / (2 * e);
        for (int i = 0; i < 2; ++i) {
            // Column k of the Hessian in (q, v): ∂L_q/∂x_k and ∂L_v/∂x_k.
            EXPECT_NEAR(k < 2 ? d.lqq(i, k) : d.lqv(i, k - 2), dlq(i), 1e-6) << i << k;
            EXPECT_NEAR(k < 2 ? d.lqv(k, i) : d.lvv(i, k - 2), dlv(i), 1e-6) << i << k;
        }
    }
    EXPECT_NEAR(d.value - l(q, v, 0.0), t * q(0), 1e-15); // t enters as written
}

TEST(ExpressionForce, JacobiansAgainstFiniteDifferences) {
    // Reference: central differences of the compiled force, step 1e-6 (truncation ~1e-12).
    const expression_force f({"-c*x_dot + k*sin(y)*t", "-c*y_dot*x**2 + atan(x*y_dot)"}, {"x", "y"},
                             {{"c", 0.3}, {"k", 2.0}});
    EXPECT_FALSE(f.zero());
    const vec<dynamic> q = vec<2>{0.4, -0.7}, v = vec<2>{0.9, 0.3};
    const double t = 0.5, e = 1e-6;
    force_terms<dynamic> r;
    f.derivatives(q, v, t, r);
    EXPECT_LE((r.f - f(q, v, t)).norm(), 0.0);
    EXPECT_NEAR(r.f(0), -0.3 * 0.9 + 2.0 * std::sin(-0.7) * t, 1e-15); // the formula itself
    for (int k = 0; k < 4; ++k) {
        vec<dynamic> qp = q, qm = q, vp = v, vm = v;
        (k < 2 ? qp : vp)(k % 2) += e;
        (k < 2 ? qm : vm)(k % 2) -= e;
        const vec<dynamic> fd = (f(qp, vp, t) - f(qm, vm, t)) / (2 * e);
        const vec<dynamic> col = k < 2 ? vec<dynamic>(r.fq.col(k)) : vec<dynamic>(r.fv.col(k - 2));
        EXPECT_LE((col - fd).norm(), 1e-8) << k;
    }
    EXPECT_TRUE(expression_force(2).zero());
    EXPECT_THROW(expression_force({"-x_dot"}, {"x", "y"}), std::invalid_argument); // one of two
    EXPECT_THROW(expression_force({"-c*x_dot"}, {"x"}), expr::parse_error);        // unknown c
}

TEST(ExpressionEngine, SimpsonOnThePendulumConvergesToTheExactSolution) {
    // Reference: the pendulum's exact solution (Jacobi elliptic functions); Simpson is of
    // order 4, so halving h divides the error by 2⁴ = 16 (taken as > 12).
    const double m = 1.0, w = 2.0, q0 = 1.2;
    const expression_lagrangian l("0.5*m*q_dot**2 - m*w**2*(1 - cos(q))", {"q"},
                                  {{"m", m}, {"w", w}});
    const lagrangian_system<expression_lagrangian> sys(l);
    const pendulum::exact_solution exact(m, w, q0, 0.0);
    auto error = [&](int n) {
        const double h = exact.period() / n;
        general::stepper<expression_lagrangian> s(sys, h, scheme_kind::simpson);
        phase_state<dynamic> x{vec<dynamic>::Constant(1, q0), vec<dynamic>::Zero(1)};
        run_summary sum;
        // t = 4.25 periods, mid-swing (at whole periods the phase error hides at the turning
        // point).
        const int steps = 4 * n + n / 4;
        for (int j = 1; j <= steps; ++j)
            advance(s, x, 0.0, static_cast<std::size_t>(j), sum);
        return std::abs(x.q(0) - exact.at(steps * h).q(0));
    };
    const double e1 = error(40), e2 = error(80);
    EXPECT_LT(e2, 1e-5);
    EXPECT_GT(e1 / e2, 12.0) << e1 << " " << e2;
    EXPECT_LT(e1 / e2, 20.0) << e1 << " " << e2;
}

} // namespace
} // namespace varsym
