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
#include <memory>
#include <tuple>
#include <vector>

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
    // predictor's two points), and takes the momentum from the last iterate's; with chord updates
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
    // The momentum from the last iterate's derivatives on most steps (where that is within
    // round-off: momentum_change_linearised), else 4 gradients.
    EXPECT_LE(full_g, 4 * n / 4);
    EXPECT_GT(full_g, 0); // and the guard does send some steps to the evaluation
    const auto [chord_h, chord_g] = count(options(iteration_kind::newton));
    // At this coarse step (100 per orbit) most steps' second update is a chord update.
    EXPECT_LE(chord_h, full_h - 4 * n / 2);
    EXPECT_GE(chord_g, 4 * n / 2);
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

namespace {
/// The three-link arm by hand, logging every evaluation: (second derivatives?, q, q̇).
struct logging {
    static constexpr int dim = 3;
    linked_pendulum::lagrangian<3> l;
    std::shared_ptr<std::vector<std::tuple<bool, vec<3>, vec<3>>>> log =
        std::make_shared<std::vector<std::tuple<bool, vec<3>, vec<3>>>>();
    double operator()(const vec<3>& q, const vec<3>& v) const { return l(q, v); }
    void gradient(const vec<3>& q, const vec<3>& v, lagrangian_terms<3>& t) const {
        log->emplace_back(false, q, v);
        l.gradient(q, v, t);
    }
    void derivatives(const vec<3>& q, const vec<3>& v, lagrangian_terms<3>& t) const {
        log->emplace_back(true, q, v);
        l.derivatives(q, v, t);
    }
    /// Chord updates dropped: second derivatives asked for where first derivatives were
    /// just evaluated (the same point among the last 4 evaluations: gauss-4's points).
    [[nodiscard]] int dropped() const {
        int n = 0;
        for (std::size_t i = 1; i < log->size(); ++i) {
            if (!std::get<0>((*log)[i])) continue;
            for (std::size_t k = i > 4 ? i - 4 : 0; k < i; ++k)
                if (!std::get<0>((*log)[k]) && std::get<1>((*log)[k]) == std::get<1>((*log)[i]) &&
                    std::get<2>((*log)[k]) == std::get<2>((*log)[i])) {
                    ++n;
                    break;
                }
        }
        return n;
    }
};

/// The general engine's Newton solve and its two momenta (protected in the stepper).
template <class L, class F = unforced>
struct momentum_probe : general::stepper<L, F> {
    using general::stepper<L, F>::stepper;
    bool solve(const phase_state<L::dim>& x) { return this->solve_newton(x).converged; }
    /// Whether the last solve's guard let the step take the momentum from its last iterate.
    [[nodiscard]] bool guarded() const { return this->linearised_; }
    [[nodiscard]] double work() const { return this->work_; }
    /// Σ_k w_k |f_k| |v_k| at the current increments (after evaluated()): the size of the
    /// work's terms, which can cancel in the work itself.
    double work_terms(const phase_state<L::dim>& x) {
        double sum = 0.0;
        if constexpr (!std::is_same_v<F, unforced>)
            for (int k = 0; k < this->r_; ++k) {
                this->set_point(x.q, k);
                sum += this->tab_.quad.weights[static_cast<std::size_t>(k)] *
                       this->fterms_[static_cast<std::size_t>(k)]
                           .f.template lpNorm<Eigen::Infinity>() *
                       this->vk_.template lpNorm<Eigen::Infinity>();
            }
        return sum;
    }
    vec<L::dim> linearised(const phase_state<L::dim>& x, bool correct) {
        if (!correct) this->delta_.setZero();
        EXPECT_TRUE(this->momentum_change_linearised(x));
        return this->dp_;
    }
    vec<L::dim> evaluated(const phase_state<L::dim>& x) {
        EXPECT_TRUE(this->momentum_change(x));
        return this->dp_;
    }
};
} // namespace

TEST(GeneralIteration, DroppedChordUpdatesGiveNewtonsStep) {
    // A chord update that contracts less than 8 times is dropped and the iterate gets a fresh
    // Jacobian. With chord_start = 0.5 chords begin after the first Newton update, and on the
    // arm at h = 0.1 some contract too slowly: the steps still equal full Newton's to 1e-13
    // (EveryVariantTakesNewtonsStep's bound). The log shows the path was taken (not vacuous).
    newton_options opt = options(iteration_kind::newton);
    opt.chord_start = 0.5;
    const lagrangian_system<logging> sys(logging{arm});
    EXPECT_LE(worst_gap(sys, 0.1, {scheme_kind::gauss, 4}, arm_x0, 100, opt), 1e-13);
    EXPECT_GT(sys.lagrangian().dropped(), 0);
}

