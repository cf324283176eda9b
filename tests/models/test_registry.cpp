// tests/models/test_registry.cpp: every model of the registry (varsym/models/model.hpp) through
// every operation of its simulation: it steps with each scheme, its columns are finite, its
// energy is kept where it is conserved, a saved run state resumes bit for bit, the tangent map
// is symplectic and matches central differences, ensemble members and sections run. The loops
// cover whatever the registry holds, so a model added there is tested here without a line more.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>

#include "varsym/models/model.hpp"

namespace vm = varsym::models;
using varsym::scheme_kind;
using varsym::scheme_spec;

namespace {

/// The step size of a short test run: 1/200 of the period, or of the default run's time per
/// 10 000 steps' worth (small enough for every default state).
double test_step(const vm::model& m, const vm::problem& pr) {
    if (pr.period > 0.0) return pr.period / 200.0;
    return m.time / static_cast<double>(m.steps) / 2.0;
}

std::unique_ptr<vm::simulation> simulate(const vm::model& m, const scheme_spec& spec) {
    const vm::problem pr = m.prepare(m.defaults());
    return pr.simulate({spec, {}, test_step(m, pr)});
}

const std::vector<scheme_spec> schemes{scheme_spec(scheme_kind::newmark),
                                       scheme_spec(scheme_kind::simpson),
                                       scheme_spec(scheme_kind::gauss, 2)};

} // namespace

TEST(Registry, HoldsTheModelsWithTheirData) {
    ASSERT_GE(vm::registry().size(), 11U);
    for (const vm::model& m : vm::registry()) {
        SCOPED_TRACE(m.name);
        EXPECT_FALSE(m.summary.empty());
        EXPECT_GT(m.dim, 0);
        EXPECT_EQ(static_cast<int>(m.q0.size()), m.dim);
        EXPECT_EQ(static_cast<int>(m.p0.size()), m.dim);
        EXPECT_TRUE(m.steps_per_period > 0 || (m.time > 0.0 && m.steps > 0));
        EXPECT_GT(m.ensemble_steps, 0);
        for (const auto& p : m.parameters)
            EXPECT_NO_THROW(p.check(p.value)) << p.name; // every default is in its range
        EXPECT_EQ(vm::find(m.name), &m);
    }
    for (const char* name : {"pendulum", "kepler", "cart-pole", "acrobot", "chain", "four-bar",
                             "slider-crank", "spherical-pendulum"})
        EXPECT_NE(vm::find(name), nullptr) << name;
}

TEST(Registry, RefusesBadInputNamingTheModelAndTheClosestName) {
    const vm::model& pendulum = vm::get("pendulum");
    EXPECT_THROW((void)pendulum.prepare({{-1.0, 1.0}}), std::invalid_argument);
    try {
        (void)pendulum.prepare({{1.0, 1.0}}, {{1.0, 2.0}, {}, {}});
        FAIL() << "two values for d = 1 accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("pendulum: q0 needs 1 value"), std::string::npos)
            << e.what();
    }
    try {
        (void)vm::get("acrobat");
        FAIL();
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("did you mean 'acrobot'"), std::string::npos);
    }
    EXPECT_EQ(vm::closest("stesp_per_period", {"steps_per_period", "every", "q0"}).front(),
              "steps_per_period");
    EXPECT_TRUE(vm::closest("xyz", {"steps_per_period", "every"}).empty()); // nothing near
    const vm::model& kepler = vm::get("kepler");
    EXPECT_THROW((void)kepler.prepare(kepler.defaults(), {{1.0, 0.0}, {}, {}}),
                 std::invalid_argument); // its start follows from its parameters
}

TEST(Registry, EveryModelStepsWithEverySchemeAndKeepsItsEnergy) {
    for (const vm::model& m : vm::registry())
        for (const scheme_spec& spec : schemes) {
            SCOPED_TRACE(m.name + " " + spec.label());
            const auto sim = simulate(m, spec);
            const double e0 = sim->watched_energy();
            std::vector<double> values(sim->columns().size());
            double worst = 0.0;
            ASSERT_TRUE(sim->advance(200, [&] {
                worst = std::max(worst, std::abs(sim->watched_energy() - e0));
                return false;
            }));
            EXPECT_EQ(sim->step(), 200U);
            EXPECT_DOUBLE_EQ(sim->time(), 200 * sim->step_size());
            sim->values(values);
            for (double v : sim->q())
                EXPECT_TRUE(std::isfinite(v));
            EXPECT_TRUE(std::isfinite(values.at(0))); // every model's first column: energy
            if (sim->conserves_energy()) { // 200 steps of h = T/200 or less: bounded error
                // Measured over the models (200 steps): at most 8.4e-3 of |E0| with Newmark
                // (Kepler; order 2) and 2.5e-6 with Simpson and gauss-2 (Kepler; order 4); the
                // double pendulum starts with E0 = 0 and errs by 5e-9 J. Budgets: 2e-2 and 1e-5
                // of |E0| (2.4 and 4 times those), plus 1e-8 J (2 times).
                const double relative = spec.label() == "newmark" ? 2e-2 : 1e-5;
                EXPECT_LT(worst, relative * std::abs(e0) + 1e-8);
            }
        }
}

