// tests/systems/test_time_dependent.cpp: time-dependent Lagrangians L(q, q̇, t) in the general
// engine and the constrained one (systems/lagrangian.hpp, schemes/variational.hpp,
// schemes/constrained.hpp).
// References:
//  - Caldirola–Kanai: L = e^{γt}(½ m q̇² − ½ k q²) gives m q̈ + γ m q̇ + k q = 0, solved exactly,
//    with p = e^{γt} m q̇: the observed orders must be 2 (Newmark), 4 (Simpson), 2s (the family);
//  - Mathieu: L = ½ m q̇² − ½ k(t) q², against the free particle driven by the force −k(t) q: the
//    two are the same equations at every quadrature node, so the same steps to round-off;
//  - Kapitza's pendulum (pivot at height a cos Ωt): in Cartesian coordinates relative to the
//    pivot with |x| = ℓ, L depends on t through q̇ (a moving frame); against the same pendulum in
//    its angle, and the inverted position stable for a²Ω² > 2gℓ (Landau & Lifshitz, Mechanics,
//    §30), falling without the drive (the negative control).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "test_support.hpp"
#include "varsym/run/state.hpp"
#include "varsym/schemes/constrained.hpp"
#include "varsym/schemes/variational.hpp"

using namespace varsym;

using test::member;

namespace {

// L = e^{γt}(½ m q̇² − ½ k (1 + ε cos Ωt) q²): Caldirola–Kanai for ε = 0, Mathieu for γ = 0.
struct caldirola_mathieu {
    static constexpr int dim = 1;
    double m = 1.0, k = 4.0, gamma = 0.3, eps = 0.0, omega = 0.0;
    double stiffness(double t) const { return k * (1.0 + eps * std::cos(omega * t)); }
    template <class T>
    T operator()(const tvec<T, 1>& q, const tvec<T, 1>& v, double t) const {
        return std::exp(gamma * t) * ((0.5 * m) * v(0) * v(0) - (0.5 * stiffness(t)) * q(0) * q(0));
    }
};

struct kinetic {
    static constexpr int dim = 1;
    double m = 1.0;
    template <class T>
    T operator()(const tvec<T, 1>&, const tvec<T, 1>& v) const {
        return (0.5 * m) * v(0) * v(0);
    }
};

// The Mathieu potential's force −k(t) q on the free particle.
struct stiffness_force {
    static constexpr int dim = 1;
    caldirola_mathieu l;
    template <class T>
    tvec<T, 1> operator()(const tvec<T, 1>& q, const tvec<T, 1>&, double t) const {
        return tvec<T, 1>(-l.stiffness(t) * q(0));
    }
};

/// The exact Caldirola–Kanai state at t from q0, q̇0 at t0 (p = e^{γt} m q̇).
phase_state<1> caldirola_exact(const caldirola_mathieu& l, double q0, double v0, double t0,
                               double t) {
    const double a = 0.5 * l.gamma, wd = std::sqrt(l.k / l.m - a * a), tau = t - t0;
    const double b = (v0 + a * q0) / wd, e = std::exp(-a * tau);
    const double c = std::cos(wd * tau), s = std::sin(wd * tau);
    const double q = e * (q0 * c + b * s);
    const double v = e * (-a * (q0 * c + b * s) + wd * (-q0 * s + b * c));
    return {vec<1>{q}, vec<1>{std::exp(l.gamma * t) * l.m * v}};
}

/// max(|q − q_exact|, |p − p_exact| e^{−γT}) at T = t0 + 10 after n steps from t0 = 0.5.
double caldirola_error(scheme_spec spec, int n) {
    const caldirola_mathieu l;
    const double t0 = 0.5, t_end = t0 + 10.0, q0 = 1.0, v0 = 0.5;
    general::stepper<caldirola_mathieu> st(lagrangian_system<caldirola_mathieu>(l),
                                           (t_end - t0) / n, spec);
    phase_state<1> x = caldirola_exact(l, q0, v0, t0, t0);
    integrate(st, x, t0, static_cast<std::size_t>(n), [](auto, auto, const auto&) {});
    const phase_state<1> ref = caldirola_exact(l, q0, v0, t0, t_end);
    return std::max(std::abs(x.q(0) - ref.q(0)),
                    std::abs(x.p(0) - ref.p(0)) * std::exp(-l.gamma * t_end));
}

} // namespace

