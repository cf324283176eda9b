// tests/schemes/test_family.cpp: the Lobatto and Gauss variational family against the paper's
// schemes it contains, against an independent Lobatto IIIA–IIIB implementation, and for
// symplecticity of every member.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "compare_steppers.hpp"
#include "test_support.hpp"
#include "varsym/diagnostics/symplecticity.hpp"
#include "varsym/problems/pendulum.hpp"
#include "varsym/reference/lobatto_prk.hpp"
#include "varsym/schemes/galerkin.hpp"
#include "varsym/schemes/newmark.hpp"
#include "varsym/schemes/simpson.hpp"

using namespace varsym;
using galerkin::rule_kind;
using std::numbers::pi;

namespace {

using test::max_difference;
using test::paper_h;
using test::paper_x0;
using test::pendulum_sys;

} // namespace

TEST(Family, TablesArePartitionsOfUnity) {
    // Σ_i ℓ_i = 1 and Σ_i ℓ_i' = 0 at every quadrature node, so Σ_i A_il = 0: what makes
    // p_{j+1} − p_j = −h Σ_k w_k ∇V(q_k) (discrete Noether for translations).
    for (auto kind : {rule_kind::lobatto, rule_kind::gauss})
        for (int s = 1; s <= galerkin::max_degree; ++s) {
            const auto t = galerkin::tableau::make(kind, s);
            EXPECT_LT((t.phi.colwise().sum().array() - 1.0).abs().maxCoeff(), 1e-13) << s;
            EXPECT_LT(t.dphi.colwise().sum().cwiseAbs().maxCoeff(), 1e-10) << s;
            EXPECT_LT(t.stiffness.colwise().sum().cwiseAbs().maxCoeff(), 1e-9) << s;
        }
}

// Lobatto s = 2 is the paper's Simpson scheme and Gauss s = 1 its Newmark scheme: the same
// discrete Lagrangians, solved differently. Tolerance as for the paper's full systems:
// round-off in the increments over 10 periods (measured ≤ 3e-14).
TEST(Family, LobattoTwoIsSimpson) {
    EXPECT_LE(max_difference(galerkin::stepper(pendulum_sys, paper_h, rule_kind::lobatto, 2),
                             simpson::stepper(pendulum_sys, paper_h), paper_x0, 500),
              1e-13);
    const auto sys = test::coupled_system();
    const phase_state<2> x0{vec<2>{1.0, -0.5}, vec<2>{0.3, 1.2}};
    EXPECT_LE(max_difference(galerkin::stepper(sys, 0.05, rule_kind::lobatto, 2),
                             simpson::stepper(sys, 0.05), x0, 400),
              1e-13);
}

TEST(Family, GaussOneIsNewmark) {
    EXPECT_LE(max_difference(galerkin::stepper(pendulum_sys, paper_h, rule_kind::gauss, 1),
                             newmark::stepper(pendulum_sys, paper_h), paper_x0, 500),
              1e-13);
    const auto sys = test::coupled_system();
    const phase_state<2> x0{vec<2>{1.0, -0.5}, vec<2>{0.3, 1.2}};
    EXPECT_LE(max_difference(galerkin::stepper(sys, 0.05, rule_kind::gauss, 1),
                             newmark::stepper(sys, 0.05), x0, 400),
              1e-13);
}

// For constant M the Lobatto variational integrator of degree s is the (s+1)-stage Lobatto
// IIIA–IIIB method; lobatto_prk solves that method's stages by fixed-point iteration from its
// Butcher tableaux. Measured agreement ≤ 6e-14 over 200 steps; the bound is 1e-12.
TEST(Family, LobattoEqualsLobattoIIIAIIIB) {
    const auto sys = test::coupled_system();
    const phase_state<2> x0{vec<2>{1.0, -0.5}, vec<2>{0.3, 1.2}};
    for (int s = 1; s <= 4; ++s) {
        EXPECT_LE(max_difference(galerkin::stepper(pendulum_sys, paper_h, rule_kind::lobatto, s),
                                 lobatto_prk::stepper(pendulum_sys, paper_h, s), paper_x0, 200),
                  1e-12)
            << "pendulum, s = " << s;
        EXPECT_LE(max_difference(galerkin::stepper(sys, 0.05, rule_kind::lobatto, s),
                                 lobatto_prk::stepper(sys, 0.05, s), x0, 200),
                  1e-12)
            << "coupled pendulums, s = " << s;
    }
}

