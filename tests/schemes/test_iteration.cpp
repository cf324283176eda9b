// tests/schemes/test_iteration.cpp: the family stepper's iterations and predictors
// (newton_options::iteration, ::predictor). The reference is the stepper's own full Newton
// with the Taylor predictor: every variant must solve the same equations to the same round-off
// floor, so from the same state its step may differ only by round-off (the bound,
// 1e-13 relative to the state, is ~500 ulp). Negative controls show that the comparison sees a
// step stopped early and that a resume without the history is not bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <numbers>
#include <string>
#include <vector>

#include "compare_steppers.hpp"
#include "varsym/problems/kepler.hpp"
#include "varsym/problems/pendulum.hpp"
#include "varsym/problems/solar_system.hpp"
#include "varsym/run/state.hpp"
#include "varsym/schemes/galerkin.hpp"

using namespace varsym;
using galerkin::rule_kind;

namespace {

struct variant {
    iteration_kind iteration;
    predictor_kind predictor;
};
const std::vector<variant> variants = {{iteration_kind::newton, predictor_kind::previous},
                                       {iteration_kind::simplified, predictor_kind::taylor},
                                       {iteration_kind::simplified, predictor_kind::previous},
                                       {iteration_kind::fixed_point, predictor_kind::taylor},
                                       {iteration_kind::fixed_point, predictor_kind::previous},
                                       {iteration_kind::newton, predictor_kind::forces},
                                       {iteration_kind::fixed_point, predictor_kind::forces}};

newton_options options_of(const variant& v) {
    newton_options o;
    o.iteration = v.iteration;
    o.predictor = v.predictor;
    return o;
}

/// Steps n times with `opt` from x0; before each step, Newton (Taylor start) steps from the same
/// state. Returns the largest difference of the two steps relative to max(1, |q|, |p|), and the
/// mean iterations per step of `opt`.
template <class System>
std::pair<double, double> step_difference(const System& sys, phase_state<System::dim> x, double h,
                                          rule_kind kind, int s, const newton_options& opt, int n) {
    newton_options full;
    full.iteration = iteration_kind::newton;
    galerkin::stepper<System> tried(sys, h, kind, s, opt), newton(sys, h, kind, s, full);
    double worst = 0.0, iterations = 0.0;
    for (int j = 0; j < n; ++j) {
        phase_state<System::dim> y = x;
        EXPECT_TRUE(newton.step(y).converged);
        const newton_report rep = tried.step(x);
        EXPECT_TRUE(rep.converged);
        iterations += rep.iterations;
        const double scale = std::max(
            {1.0, x.q.template lpNorm<Eigen::Infinity>(), x.p.template lpNorm<Eigen::Infinity>()});
        worst = std::max({worst, (x.q - y.q).template lpNorm<Eigen::Infinity>() / scale,
                          (x.p - y.p).template lpNorm<Eigen::Infinity>() / scale});
    }
    return {worst, iterations / n};
}

template <class System>
void expect_same_steps(const char* name, const System& sys, const phase_state<System::dim>& x0,
                       double h, int n) {
    for (rule_kind kind : {rule_kind::gauss, rule_kind::lobatto})
        for (int s = kind == rule_kind::gauss ? 2 : 3; s <= 6; ++s)
            for (const variant& v : variants) {
                const auto [diff, its] = step_difference(sys, x0, h, kind, s, options_of(v), n);
                EXPECT_LE(diff, 1e-13)
                    << name << (kind == rule_kind::gauss ? " gauss-" : " lobatto-") << s
                    << " iteration " << static_cast<int>(v.iteration) << " predictor "
                    << static_cast<int>(v.predictor);
            }
}

} // namespace

TEST(Iteration, EveryVariantTakesNewtonsSteps) {
    // The pendulum from q0 = π/2 at 20 steps per period, Kepler e = 0.6 at 100 steps per orbit
    // (through pericentre, where the step is hardest), and the outer solar system at 40 steps
    // per Jupiter period (d = 18).
    const double pendulum_period =
        pendulum::exact_solution(1.0, 2 * std::numbers::pi, std::numbers::pi / 2, 0.0).period();
    expect_same_steps("pendulum", pendulum::make_system(1.0, 2 * std::numbers::pi),
                      phase_state<1>{vec<1>{std::numbers::pi / 2}, vec<1>{0.0}},
                      pendulum_period / 20, 60);
    const kepler::orbit orbit(0.6, 1.0);
    expect_same_steps("kepler", kepler::make_system(), orbit.at(0.0L), orbit.period() / 100, 120);
    expect_same_steps("solar", solar_system::make_system(), solar_system::initial_state(),
                      solar_system::jupiter_period / 40, 40);
}