TEST(TimeDependent, CaldirolaKanaiReferenceIsSane) {
    const caldirola_mathieu l;
    const auto at = [&](double t) { return caldirola_exact(l, 1.0, 0.5, 0.5, t); };
    EXPECT_NEAR(at(0.5).q(0), 1.0, 1e-15);
    const double t = 3.1, e = 1e-4;
    const auto v = [&](double u) { return at(u).p(0) * std::exp(-l.gamma * u) / l.m; };
    const double acc = (v(t + e) - v(t - e)) / (2 * e);
    EXPECT_NEAR(l.m * acc + l.gamma * l.m * v(t) + l.k * at(t).q(0), 0.0, 1e-7);
}

TEST(TimeDependent, CaldirolaKanaiOrdersOfTheFamily) {
    // h = 0.1 and 0.05 to t = 10.5 from t = 0.5. Ignoring the time (the undamped oscillator)
    // would leave an O(1) error at both.
    for (const member& m : test::five_members) {
        const double coarse = caldirola_error(m.spec, 100), fine = caldirola_error(m.spec, 200);
        const double observed = std::log2(coarse / fine);
        SCOPED_TRACE(m.spec.label() + ": errors " + test::sci(coarse) + ", " + test::sci(fine));
        EXPECT_NEAR(observed, m.order, 0.2);
        EXPECT_LT(fine, 1e-2);
        RecordProperty("order_" + m.spec.label(), test::sci(observed));
    }
}

TEST(TimeDependent, APotentialInLIsTheSameAsItsForce) {
    // Mathieu's equation two ways; both by Newton. Values are O(1): 1e-12 allows the two
    // paths' different roundings of k(t) q over 400 steps.
    caldirola_mathieu l;
    l.gamma = 0.0;
    l.eps = 0.4;
    l.omega = 3.1;
    newton_options opt;
    opt.iteration = iteration_kind::newton;
    auto difference = [&](scheme_spec spec, const stiffness_force& f) {
        general::stepper<caldirola_mathieu> a(lagrangian_system<caldirola_mathieu>(l), 0.05, spec,
                                              opt);
        general::stepper<kinetic, stiffness_force> b(lagrangian_system<kinetic>({}), f, 0.05, spec,
                                                     opt);
        phase_state<1> xa{vec<1>{1.0}, vec<1>{0.2}}, xb = xa;
        double worst = 0.0;
        run_summary sa, sb;
        for (std::size_t j = 1; j <= 400; ++j) {
            advance(a, xa, 0.3, j, sa);
            advance(b, xb, 0.3, j, sb);
            worst = std::max({worst, std::abs(xa.q(0) - xb.q(0)), std::abs(xa.p(0) - xb.p(0))});
        }
        return worst;
    };
    for (scheme_spec spec :
         {scheme_spec(scheme_kind::simpson), scheme_spec(scheme_kind::gauss, 3)}) {
        const double same = difference(spec, stiffness_force{l});
        EXPECT_LE(same, 1e-12) << spec.label();
        RecordProperty("potential_vs_force_" + spec.label(), test::sci(same));
        caldirola_mathieu steady = l; // negative control: the force without its time dependence
        steady.eps = 0.0;
        EXPECT_GT(difference(spec, stiffness_force{steady}), 1e-2) << spec.label();
    }
}