TEST(Family, EveryMemberIsSymplectic) {
    // Jᵀ Ω J = Ω by finite differences of the step map (tolerance as in
    // tests/numeric/test_symplecticity.cpp), d = 1 and d = 2, every degree offered, both rules.
    const auto sys2 = test::coupled_system();
    const phase_state<1> x1{vec<1>{0.3}, vec<1>{-2.0}};
    const phase_state<2> x2{vec<2>{1.0, -0.5}, vec<2>{0.3, 1.2}};
    for (auto kind : {rule_kind::lobatto, rule_kind::gauss})
        for (int s = 1; s <= galerkin::max_degree; ++s) {
            auto step1 = [&](phase_state<1>& y) {
                galerkin::stepper(pendulum_sys, 0.05, kind, s).step(y);
            };
            auto step2 = [&](phase_state<2>& y) { galerkin::stepper(sys2, 0.1, kind, s).step(y); };
            EXPECT_LE(symplecticity_defect(tangent_map<1>(step1, x1)), 1e-10) << "d = 1, s = " << s;
            EXPECT_LE(symplecticity_defect(tangent_map<2>(step2, x2)), 1e-10) << "d = 2, s = " << s;
        }
}

TEST(Family, RefusesBadDegrees) {
    EXPECT_THROW(galerkin::tableau::make(rule_kind::gauss, 0), std::invalid_argument);
    EXPECT_THROW(galerkin::tableau::make(rule_kind::lobatto, galerkin::max_degree + 1),
                 std::invalid_argument);
}

// The fixed point's sweeps at d = 1 run on raw entries (stepper::scalar_sweep); at a run-time d
// they go through the general sweep. Both do the same operations in the same order, so the
// pendulum written with run-time-sized vectors takes the same steps bit for bit over 400 steps,
// for both starts and both rules (without FMA contraction, as the project builds). A raw sweep
// whose flight term was off by 1e-6 failed this (tried by hand); the closing sweep, shared code,
// absorbs mere reorderings of the other sweeps' roundings. Negative control: a mass off by 1e-9
// moves the steps by more than 1e-10 (measured 4e-8).
TEST(Family, ScalarSweepTakesTheGeneralSweepsSteps) {
    struct dynamic_pendulum {
        double m, omega;
        [[nodiscard]] double value(const Eigen::VectorXd& q) const {
            const double s = std::sin(0.5 * q(0));
            return 2.0 * m * omega * omega * s * s;
        }
        [[nodiscard]] Eigen::VectorXd gradient(const Eigen::VectorXd& q) const {
            return Eigen::VectorXd::Constant(1, m * omega * omega * std::sin(q(0)));
        }
        [[nodiscard]] Eigen::MatrixXd hessian(const Eigen::VectorXd& q) const {
            return Eigen::MatrixXd::Constant(1, 1, m * omega * omega * std::cos(q(0)));
        }
    };
    const auto run_time = [](double m) {
        return separable_system<dynamic, dynamic_pendulum>(Eigen::MatrixXd::Constant(1, 1, m),
                                                           dynamic_pendulum{1.0, 2 * pi});
    };
    for (auto kind : {rule_kind::lobatto, rule_kind::gauss})
        for (int s : {3, 6})
            for (auto start : {predictor_kind::taylor, predictor_kind::forces}) {
                newton_options opt;
                opt.predictor = start;
                galerkin::stepper fixed(pendulum_sys, paper_h, kind, s, opt);
                galerkin::stepper general(run_time(1.0), paper_h, kind, s, opt);
                galerkin::stepper heavier(run_time(1.0 + 1e-9), paper_h, kind, s, opt);
                phase_state<1> a = paper_x0;
                phase_state<dynamic> b{Eigen::VectorXd(a.q), Eigen::VectorXd(a.p)}, c = b;
                double worst = 0.0, control = 0.0;
                for (int j = 0; j < 400; ++j) {
                    ASSERT_TRUE(fixed.step(a).converged);
                    ASSERT_TRUE(general.step(b).converged);
                    ASSERT_TRUE(heavier.step(c).converged);
                    worst = std::max({worst, std::abs(a.q(0) - b.q(0)), std::abs(a.p(0) - b.p(0))});
                    control = std::max({control, std::abs(c.q(0) - b.q(0))});
                }
                EXPECT_EQ(worst, 0.0) << s << " " << static_cast<int>(kind);
                EXPECT_GE(control, 1e-10) << s << " " << static_cast<int>(kind);
            }
}