TEST(Iteration, DefaultIsTheFixedPoint) {
    // The default (iteration_kind::automatic), chosen by measurement (docs/performance.md): the
    // same steps, bit for bit and iteration for iteration, as the fixed point, at d = 1 and 2,
    // and not Newton's (the control: the two differ in their iteration counts).
    auto run = [](const auto& sys, auto x, double h, iteration_kind it) {
        newton_options opt;
        opt.iteration = it;
        galerkin::stepper st(sys, h, rule_kind::gauss, 4, opt);
        int iterations = 0;
        for (int j = 0; j < 50; ++j)
            iterations += st.step(x).iterations;
        return std::pair{x, iterations};
    };
    const kepler::orbit orbit(0.6, 1.0);
    const auto kepler_sys = kepler::make_system();
    const double h = orbit.period() / 100;
    const auto [xa, na] = run(kepler_sys, orbit.at(0.0L), h, iteration_kind::automatic);
    const auto [xf, nf] = run(kepler_sys, orbit.at(0.0L), h, iteration_kind::fixed_point);
    const auto [xn, nn] = run(kepler_sys, orbit.at(0.0L), h, iteration_kind::newton);
    EXPECT_EQ(na, nf);
    EXPECT_NE(na, nn);
    EXPECT_EQ((xa.q - xf.q).norm() + (xa.p - xf.p).norm(), 0.0);
    const auto pendulum_system = pendulum::make_system(1.0, 2 * std::numbers::pi);
    const phase_state<1> p0{vec<1>{std::numbers::pi / 2}, vec<1>{0.0}};
    const auto [ya, ma] = run(pendulum_system, p0, 0.02, iteration_kind::automatic);
    const auto [yn, mn] = run(pendulum_system, p0, 0.02, iteration_kind::newton);
    const auto [yf, mf] = run(pendulum_system, p0, 0.02, iteration_kind::fixed_point);
    EXPECT_EQ(ma, mf);
    EXPECT_NE(ma, mn);
    EXPECT_EQ(ya.q(0), yf.q(0));
    EXPECT_EQ(ya.p(0), yf.p(0));
}

TEST(Iteration, ComparisonSeesAStepStoppedEarly) {
    // Negative control: the fixed point told to stop at a 1e-6 update leaves the step's
    // equations unsolved by far more than the bound above.
    newton_options loose = options_of({iteration_kind::fixed_point, predictor_kind::taylor});
    loose.tolerance = 1e-6;
    const kepler::orbit orbit(0.6, 1.0);
    const auto [diff, its] = step_difference(kepler::make_system(), orbit.at(0.0L),
                                             orbit.period() / 100, rule_kind::gauss, 4, loose, 50);
    EXPECT_GT(diff, 1e-13);
}

TEST(Iteration, PreviousStepPredictorSavesIterations) {
    // The previous step's polynomial continued is O(h^(s+1)) where Taylor is O(h³): the linear
    // iterations need fewer sweeps from it (a predictor silently not used would fail this).
    const kepler::orbit orbit(0.6, 1.0);
    for (iteration_kind it : {iteration_kind::simplified, iteration_kind::fixed_point}) {
        const auto sys = kepler::make_system();
        const double h = orbit.period() / 200;
        const auto taylor = step_difference(sys, orbit.at(0.0L), h, rule_kind::gauss, 5,
                                            options_of({it, predictor_kind::taylor}), 200);
        const auto previous = step_difference(sys, orbit.at(0.0L), h, rule_kind::gauss, 5,
                                              options_of({it, predictor_kind::previous}), 200);
        EXPECT_LT(previous.second, taylor.second - 0.1) << static_cast<int>(it);
    }
}