TEST(Registry, EveryModelResumesBitForBitFromASavedState) {
    for (const vm::model& m : vm::registry()) {
        SCOPED_TRACE(m.name);
        const auto a = simulate(m, scheme_spec(scheme_kind::gauss, 2));
        a->advance(37);
        const varsym::run_state<varsym::dynamic> saved = a->save();
        a->advance(80);
        const auto b = simulate(m, scheme_spec(scheme_kind::gauss, 2));
        b->restore(saved);
        b->advance(80);
        for (int i = 0; i < m.dim; ++i) {
            EXPECT_EQ(a->q()[static_cast<std::size_t>(i)], b->q()[static_cast<std::size_t>(i)]);
            EXPECT_EQ(a->p()[static_cast<std::size_t>(i)], b->p()[static_cast<std::size_t>(i)]);
        }
        // Negative control: the comparison sees a difference of 1e-12 in the saved state.
        varsym::run_state<varsym::dynamic> nudged = saved;
        nudged.x.q(0) += 1e-12 * std::max(1.0, std::abs(nudged.x.q(0)));
        const auto c = simulate(m, scheme_spec(scheme_kind::gauss, 2));
        c->restore(nudged);
        c->advance(80);
        bool differs = false;
        for (int i = 0; i < m.dim; ++i)
            differs = differs ||
                      a->q()[static_cast<std::size_t>(i)] != c->q()[static_cast<std::size_t>(i)] ||
                      a->p()[static_cast<std::size_t>(i)] != c->p()[static_cast<std::size_t>(i)];
        EXPECT_TRUE(differs);
    }
}

TEST(Registry, EveryTangentMapIsSymplecticAndMatchesDifferences) {
    for (const vm::model& m : vm::registry()) {
        SCOPED_TRACE(m.name);
        const auto sim = simulate(m, scheme_spec(scheme_kind::simpson));
        sim->advance(10);
        Eigen::MatrixXd j;
        if (!sim->has_tangent_map()) { // the rigid bodies' Lie group integrator
            EXPECT_THROW(sim->tangent_map(j), std::logic_error);
            continue;
        }
        sim->tangent_map(j);
        const int d = m.dim;
        ASSERT_EQ(j.rows(), 2 * d);
        Eigen::MatrixXd omega = Eigen::MatrixXd::Zero(2 * d, 2 * d);
        omega.topRightCorner(d, d).setIdentity();
        omega.bottomLeftCorner(d, d) = -Eigen::MatrixXd::Identity(d, d);
        // Symplectic to round-off: JᵀΩJ = Ω (the step map is a canonical transformation). A
        // constrained model's map is symplectic on the constraint manifold's cotangent bundle
        // only, not on all of R^2d (tests/diagnostics/test_tangent.cpp checks it there); a
        // forced one (a work column) is not symplectic where its force dissipates (the arm's
        // damping and controller). Both still match the differences below.
        const auto& cols = sim->columns();
        const bool canonical =
            std::find(cols.begin(), cols.end(), "constraint_residual") == cols.end() &&
            std::find(cols.begin(), cols.end(), "work") == cols.end();
        if (canonical) {
            EXPECT_LT((j.transpose() * omega * j - omega).cwiseAbs().maxCoeff(), 1e-9);
        }
        // Against central differences of the step from perturbed states (O(ε²) ≈ 1e-10).
        const varsym::run_state<varsym::dynamic> at = sim->save();
        const double eps = 1e-5;
        for (int k = 0; k < 2 * d; ++k) {
            Eigen::VectorXd plus, minus;
            for (const double sign : {1.0, -1.0}) {
                auto probe = simulate(m, scheme_spec(scheme_kind::simpson));
                varsym::run_state<varsym::dynamic> s = at;
                (k < d ? s.x.q(k) : s.x.p(k - d)) += sign * eps;
                s.carry_q.setZero();
                s.carry_p.setZero();
                probe->restore(s);
                probe->advance(at.step + 1);
                Eigen::VectorXd out(2 * d);
                for (int i = 0; i < d; ++i) {
                    out(i) = probe->q()[static_cast<std::size_t>(i)];
                    out(d + i) = probe->p()[static_cast<std::size_t>(i)];
                }
                (sign > 0 ? plus : minus) = out;
            }
            const Eigen::VectorXd fd = (plus - minus) / (2.0 * eps);
            EXPECT_LT((fd - j.col(k)).cwiseAbs().maxCoeff(),
                      1e-6 * std::max(1.0, j.cwiseAbs().maxCoeff()))
                << "column " << k;
        }
    }
}