TEST(GeneralIteration, MomentumFromTheLastIterateIsTheStepsMomentum) {
    // p_{j+1} − p_j from Newton's last iterate's derivatives, corrected to first order for the
    // last update (momentum_change_linearised), against h Σ w_k L_q evaluated again at the
    // converged increments (momentum_change), on the arm (by hand) and Kepler (AD), default
    // Newton (a chord update last) and full Newton, over 100 steps of a run. Either is the
    // momentum at increments known to Newton's stop, so they agree to
    // EveryVariantTakesNewtonsStep's 1e-13 of p (measured: 1.2e-14 on the arm). Negative control:
    // without the correction they differ by 1e-8 (the last updates are that large), so the
    // correction is what agrees.
    auto check = [](auto sys, double h, auto x, const newton_options& opt) {
        using L = typename decltype(sys)::lagrangian_type;
        momentum_probe<L> probe(sys, h, {scheme_kind::gauss, 4}, opt);
        general::stepper<L> run(sys, h, {scheme_kind::gauss, 4}, opt);
        double worst = 0.0, uncorrected = 0.0;
        for (int j = 0; j < 100; ++j) {
            const double scale = std::max(1.0, x.p.template lpNorm<Eigen::Infinity>());
            EXPECT_TRUE(probe.solve(x));
            const auto a = probe.linearised(x, true), b = probe.evaluated(x);
            worst = std::max(worst, (a - b).template lpNorm<Eigen::Infinity>() / scale);
            EXPECT_TRUE(probe.solve(x));
            const auto c = probe.linearised(x, false);
            uncorrected = std::max(uncorrected, (c - b).template lpNorm<Eigen::Infinity>() / scale);
            EXPECT_TRUE(run.step(x).converged);
        }
        EXPECT_LE(worst, 1e-13);
        EXPECT_GT(uncorrected, 1e-11);
    };
    for (const newton_options& opt : {options(iteration_kind::newton), full_newton()}) {
        check(lagrangian_system<linked_pendulum::lagrangian<3>>(arm), 0.02, arm_x0, opt);
        check(lagrangian_system<kepler::lagrangian>({}), orbit.period() / 100, orbit.at(0.0), opt);
    }
}

namespace {
/// A force on the arm with Jacobians neither symmetric nor constant, by AD (no derivatives by
/// hand, so chord updates keep the Jacobian iterate's f_q and f_v): a q-dependent drag and a
/// circulatory coupling.
struct drag_and_twist {
    static constexpr int dim = 3;
    template <class T>
    tvec<T, 3> operator()(const tvec<T, 3>& q, const tvec<T, 3>& v, double) const {
        using std::sin;
        tvec<T, 3> f;
        f(0) = -0.3 * (1.0 + 0.5 * sin(q(1))) * v(0) + 0.4 * q(2);
        f(1) = -0.2 * v(1) * v(0) - 0.3 * q(0);
        f(2) = -0.1 * v(2) + 0.2 * sin(q(0)) * v(1);
        return f;
    }
};
} // namespace

TEST(GeneralIteration, MomentumAndWorkFromTheLastIterateWithAForce) {
    // As above with forces that join L_q: Rayleigh damping (Jacobians by hand) and a force by AD
    // whose f_q and f_v are neither symmetric nor constant (a transposed or stale Jacobian shows).
    // The step's work Σ_k w_k f_k·v_k comes from f corrected to first order at the converged
    // velocities. The momentum agrees with its evaluation at the converged increments to 1e-13
    // of |p| on every step, and to 2e-14 (measured 3.8e-15) on the steps whose guard passes,
    // where step() takes it; some steps pass and some do not. The work agrees to 1e-12 of
    // Σ_k w_k |f_k| |q̇_k| (measured 7.5e-14; its terms cancel in the circulatory force's work,
    // which only enters the energy balance, against a scheme error of order (hω)^9 per step).
    // Negative control: the uncorrected momentum differs by 1e-8.
    using L = linked_pendulum::lagrangian<3>;
    auto check = [](auto force) {
        using F = decltype(force);
        const lagrangian_system<L> sys(arm);
        momentum_probe<L, F> probe(sys, force, 0.02, {scheme_kind::gauss, 4},
                                   options(iteration_kind::newton));
        general::stepper<L, F> run(sys, force, 0.02, {scheme_kind::gauss, 4});
        phase_state<3> x = arm_x0;
        double worst = 0.0, worst_work = 0.0, uncorrected = 0.0, worst_guarded = 0.0;
        int guarded = 0;
        for (int j = 0; j < 100; ++j) {
            const double scale = std::max(1.0, x.p.lpNorm<Eigen::Infinity>());
            ASSERT_TRUE(probe.solve(x));
            const vec<3> a = probe.linearised(x, true);
            const double wa = probe.work();
            const vec<3> b = probe.evaluated(x);
            const double wb = probe.work();
            const double gap = (a - b).template lpNorm<Eigen::Infinity>() / scale;
            worst = std::max(worst, gap);
            if (probe.guarded()) {
                ++guarded;
                worst_guarded = std::max(worst_guarded, gap);
            }
            worst_work = std::max(worst_work, std::abs(wa - wb) / probe.work_terms(x));
            ASSERT_TRUE(probe.solve(x));
            uncorrected = std::max(
                uncorrected,
                (probe.linearised(x, false) - b).template lpNorm<Eigen::Infinity>() / scale);
            ASSERT_TRUE(run.step(x).converged);
        }
        EXPECT_LE(worst, 1e-13);
        EXPECT_LE(worst_guarded, 2e-14); // where the step itself uses it: tens of ulps
        EXPECT_GT(guarded, 0);           // the guard lets some steps through
        EXPECT_LT(guarded, 100);         // and sends others to the evaluation
        EXPECT_LE(worst_work, 1e-12);
        EXPECT_GT(uncorrected, 1e-11);
    };
    check(rayleigh_damping<3>::diagonal(vec<3>{0.3, 0.2, 0.1}));
    check(drag_and_twist{});
}