TEST(Iteration, ForcesPredictorSavesMoreIterations) {
    // The previous step's gradients continued are O(h^(r+1)) and enter X through h², so the
    // start is two orders closer than the polynomial continued: fewer sweeps still, on Kepler
    // (e = 0.6) and the pendulum, Gauss and Lobatto (a predictor silently not used would fail).
    const kepler::orbit orbit(0.6, 1.0);
    const auto sys = kepler::make_system();
    const double h = orbit.period() / 100;
    for (rule_kind kind : {rule_kind::gauss, rule_kind::lobatto}) {
        const auto previous = step_difference(
            sys, orbit.at(0.0L), h, kind, 4,
            options_of({iteration_kind::fixed_point, predictor_kind::previous}), 200);
        const auto forces =
            step_difference(sys, orbit.at(0.0L), h, kind, 4,
                            options_of({iteration_kind::fixed_point, predictor_kind::forces}), 200);
        EXPECT_LT(forces.second, previous.second - 0.5) << static_cast<int>(kind);
        EXPECT_LE(forces.first, 1e-13);
    }
}

TEST(Iteration, ForceExtrapolationAndClosedFormTables) {
    // force_extrapolation continues samples at the previous step's nodes c_m − 1 (and 0 for
    // Gauss) to c_k: exact for polynomials of degree < the number of samples. The closed form's
    // tables [K, c] must solve A [Kᵀ, c] = [U, −e_0] for A and U as applied (kinetic, wphi,
    // with their low parts) far below an ulp: checked in long double (1e-19), where the double
    // parts alone miss by ~1e-16 (the control: a closed form without its low parts would leave
    // a root off by an ulp at every step).
    for (rule_kind kind : {rule_kind::gauss, rule_kind::lobatto})
        for (int s = 1; s <= 8; ++s) {
            const galerkin::tableau t = galerkin::tableau::make(kind, s);
            const Eigen::MatrixXd& e = t.force_extrapolation;
            const auto r = static_cast<Eigen::Index>(t.quad.nodes.size());
            ASSERT_EQ(e.cols(), r);
            ASSERT_EQ(e.rows(), kind == rule_kind::gauss ? r + 1 : r);
            for (Eigen::Index k = 0; k < e.rows(); ++k)
                for (Eigen::Index c = 0; c < r; ++c) {
                    double sum = 0.0, size = 0.0;
                    for (Eigen::Index m = 0; m < e.rows(); ++m) {
                        const double at = m < r ? t.quad.nodes[static_cast<std::size_t>(m)] - 1 : 0;
                        sum += e(m, c) * std::pow(at, static_cast<double>(k));
                        size += std::abs(e(m, c));
                    }
                    const double exact =
                        std::pow(t.quad.nodes[static_cast<std::size_t>(c)], static_cast<double>(k));
                    EXPECT_NEAR(sum, exact, 1e-14 * size) << "s = " << s << ", degree " << k;
                }
            using ld = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
            const ld a = t.kinetic.hi.cast<long double>() + t.kinetic.lo.cast<long double>();
            ld rhs(s, r + 1), hi(s, r + 1), lo(s, r + 1);
            rhs << t.wphi.hi.cast<long double>() + t.wphi.lo.cast<long double>(), ld::Zero(s, 1);
            rhs(0, r) = -1;
            hi << t.sweep.hi.transpose().cast<long double>(),
                t.flight.hi.transpose().cast<long double>();
            lo << t.sweep.lo.transpose().cast<long double>(),
                t.flight.lo.transpose().cast<long double>();
            const long double scale = a.cwiseAbs().maxCoeff() * hi.cwiseAbs().maxCoeff();
            const ld refined = a * (hi + lo) - rhs;
            EXPECT_LE(static_cast<double>(refined.cwiseAbs().maxCoeff() / scale), 1e-18)
                << "s = " << s;
            if (s >= 3) {
                const ld rounded = a * hi - rhs;
                EXPECT_GT(static_cast<double>(rounded.cwiseAbs().maxCoeff() / scale), 1e-18)
                    << "s = " << s;
            }
            // The free flight: c holds the control nodes d_1 … d_s.
            for (int l = 0; l < s; ++l)
                EXPECT_NEAR(t.flight.hi(0, l), t.control[static_cast<std::size_t>(l + 1)], 1e-15);
        }
}

