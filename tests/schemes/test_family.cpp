// tests/schemes/test_family.cpp: the Lobatto and Gauss variational family against the paper's
// schemes it contains, against an independent Lobatto IIIA–IIIB implementation, and for
// symplecticity of every member.
#include <gtest/gtest.h>

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