TEST(TimeDependent, ResumedRunsContinueBitForBit) {
    // Automatic derivatives: the simplified iteration, whose kept Jacobian's time t̄ travels in
    // the history.
    caldirola_mathieu l;
    l.eps = 0.4;
    l.omega = 3.1;
    const lagrangian_system<caldirola_mathieu> sys(l);
    const double h = 0.05;
    const phase_state<1> x0{vec<1>{1.0}, vec<1>{0.2}};
    general::stepper<caldirola_mathieu> whole(sys, h, scheme_kind::simpson);
    run_state<1> a = run_state<1>::start(x0, 0.5);
    integrate_from(whole, a, 60, [](const auto&) {});

    general::stepper<caldirola_mathieu> first(sys, h, scheme_kind::simpson);
    run_state<1> b = run_state<1>::start(x0, 0.5);
    integrate_from(first, b, 30, [](const auto&) {});
    snapshot(first, b);
    ASSERT_EQ(b.history.size(), 6U); // kept, q̄, v̄; t̄, work, carry
    general::stepper<caldirola_mathieu> second(sys, h, scheme_kind::simpson);
    restore(second, b);
    integrate_from(second, b, 60, [](const auto&) {});
    EXPECT_EQ(a.x.q(0), b.x.q(0));
    EXPECT_EQ(a.x.p(0), b.x.p(0));
}

TEST(TimeDependent, StepJacobianMatchesFiniteDifferencesAndIsSymplectic) {
    // The Caldirola–Kanai map contracts (q, q̇) but is symplectic in (q, p): det J = 1 (d = 1).
    const caldirola_mathieu l;
    newton_options opt;
    opt.iteration = iteration_kind::newton;
    auto make = [&] {
        general::stepper<caldirola_mathieu> st(lagrangian_system<caldirola_mathieu>(l), 0.1,
                                               {scheme_kind::gauss, 3}, opt);
        st.set_time(2.0);
        return st;
    };
    const phase_state<1> x{vec<1>{0.7}, vec<1>{-0.4}};
    auto st = make();
    phase_state<1> y = x;
    ASSERT_TRUE(st.step(y).converged);
    Eigen::MatrixXd j;
    st.step_jacobian(x, j);
    Eigen::MatrixXd fd(2, 2);
    const double eps = 1e-6;
    for (int c = 0; c < 2; ++c) {
        phase_state<1> plus = x, minus = x;
        (c == 0 ? plus.q(0) : plus.p(0)) += eps;
        (c == 0 ? minus.q(0) : minus.p(0)) -= eps;
        auto sp = make(), sm = make();
        ASSERT_TRUE(sp.step(plus).converged && sm.step(minus).converged);
        fd.col(c) << (plus.q(0) - minus.q(0)) / (2 * eps), (plus.p(0) - minus.p(0)) / (2 * eps);
    }
    EXPECT_LE((j - fd).lpNorm<Eigen::Infinity>(), 1e-8);
    EXPECT_NEAR(j.determinant(), 1.0, 1e-13);
    RecordProperty("jacobian_vs_fd", test::sci((j - fd).lpNorm<Eigen::Infinity>()));
    RecordProperty("det_minus_one", test::sci(std::abs(j.determinant() - 1.0)));
}

