// tests/schemes/test_general_iteration.cpp: the general engine's linear iterations (simplified
// Newton and the fixed point, schemes/variational_solve.hpp) and Newton's chord updates against
// its full Newton.
// Reference: Newton on the same step equations with the exact Jacobian at every iterate
// (newton_options::chord_start = 0; schemes/variational.hpp,
// tested against the separable paths in test_general.cpp). Every variant solves the same
// equations to round-off, so each step from a state of Newton's run must equal Newton's step
// from it to 1e-13 relative (a few hundred ulps: two iterations that stop at the round-off floor
// from different last iterates). Negative control: a linear iteration stopped at 1e-6 differs.
#include <gtest/gtest.h>

#include <algorithm>

#include "compare_steppers.hpp"
#include "varsym/problems/heavy_top.hpp"
#include "varsym/problems/kepler.hpp"
#include "varsym/problems/linked_pendulum.hpp"
#include "varsym/run/state.hpp"
#include "varsym/schemes/variational.hpp"
#include "varsym/solvers/solver_name.hpp"

using namespace varsym;

namespace {

// A three-link pendulum: its mass matrix depends on q, so L_vv and L_qv change along the run.
const linked_pendulum::lagrangian<3> arm({1.0, 0.7, 0.4}, {1.0, 0.8, 0.6}, 9.81);
const phase_state<3> arm_x0{vec<3>{1.2, -0.4, 0.9}, vec<3>{0.0, 0.5, -0.3}};
using arm_ad = linked_pendulum::automatic<3>;
const kepler::orbit orbit(0.6, 1.0);

newton_options options(iteration_kind kind, double tolerance = 0.0) {
    newton_options o;
    o.iteration = kind;
    if (tolerance > 0.0) o.tolerance = tolerance;
    return o;
}

/// Newton with a fresh Jacobian at every iterate: no chord updates.
newton_options full_newton() {
    newton_options o = options(iteration_kind::newton);
    o.chord_start = 0.0;
    return o;
}

/// The largest difference, relative to max(|q|, |p|, 1), of one step of the variant `opt`
/// from full Newton's step, from every state of n steps of full Newton's run.
template <class L>
double worst_gap(const lagrangian_system<L>& sys, double h, scheme_spec spec, phase_state<L::dim> x,
                 int n, const newton_options& opt) {
    general::stepper<L> newton(sys, h, spec, full_newton()), variant(sys, h, spec, opt);
    double worst = 0.0;
    for (int j = 0; j < n; ++j) {
        phase_state<L::dim> y = x;
        EXPECT_TRUE(newton.step(x).converged);
        EXPECT_TRUE(variant.step(y).converged);
        const double scale = std::max(
            {x.q.template lpNorm<Eigen::Infinity>(), x.p.template lpNorm<Eigen::Infinity>(), 1.0});
        worst = std::max({worst, (x.q - y.q).template lpNorm<Eigen::Infinity>() / scale,
                          (x.p - y.p).template lpNorm<Eigen::Infinity>() / scale});
    }
    return worst;
}

} // namespace

TEST(GeneralIteration, EveryVariantTakesNewtonsStep) {
    // Newton's own chord updates (the default, newton_options::chord_start) among the variants.
    for (auto kind :
         {iteration_kind::newton, iteration_kind::simplified, iteration_kind::fixed_point}) {
        const newton_options opt = options(kind);
        for (scheme_spec spec :
             {scheme_spec(scheme_kind::simpson), scheme_spec(scheme_kind::newmark),
              scheme_spec(scheme_kind::gauss, 4), scheme_spec(scheme_kind::lobatto, 4)}) {
            SCOPED_TRACE(spec.label() + " " + std::string(name_of(iteration_names, kind)));
            EXPECT_LE(worst_gap(lagrangian_system<kepler::lagrangian>({}), orbit.period() / 100,
                                spec, orbit.at(0.0), 200, opt),
                      1e-13);
            EXPECT_LE(worst_gap(lagrangian_system<linked_pendulum::lagrangian<3>>(arm), 0.02, spec,
                                arm_x0, 200, opt),
                      1e-13);
            EXPECT_LE(worst_gap(lagrangian_system<arm_ad>({arm}), 0.02, spec, arm_x0, 100, opt),
                      1e-13);
        }
        const auto top = heavy_top::make_system({});
        const vec<3> q{1.0, 0.0, 0.0};
        EXPECT_LE(worst_gap(top, 0.01, scheme_kind::simpson,
                            phase_state<3>{q, top.momentum(q, vec<3>{0.0, 0.5, 8.0})}, 200, opt),
                  1e-13);
    }
}

TEST(GeneralIteration, StoppedEarlyItDiffers) {
    // Negative control for the 1e-13 above: the same comparison detects a looser stop.
    const double gap =
        worst_gap(lagrangian_system<linked_pendulum::lagrangian<3>>(arm), 0.02,
                  {scheme_kind::gauss, 4}, arm_x0, 50, options(iteration_kind::simplified, 1e-6));
    EXPECT_GT(gap, 1e-11);
}

namespace {
/// Kepler's Lagrangian with its derivatives by hand, counting how often each kind is asked for.
struct counting {
    static constexpr int dim = 2;
    separable_lagrangian<kepler::system> l{kepler::make_system()};
    mutable int gradients = 0, hessians = 0;
    double operator()(const vec<2>& q, const vec<2>& v) const { return l(q, v); }
    void gradient(const vec<2>& q, const vec<2>& v, lagrangian_terms<2>& t) const {
        ++gradients;
        l.gradient(q, v, t);
    }
    void derivatives(const vec<2>& q, const vec<2>& v, lagrangian_terms<2>& t) const {
        ++hessians;
        l.derivatives(q, v, t);
    }
};
} // namespace