TEST(Iteration, DivergingFixedPointFallsBackToNewton) {
    // The pendulum near the bottom (linear, ω = 2π) at h ω = 3: the fixed point's iteration
    // matrix, O((h ω)²), has a rate above 1, so it diverges; the step is then Newton's, at the
    // cost of the iterations spent.
    const auto sys = pendulum::make_system(1.0, 2 * std::numbers::pi);
    const phase_state<1> x0{vec<1>{0.1}, vec<1>{0.0}};
    const double h = 3.0 / (2 * std::numbers::pi);
    galerkin::stepper newton(sys, h, rule_kind::gauss, 3,
                             options_of({iteration_kind::newton, predictor_kind::taylor}));
    galerkin::stepper fixed(sys, h, rule_kind::gauss, 3,
                            options_of({iteration_kind::fixed_point, predictor_kind::taylor}));
    phase_state<1> a = x0, b = x0;
    const newton_report ra = newton.step(a), rb = fixed.step(b);
    ASSERT_TRUE(ra.converged);
    ASSERT_TRUE(rb.converged);
    EXPECT_GT(rb.iterations, ra.iterations + 1); // the diverging sweeps, then Newton's
    EXPECT_NEAR(b.q(0), a.q(0), 1e-15);
    EXPECT_NEAR(b.p(0), a.p(0), 1e-14);
}

TEST(Iteration, ExtrapolationContinuesPolynomialsOfDegreeS) {
    // q(t) = t^k on the previous step [0, 1] (k ≤ s), increments X_m = q(d_m) − q(0), continued
    // to 1 + d_l: exact, so Σ_m E(m, l) X_m = q(1 + d_l) − q(1), to round-off of entries of
    // size up to ~1e3.
    for (rule_kind kind : {rule_kind::gauss, rule_kind::lobatto})
        for (int s = 1; s <= 6; ++s) {
            const galerkin::tableau t = galerkin::tableau::make(kind, s);
            for (int k = 0; k <= s; ++k)
                for (int l = 1; l <= s; ++l) {
                    double sum = 0.0;
                    for (int m = 1; m <= s; ++m)
                        sum += t.extrapolation(m - 1, l - 1) *
                               (std::pow(t.control[m], k) - std::pow(0.0, k));
                    const double exact = std::pow(1.0 + t.control[l], k) - 1.0;
                    EXPECT_NEAR(sum, exact, 1e-11 * std::pow(2.0, k))
                        << "s = " << s << ", k = " << k << ", l = " << l;
                }
        }
}

TEST(Iteration, HistoryMakesAResumeBitForBit) {
    // gauss-4 on Kepler with the previous-step predictor and a kept Jacobian: 300 steps straight,
    // or 137, a run_state saved and restored into a new stepper, and the rest. Without the
    // history the run restarts its predictor and Jacobian, which changes its iterations and
    // its last bits (the negative control in test::expect_resume_needs_history).
    const kepler::orbit orbit(0.6, 1.0);
    const auto sys = kepler::make_system();
    const double h = orbit.period() / 100;
    const newton_options opt = options_of({iteration_kind::simplified, predictor_kind::previous});
    auto make = [&] { return galerkin::stepper(sys, h, rule_kind::gauss, 4, opt); };
    const auto history = test::expect_resume_needs_history(make, orbit.at(0.0L), 300, 137);
    EXPECT_EQ(history.size(), 1U + 2 * 4 + 1 + 2);
    // The forces predictor keeps the last step's gradients at its r points (Lobatto: s + 1) and
    // the last contraction rate. At h = T/200 the resumed step without them starts from Taylor
    // and needs a sweep more (at T/100 both starts can need the same sweeps and, the last sweep
    // landing on the root to round-off, the same bits: then the control cannot see them).
    for (rule_kind kind : {rule_kind::gauss, rule_kind::lobatto}) {
        SCOPED_TRACE(kind == rule_kind::gauss ? "gauss-4, forces" : "lobatto-4, forces");
        const newton_options fo = options_of({iteration_kind::fixed_point, predictor_kind::forces});
        auto forces = [&] { return galerkin::stepper(sys, h / 2, kind, 4, fo); };
        const auto kept = test::expect_resume_needs_history(forces, orbit.at(0.0L), 300, 137);
        EXPECT_EQ(kept.size(), 1U + 2 * (kind == rule_kind::gauss ? 4 : 5) + 1);
    }
}