namespace {

// Kapitza's pendulum: the pivot at height a cos Ωt, the bob at the pivot + x with |x| = ℓ = 1,
// m = g = 1.
struct drive {
    double a = 0.1, omega = 30.0;
    double height(double t) const { return a * std::cos(omega * t); }
    double rate(double t) const { return -a * omega * std::sin(omega * t); }
};
struct kapitza_cartesian {
    static constexpr int dim = 2;
    drive pivot;
    template <class T>
    T operator()(const tvec<T, 2>& q, const tvec<T, 2>& v, double t) const {
        const T vy = v(1) + pivot.rate(t); // the bob's velocity in the fixed frame
        return 0.5 * (v(0) * v(0) + vy * vy) - (q(1) + pivot.height(t));
    }
};
struct kapitza_angle { // θ from the downward vertical: x = (sin θ, −cos θ)
    static constexpr int dim = 1;
    drive pivot;
    template <class T>
    T operator()(const tvec<T, 1>& q, const tvec<T, 1>& v, double t) const {
        using std::cos;
        using std::sin;
        const double w = pivot.rate(t);
        return 0.5 * v(0) * v(0) + w * v(0) * sin(q(0)) + cos(q(0)) + 0.5 * w * w - pivot.height(t);
    }
};
struct unit_rod {
    static constexpr int dim = 2, count = 1;
    template <class T>
    tvec<T, 1> operator()(const tvec<T, 2>& q) const {
        return tvec<T, 1>(q.squaredNorm() - 1.0);
    }
};

// From θ = π − 0.2 at rest at t = 0 (the pivot is then at rest too) to t = 10.
constexpr double kapitza_theta0 = std::numbers::pi - 0.2, kapitza_end = 10.0;

/// The angle form's θ(10) by gauss-3 with 8000 steps (Newton).
double kapitza_reference() {
    newton_options opt;
    opt.iteration = iteration_kind::newton;
    general::stepper<kapitza_angle> st(lagrangian_system<kapitza_angle>({}), kapitza_end / 8000,
                                       {scheme_kind::gauss, 3}, opt);
    phase_state<1> x{vec<1>{kapitza_theta0}, vec<1>{0.0}};
    integrate(st, x, 0.0, 8000, [](auto, auto, const auto&) {});
    return x.q(0);
}

struct kapitza_result {
    double error = 0.0, residual = 0.0, hidden = 0.0, from_top = 0.0;
};

/// n steps in Cartesian coordinates; error: |x(10) − x_ref(10)|.
kapitza_result kapitza_run(scheme_spec spec, int n, double theta_ref, double amplitude = 0.1) {
    kapitza_cartesian l;
    l.pivot.a = amplitude;
    general::constrained_stepper<kapitza_cartesian, unit_rod> st(
        lagrangian_system<kapitza_cartesian>(l), {}, kapitza_end / n, spec);
    phase_state<2> x{vec<2>{std::sin(kapitza_theta0), -std::cos(kapitza_theta0)}, vec<2>{0, 0}};
    st.check_initial(x);
    kapitza_result r;
    integrate(st, x, 0.0, static_cast<std::size_t>(n), [&](auto, auto, const phase_state<2>& y) {
        r.residual = std::max(r.residual, st.residual(y.q));
        r.hidden = std::max(r.hidden, st.hidden_residual(y));
        // The angle from the upward vertical.
        r.from_top = std::max(r.from_top, std::acos(std::clamp(y.q(1), -1.0, 1.0)));
    });
    r.error = (x.q - vec<2>{std::sin(theta_ref), -std::cos(theta_ref)}).lpNorm<Eigen::Infinity>();
    return r;
}

} // namespace

TEST(TimeDependent, KapitzaPendulumInAMovingFrameMatchesItsAngleForm) {
    const double theta_ref = kapitza_reference();
    for (const member& m : {member{scheme_kind::newmark, 2}, member{scheme_kind::simpson, 4},
                            member{{scheme_kind::gauss, 2}, 4}}) {
        const kapitza_result coarse = kapitza_run(m.spec, 1000, theta_ref),
                             fine = kapitza_run(m.spec, 2000, theta_ref);
        const double observed = std::log2(coarse.error / fine.error);
        SCOPED_TRACE(m.spec.label() + ": errors " + test::sci(coarse.error) + ", " +
                     test::sci(fine.error));
        EXPECT_NEAR(observed, m.order, 0.2);
        // The constraint's scale is ℓ² = 1, the hidden one's |x| |q̇| ≲ 3 (q̇ from p at each
        // step's own time: at t = 0 instead it would be off by the pivot's rate, up to 3).
        EXPECT_LE(std::max(coarse.residual, fine.residual), 1e-13);
        EXPECT_LE(std::max(coarse.hidden, fine.hidden), 1e-13);
        // a²Ω² = 9 > 2gℓ: the inverted pendulum stays up (it starts 0.2 from the top).
        EXPECT_LT(fine.from_top, 0.5);
        RecordProperty("kapitza_order_" + m.spec.label(), test::sci(observed));
        RecordProperty("kapitza_hidden_" + m.spec.label(), test::sci(fine.hidden));
    }
    // Without the drive it falls.
    EXPECT_GT(kapitza_run(scheme_kind::simpson, 1000, theta_ref, 0.0).from_top, 2.0);
}
