// Poincaré sections (run/section.hpp): the crossing of q = 0 (upwards) located on each step and
// refined on the scheme's own map, against the exact solution: the pendulum from rest at q0 = 2
// crosses at t = 3T/4 with p = sqrt(2 m E) (T from the elliptic integral), the unit oscillator
// from q0 = 1 at t = 3π/2 with p = 1. The error falls at the scheme's order (2s), which is the
// accuracy of the discrete flow itself; the polynomial's root alone is worse (negative control).
// The general engine (any L) finds the same crossings as the separable stepper of the same
// scheme on the same pendulum: its step is the same discrete map (schemes/variational.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <optional>

#include "varsym/problems/oscillator.hpp"
#include "varsym/problems/pendulum.hpp"
#include "varsym/run/section.hpp"
#include "varsym/schemes/scheme_kind.hpp"
#include "varsym/schemes/variational.hpp"

namespace varsym {
namespace {

struct crossing_error {
    double time, momentum;
};

/// The first upward crossing of q_0 = 0 from x0 with n steps per `period`, against (t*, p*).
template <class System, class X>
crossing_error first_crossing(const scheme_spec& spec, const System& sys, X x0, double period,
                              int n, double t_exact, double p_exact, bool refine) {
    const double h = period / n;
    const section_plane plane{false, 0, 0.0, +1};
    return with_stepper(spec, sys, h, {}, [&](auto& s) {
        X x = x0;
        for (int j = 0; j < 2 * n; ++j) {
            const X from = x;
            EXPECT_TRUE(s.step(x).converged);
            if (auto c = find_crossing(s, from, x, j * h, plane, refine))
                return crossing_error{std::abs(c->time - t_exact), std::abs(c->x.p(0) - p_exact)};
        }
        ADD_FAILURE() << "no crossing";
        return crossing_error{1.0, 1.0};
    });
}

TEST(section, pendulum_crossing_converges_at_the_scheme_order) {
    const double q0 = 2.0;
    const auto sys = pendulum::make_system(1.0, 1.0);
    const double period = pendulum::exact_solution(1.0, 1.0, q0, 0.0).period();
    const double p_star = std::sqrt(2.0 * (1.0 - std::cos(q0)));
    const phase_state<1> x0{vec<1>{q0}, vec<1>{0.0}};
    for (const scheme_spec spec :
         {scheme_spec(scheme_kind::simpson), scheme_spec(scheme_kind::newmark),
          scheme_spec(scheme_kind::gauss, 2), scheme_spec(scheme_kind::lobatto, 3)}) {
        SCOPED_TRACE(spec.label());
        const auto coarse = first_crossing(spec, sys, x0, period, 40, 0.75 * period, p_star, true);
        const auto fine = first_crossing(spec, sys, x0, period, 80, 0.75 * period, p_star, true);
        // Observed orders from halving h: the scheme's 2s, within 0.4 (asymptotic range).
        const double ot = std::log2(coarse.time / fine.time),
                     op = std::log2(coarse.momentum / fine.momentum);
        EXPECT_NEAR(ot, spec.order(), 0.4) << coarse.time << " " << fine.time;
        EXPECT_NEAR(op, spec.order(), 0.4) << coarse.momentum << " " << fine.momentum;
        if (spec.order() >= 4) {
            // Negative control: the polynomial's root alone is off by more (order s + 1).
            const auto poly =
                first_crossing(spec, sys, x0, period, 40, 0.75 * period, p_star, false);
            EXPECT_GT(poly.momentum, 3.0 * coarse.momentum);
        }
    }
}

TEST(section, oscillator_crossing_is_exact_to_the_scheme_error) {
    const Eigen::MatrixXd one = Eigen::MatrixXd::Identity(1, 1);
    const auto sys = oscillator::make_system(one, one);
    phase_state<dynamic> x0;
    x0.q = Eigen::VectorXd::Ones(1);
    x0.p = Eigen::VectorXd::Zero(1);
    const double period = 2.0 * std::numbers::pi;
    const auto c40 =
        first_crossing(scheme_kind::simpson, sys, x0, period, 40, 0.75 * period, 1.0, true);
    const auto c80 =
        first_crossing(scheme_kind::simpson, sys, x0, period, 80, 0.75 * period, 1.0, true);
    // Simpson's phase error on the oscillator is (hω)⁴ t/2880 per unit time: 3.7e-6 at t = 3π/2,
    // h = T/40 (the paper's eq. for the numerical frequency); the crossing inherits it.
    EXPECT_LT(c40.time, 1e-5);
    EXPECT_NEAR(std::log2(c40.time / c80.time), 4.0, 0.3);
    EXPECT_LT(c40.momentum, 2e-6); // measured 1.06e-6 ≈ (hω)⁴/576, also falling at order 4
    EXPECT_NEAR(std::log2(c40.momentum / c80.momentum), 4.0, 0.3);
}

TEST(section, no_crossing_in_the_other_direction_or_off_the_plane) {
    const auto sys = pendulum::make_system(1.0, 1.0);
    simpson::stepper s(sys, 0.1);
    phase_state<1> x{vec<1>{0.05}, vec<1>{-1.0}}, from = x;
    ASSERT_TRUE(s.step(x).converged); // q goes down through 0
    EXPECT_FALSE(find_crossing(s, from, x, 0.0, {false, 0, 0.0, +1}).has_value());
    EXPECT_TRUE(find_crossing(s, from, x, 0.0, {false, 0, 0.0, -1}).has_value());
    EXPECT_TRUE(find_crossing(s, from, x, 0.0, {false, 0, 0.0, 0}).has_value());
    EXPECT_FALSE(find_crossing(s, from, x, 0.0, {false, 0, 1.0, 0}).has_value());
}

/// The pendulum of pendulum::make_system(1, 1) as a Lagrangian (automatic derivatives).
struct section_pendulum_lagrangian {
    static constexpr int dim = 1;
    template <class T>
    T operator()(const tvec<T, 1>& q, const tvec<T, 1>& v) const {
        using std::cos;
        return 0.5 * v(0) * v(0) - (1.0 - cos(q(0)));
    }
};

/// The first crossing of `plane` by s from x0 (at most 2n steps of s's own size).
template <class S, class X>
std::optional<section_point<S::dim>> first_of(S& s, X x, const section_plane& plane, int n) {
    for (int j = 0; j < 2 * n; ++j) {
        const X from = x;
        EXPECT_TRUE(s.step(x).converged);
        if (auto c = find_crossing(s, from, x, j * s.step_size(), plane)) return c;
    }
    return std::nullopt;
}

TEST(section, general_engine_crosses_where_the_separable_stepper_does) {
    const double q0 = 2.0, period = pendulum::exact_solution(1.0, 1.0, q0, 0.0).period();
    const auto sep = pendulum::make_system(1.0, 1.0);
    const lagrangian_system<section_pendulum_lagrangian> gen{section_pendulum_lagrangian{}};
    const phase_state<1> x0{vec<1>{q0}, vec<1>{0.0}};
    const double p_star = std::sqrt(2.0 * (1.0 - std::cos(q0)));
    // q = 0 upwards (at 3T/4, p = p*) and p = 0 upwards (at T/2, q = −q0): the second uses the
    // rate ṗ = ∂L/∂q of the Lagrangian path.
    const section_plane through_q{false, 0, 0.0, +1}, through_p{true, 0, 0.0, +1};
    for (const scheme_spec spec :
         {scheme_spec(scheme_kind::simpson), scheme_spec(scheme_kind::gauss, 2)}) {
        SCOPED_TRACE(spec.label());
        const double h = period / 40;
        general::stepper<section_pendulum_lagrangian> g(gen, h, spec,
                                                        {.iteration = iteration_kind::newton});
        static_assert(dense_stepper<decltype(g)>);
        const auto gq = first_of(g, x0, through_q, 40);
        general::stepper<section_pendulum_lagrangian> g2(gen, h, spec,
                                                         {.iteration = iteration_kind::newton});
        const auto gp = first_of(g2, x0, through_p, 40);
        ASSERT_TRUE(gq && gp);
        with_stepper(spec, sep, h, {}, [&](auto& s) {
            const auto sq = first_of(s, x0, through_q, 40);
            auto s2 = s.with_step_size(h);
            const auto sp = first_of(s2, x0, through_p, 40);
            ASSERT_TRUE(sq && sp);
            // The same map, solved by another path: agreement to round-off (measured ≤ 5e-16).
            EXPECT_NEAR(gq->time, sq->time, 1e-12);
            EXPECT_NEAR(gq->x.p(0), sq->x.p(0), 1e-12);
            EXPECT_NEAR(gp->time, sp->time, 1e-12);
            EXPECT_NEAR(gp->x.q(0), sp->x.q(0), 1e-12);
        });
        // And both near the exact crossing, to the scheme's error at h = T/40 (order 4: the
        // pendulum test above measures ~1e-5 in time).
        EXPECT_NEAR(gq->time, 0.75 * period, 1e-4);
        EXPECT_NEAR(gq->x.p(0), p_star, 1e-4);
        EXPECT_NEAR(gp->time, 0.5 * period, 1e-4);
        EXPECT_NEAR(gp->x.q(0), -q0, 1e-4);
    }
}

} // namespace
} // namespace varsym