TEST(GeneralIteration, SweepsEvaluateFirstDerivativesOnly) {
    // Full Newton evaluates second derivatives at every point of every iterate (and at the
    // predictor's two points), and first derivatives only for the momentum; with chord updates
    // Newton builds fewer Jacobians, and its chord updates evaluate first derivatives; the
    // simplified iteration evaluates second derivatives only where it refreshes its Jacobian
    // (two per refresh: the Taylor predictor's), which on Kepler at 100 steps per orbit is
    // seldom. Gauss-4: 4 points.
    const int n = 200;
    auto count = [&](const newton_options& opt) {
        general::stepper<counting> s(lagrangian_system<counting>({}), orbit.period() / 100,
                                     {scheme_kind::gauss, 4}, opt);
        phase_state<2> x = orbit.at(0.0);
        for (int j = 0; j < n; ++j)
            EXPECT_TRUE(s.step(x).converged);
        return std::pair{s.system().lagrangian().hessians, s.system().lagrangian().gradients};
    };
    const auto [full_h, full_g] = count(full_newton());
    EXPECT_GE(full_h, (2 + 2 * 4) * n); // predictor, ≥ 2 iterations × 4 points
    EXPECT_EQ(full_g, 4 * n);           // the momentum's
    const auto [chord_h, chord_g] = count(options(iteration_kind::newton));
    // At this coarse step (100 per orbit) most steps' second update is a chord update.
    EXPECT_LE(chord_h, full_h - 4 * n / 2);
    EXPECT_GE(chord_g, 4 * n + 4 * n / 2);
    const auto [simplified_h, simplified_g] = count(options(iteration_kind::simplified));
    EXPECT_LE(simplified_h, n / 5) << "the kept Jacobian is refreshed too often";
    EXPECT_GE(simplified_g, 3 * 4 * n); // ≥ 3 sweeps × 4 points per step
}

TEST(GeneralIteration, DefaultIsSimplifiedForAutomaticDerivatives) {
    // `automatic`: the simplified iteration for Kepler's L by AD, Newton for it by hand. The
    // default run repeats the explicit one to the bit and to the iteration count.
    auto run = [](auto sys, const newton_options& opt, long& iterations) {
        general::stepper s(sys, orbit.period() / 100, {scheme_kind::gauss, 4}, opt);
        phase_state<2> x = orbit.at(0.0);
        iterations = 0;
        for (int j = 0; j < 50; ++j)
            iterations += s.step(x).iterations;
        return x;
    };
    const lagrangian_system<kepler::lagrangian> ad({});
    const lagrangian_system<counting> hand({});
    long n_default = 0, n_simplified = 0, n_newton = 0;
    const auto a = run(ad, {}, n_default),
               b = run(ad, options(iteration_kind::simplified), n_simplified);
    run(ad, options(iteration_kind::newton), n_newton);
    EXPECT_TRUE(a.q == b.q && a.p == b.p);
    EXPECT_EQ(n_default, n_simplified);
    EXPECT_NE(n_default, n_newton); // the counts tell the two apart (2 per step against ~5)
    long h_default = 0, h_newton = 0;
    run(hand, {}, h_default);
    run(hand, options(iteration_kind::newton), h_newton);
    EXPECT_EQ(h_default, h_newton);
    EXPECT_EQ(h_newton, 2 * 50);
}

TEST(GeneralIteration, DivergenceHandsTheStepToNewton) {
    // One link (a pendulum, ω = √(g/l) = π): at h ω = 3 the fixed point's free-particle Jacobian
    // misses the curvature by (hω)², so its iteration diverges, and the step falls to Newton.
    using one = linked_pendulum::lagrangian<1>;
    const one l({1.0}, {9.81 / (std::numbers::pi * std::numbers::pi)}, 9.81);
    const double h = 3.0 / std::numbers::pi;
    const phase_state<1> x0{vec<1>{2.0}, vec<1>{0.0}};
    general::stepper<one> newton(lagrangian_system<one>(l), h, {scheme_kind::gauss, 2});
    general::stepper<one> fixed(lagrangian_system<one>(l), h, {scheme_kind::gauss, 2},
                                options(iteration_kind::fixed_point));
    phase_state<1> x = x0, y = x0;
    const newton_report a = newton.step(x), b = fixed.step(y);
    ASSERT_TRUE(a.converged);
    ASSERT_TRUE(b.converged);
    EXPECT_GT(b.iterations, a.iterations); // the fixed point's sweeps, then Newton's
    EXPECT_LE(std::abs(x.q(0) - y.q(0)), 1e-13);
    EXPECT_LE(std::abs(x.p(0) - y.p(0)), 1e-13);
}

TEST(GeneralIteration, HistoryMakesAResumeBitForBit) {
    // The kept Jacobian's point goes into run_state::history: 300 steps of Kepler (AD) straight,
    // or 137, the state saved and restored into a new stepper, and the rest. Without the
    // history the Jacobian is refreshed at step 137, which changes the sweeps and the last bits
    // (the negative control in test::expect_resume_needs_history).
    using L = kepler::lagrangian;
    const lagrangian_system<L> sys({});
    auto make = [&] {
        return general::stepper<L>(sys, orbit.period() / 100, {scheme_kind::gauss, 4},
                                   options(iteration_kind::simplified));
    };
    const auto history = test::expect_resume_needs_history(make, orbit.at(0.0), 300, 137);
    ASSERT_EQ(history.size(), 1U + 2 * 2);
    EXPECT_EQ(history[0], 1.0); // a Jacobian is kept there: the history matters
    auto d = make();
    auto e = run_state<2>::start(orbit.at(0.0));
    e.history = history;
    e.history.pop_back();
    EXPECT_THROW(restore(d, e), std::invalid_argument);
}