TEST(Registry, EveryModelRunsEnsembleMembersAndSectionsWhereItHasDenseOutput) {
    for (const vm::model& m : vm::registry()) {
        SCOPED_TRACE(m.name);
        const auto sim = simulate(m, scheme_spec(scheme_kind::simpson));
        varsym::member_plan plan;
        plan.steps = 100;
        const varsym::member_result r = sim->run_member(plan, nullptr);
        EXPECT_EQ(r.status, varsym::member_result::outcome::completed);
        EXPECT_EQ(r.steps, 100);
        // λ where the stepper has a tangent map; NaN (not a made-up number) where it has none.
        EXPECT_EQ(std::isfinite(r.lyapunov), sim->has_tangent_map());
        EXPECT_EQ(sim->step(), 0U); // the member ran on a copy
        // An event at q_1 = q_1(0) + 1e9 never happens; one at t = 10 h does, at t = 10 h.
        const double h = sim->step_size();
        const varsym::member_result e =
            sim->run_member(plan, [h](double t, auto, auto) { return t - 10.5 * h; });
        EXPECT_EQ(e.status, varsym::member_result::outcome::event);
        EXPECT_NEAR(e.event_time, 10.5 * h, 1e-12);
        if (sim->has_dense_output()) {
            // The plane q_1 = the value q_1 passes through at step 25 (of a second run of the
            // same model): crossed at least once (q_1 = q_1(0)/2 was never crossed by the
            // heavy top or the cart-pole, and a section of no crossings passed).
            const auto ahead = simulate(m, scheme_spec(scheme_kind::simpson));
            ahead->advance(25);
            const double q25 = ahead->q()[0];
            ASSERT_NE(q25, sim->q()[0]); // it moved: the plane is not the start's
            const varsym::section_plane plane{false, 0, q25, 0};
            const vm::section_result s = sim->section(plane, 2000, 3, nullptr);
            EXPECT_FALSE(s.failed);
            EXPECT_GE(s.time.size(), 1U);
            EXPECT_FALSE(s.stopped);
            EXPECT_EQ(s.states.size(), s.time.size() * 2 * static_cast<std::size_t>(m.dim));
            // A stop flag already set (Ctrl-C) ends it before the first step.
            const std::atomic<bool> stop{true};
            const vm::section_result stopped = sim->section(plane, 2000, 3, &stop);
            EXPECT_TRUE(stopped.stopped && stopped.time.empty());
        } else {
            EXPECT_THROW((void)sim->section({}, 10, 1, nullptr), std::logic_error);
        }
        // The member's loop watches the flag too: stopped, at the state it started from.
        const std::atomic<bool> stop{true};
        varsym::member_plan stopping = plan;
        stopping.stop = &stop;
        const varsym::member_result s = sim->run_member(stopping, nullptr);
        EXPECT_EQ(s.status, varsym::member_result::outcome::stopped);
        EXPECT_EQ(s.steps, 0);
    }
}

TEST(Registry, ParametersMaySetTheDimensionAndShortStartsAreCompleted) {
    const vm::model& chain = vm::get("chain");
    std::vector<double> v = chain.defaults();
    v[static_cast<std::size_t>(chain.parameter_index("n"))] = 5;
    EXPECT_EQ(chain.dimension_at(v), 5);
    const vm::problem pr = chain.prepare(v);
    EXPECT_EQ(pr.q0.size(), 5U); // the lowest mode of 5 masses: A sin(pi i/6)
    EXPECT_NEAR(pr.q0[2], std::sin(3.0 * std::acos(-1.0) / 6.0), 1e-15);
    EXPECT_THROW((void)chain.prepare(v, {std::vector<double>(64, 0.1), {}, {}}),
                 std::invalid_argument); // 64 values for n = 5
    v[static_cast<std::size_t>(chain.parameter_index("n"))] = 2.5;
    EXPECT_THROW((void)chain.prepare(v), std::invalid_argument); // n is a whole number
    // The four-bar closes its loop from the crank angle alone: th1 = 1 gives the same start as
    // all three angles of that closed loop.
    const vm::model& bar = vm::get("four-bar");
    const vm::problem one = bar.prepare(bar.defaults(), {{1.0}, {}, {}});
    const vm::problem three = bar.prepare(bar.defaults(), {one.q0, {}, {}});
    for (std::size_t i = 0; i < 3; ++i)
        EXPECT_EQ(one.q0[i], three.q0[i]);
    EXPECT_THROW((void)bar.prepare(bar.defaults(), {{1.0, 2.0}, {}, {}}), std::invalid_argument);
    // Off the loop: refused, pointing to the projection; projected (project = 1): accepted.
    std::vector<double> off = one.q0;
    off[1] += 0.01;
    EXPECT_THROW((void)bar.prepare(bar.defaults(), {off, {}, {}}), std::invalid_argument);
    std::vector<double> projecting = bar.defaults();
    projecting.back() = 1.0;
    EXPECT_NO_THROW((void)bar.prepare(projecting, {off, {}, {}}));
    projecting.back() = 0.5; // a switch is 0 or 1
    EXPECT_THROW((void)bar.prepare(projecting), std::invalid_argument);
}
