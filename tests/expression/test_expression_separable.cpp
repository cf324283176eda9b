// Separable expression Lagrangians (expression_lagrangian::separable(),
// systems/expression_separable.hpp): which L are recognised as ½ q̇ᵀ M q̇ − V(q) with M constant,
// and the potential's derivatives against L's own. The separable steppers then run them:
// checked against the general engine on the same L (the same discrete map for Simpson, so
// round-off apart) and against the Kepler problem's exact orbit in the models layer's tests.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <type_traits>
#include <utility>

#include "test_support.hpp"
#include "varsym/integrate.hpp"
#include "varsym/problems/kepler.hpp"
#include "varsym/schemes/galerkin.hpp"
#include "varsym/schemes/simpson.hpp"
#include "varsym/schemes/variational.hpp"
#include "varsym/systems/expression_separable.hpp"

namespace varsym {
namespace {

bool separable_text(const std::string& text) {
    return expression_lagrangian(text, {"x", "y"}, {{"m", 2.0}}).separable();
}

TEST(ExpressionSeparable, RecognisedWhereMIsConstantAndNothingElse) {
    EXPECT_TRUE(separable_text("0.5*m*(x_dot**2 + y_dot**2) - x**4 - cos(y)"));
    EXPECT_TRUE(separable_text("0.5*(x_dot**2 + x_dot*y_dot + y_dot**2) + 1/sqrt(x**2 + y**2)"));
    // Negative controls, one per condition.
    EXPECT_FALSE(separable_text("0.5*(1 + x**2)*x_dot**2 + 0.5*y_dot**2"));     // M(q)
    EXPECT_FALSE(separable_text("0.5*(x_dot**2 + y_dot**2) + x*y_dot"));        // L_qv ≠ 0
    EXPECT_FALSE(separable_text("0.5*(x_dot**2 + y_dot**2) + 2*x_dot - x**2")); // a·q̇
    EXPECT_FALSE(separable_text("0.5*(x_dot**2 + y_dot**2) - t*x"));            // L(t)
    EXPECT_FALSE(separable_text("0.25*x_dot**4 + 0.5*y_dot**2"));               // not quadratic
    EXPECT_FALSE(separable_text("0.5*(x_dot**2 - y_dot**2)"));                  // M indefinite
    // A time that simplifies away is no time.
    EXPECT_TRUE(separable_text("0.5*(x_dot**2 + y_dot**2) - x**2 + 0*t"));
    const expression_lagrangian l("0.5*(x_dot**2 + x_dot*y_dot + 3*y_dot**2)", {"x", "y"});
    ASSERT_TRUE(l.separable());
    EXPECT_EQ(l.separable_mass()(0, 0), 1.0);
    EXPECT_EQ(l.separable_mass()(0, 1), 0.5);
    EXPECT_EQ(l.separable_mass()(1, 1), 3.0);
}

TEST(ExpressionSeparable, PotentialIsMinusLAtRest) {
    const expression_lagrangian l("0.5*m*(x_dot**2 + y_dot**2) - x**4 - cos(x*y)", {"x", "y"},
                                  {{"m", 2.0}});
    const vec<dynamic> q = vec<dynamic>(vec<2>{0.7, -1.3}), zero = vec<dynamic>::Zero(2);
    lagrangian_terms<dynamic> t;
    l.derivatives(q, zero, 0.0, t);
    EXPECT_EQ(l.potential(q), -t.value);
    EXPECT_EQ((l.potential_gradient(q) + t.lq).norm(), 0.0);
    EXPECT_EQ((l.potential_hessian(q) + t.lqq).norm(), 0.0);
    // By hand: ∂V/∂x = 4x³ − y sin(xy).
    EXPECT_NEAR(l.potential_gradient(q)(0), 4 * 0.343 + 1.3 * std::sin(-0.91), 1e-14);
}

TEST(ExpressionSeparable, SimpsonsReducedStepperMatchesTheGeneralEngine) {
    // Hénon–Heiles: Simpson's discrete map, solved by its reduced stepper and by the general
    // engine, from the same start for 2000 steps of h = 0.05 (a chaotic orbit's amplification
    // included, they stay round-off apart).
    const expression_lagrangian l("0.5*(x_dot**2 + y_dot**2) - 0.5*(x**2 + y**2) - x**2*y + y**3/3",
                                  {"x", "y"});
    ASSERT_TRUE(l.separable());
    const auto sys = separable_system_of(l);
    simpson::stepper<expression_separable_system> reduced(sys, 0.05);
    general::stepper<expression_lagrangian> engine(lagrangian_system<expression_lagrangian>(l),
                                                   0.05, scheme_spec(scheme_kind::simpson));
    phase_state<dynamic> a{vec<dynamic>(vec<2>{0.0, 0.1}), vec<dynamic>(vec<2>{0.4, 0.0})};
    phase_state<dynamic> b = a;
    double apart = 0.0;
    for (int j = 0; j < 2000; ++j) {
        ASSERT_TRUE(reduced.step(a).converged);
        ASSERT_TRUE(engine.step(b).converged);
        apart = std::max(apart, (a.q - b.q).lpNorm<Eigen::Infinity>());
    }
    EXPECT_LE(apart, 1e-10);
    RecordProperty("apart", test::sci(apart));
    EXPECT_NEAR(sys.energy(a),
                sys.energy(phase_state<dynamic>{vec<dynamic>(vec<2>{0.0, 0.1}),
                                                vec<dynamic>(vec<2>{0.4, 0.0})}),
                1e-6);
}

TEST(ExpressionSeparable, FixedSizeRunsTheBuiltInKeplersMap) {
    // Kepler typed as an expression, at its fixed size 2 (what models::simulate_expression runs
    // for one to three coordinates) and at run-time size, against the built-in model's separable
    // system: ten orbits of e = 0.6 at 200 steps an orbit, Simpson and gauss-4. The same discrete
    // map, whose ∇V differs from the built-in one only in rounding (mu x/r³ against the symbolic
    // derivative's own sequence): the orbits stay round-off apart (their phase error grows
    // linearly in the step count: 3.4e-13 and 1.4e-13 measured with clang 14; 1e-10 leaves room
    // for another compiler's rounding). Fixed and run-time sizes do the same operations: 1e-12.
    const expression_lagrangian l("0.5*(x_dot**2 + y_dot**2) + mu/sqrt(x**2 + y**2)", {"x", "y"},
                                  {{"mu", 1.0}});
    const kepler::orbit orbit(0.6, 1.0);
    const double h = orbit.period() / 200;
    for (const scheme_spec spec :
         {scheme_spec(scheme_kind::simpson), scheme_spec(scheme_kind::gauss, 4)}) {
        auto run = [&](const auto& sys) {
            return with_stepper(spec, sys, h, {}, [&](auto& st) {
                using S = std::remove_cvref_t<decltype(st)>;
                phase_state<S::dim> x{orbit.at(0.0).q, orbit.at(0.0).p};
                for (int j = 0; j < 2000; ++j)
                    EXPECT_TRUE(st.step(x).converged);
                return phase_state<2>{x.q, x.p};
            });
        };
        const phase_state<2> fixed = run(separable_system_of<2>(l));
        const phase_state<2> dynamic_size = run(separable_system_of(l));
        const phase_state<2> built_in = run(kepler::make_system());
        EXPECT_LE((fixed.q - dynamic_size.q).lpNorm<Eigen::Infinity>(), 1e-12) << spec.label();
        EXPECT_LE((fixed.q - built_in.q).lpNorm<Eigen::Infinity>(), 1e-10) << spec.label();
        EXPECT_LE((fixed.p - built_in.p).lpNorm<Eigen::Infinity>(), 1e-10) << spec.label();
        // Negative control: mu 1e-6 off moves the orbit far past the tolerance.
        const expression_lagrangian off("0.5*(x_dot**2 + y_dot**2) + mu/sqrt(x**2 + y**2)",
                                        {"x", "y"}, {{"mu", 1.000001}});
        EXPECT_GT((run(separable_system_of<2>(off)).q - built_in.q).lpNorm<Eigen::Infinity>(), 1e-6)
            << spec.label();
        RecordProperty(spec.label() + "_apart", test::sci((fixed.q - built_in.q).norm()));
    }
    EXPECT_THROW((void)separable_system_of<3>(l), std::invalid_argument); // L has 2 coordinates
}

/// An expression's potential without its batch and joint methods (`gradients`,
/// `gradient_and_hessian`): the steppers evaluate ∇V one point at a time, ∇²V apart.
template <int D>
struct one_point_at_a_time {
    expression_potential_of<D> v;
    [[nodiscard]] double value(const vec<D>& q) const { return v.value(q); }
    [[nodiscard]] vec<D> gradient(const vec<D>& q) const { return v.gradient(q); }
    [[nodiscard]] mat<D> hessian(const vec<D>& q) const { return v.hessian(q); }
};
static_assert(batch_potential<expression_potential_of<2>>);
static_assert(!batch_potential<one_point_at_a_time<2>>);
static_assert(joint_potential<expression_potential_of<2>, 2>);
static_assert(!joint_potential<one_point_at_a_time<2>, 2>);

/// Steps of the family from x for both potentials of `l`, batched and one point at a time:
/// the largest difference of (q, p) over `steps` steps.
template <int D>
double batched_against_one_at_a_time(const expression_lagrangian& batched_l,
                                     const expression_lagrangian& l, phase_state<D> x, double h,
                                     galerkin::rule_kind kind, int degree,
                                     const newton_options& opt) {
    const auto mass = l.separable_mass();
    galerkin::stepper batched(separable_system_of<D>(batched_l), h, kind, degree, opt);
    galerkin::stepper single(
        separable_system<D, one_point_at_a_time<D>>(mat<D>(mass), {expression_potential_of<D>(l)}),
        h, kind, degree, opt);
    phase_state<D> y = x;
    double worst = 0.0;
    for (int j = 0; j < 300; ++j) {
        EXPECT_TRUE(batched.step(x).converged);
        EXPECT_TRUE(single.step(y).converged);
        worst = std::max({worst, (x.q - y.q).template lpNorm<Eigen::Infinity>(),
                          (x.p - y.p).template lpNorm<Eigen::Infinity>()});
    }
    return worst;
}

TEST(ExpressionSeparable, FamilyTakesTheSameStepsWithBatchedGradients) {
    // The family stepper evaluates a batch_potential's ∇V at a sweep's points in one call
    // (tape::run_batch): the same values as one point at a time, so the same steps bit for bit.
    // d = 1 (the pendulum: the raw d = 1 sweep) and d = 2 (Kepler, e = 0.6); Gauss and Lobatto
    // (whose end points are not batched the same way), degrees whose point counts take every
    // chunk of the batch, the fixed point with both starts, and Newton (Hessians one at a time,
    // the momentum update's gradients batched).
    const expression_lagrangian pendulum("0.5*q_dot**2 + w2*cos(q)", {"q"}, {{"w2", 39.5}});
    const expression_lagrangian kepler("0.5*(x_dot**2 + y_dot**2) + mu/sqrt(x**2 + y**2)",
                                       {"x", "y"}, {{"mu", 1.0}});
    const expression_lagrangian kepler_off("0.5*(x_dot**2 + y_dot**2) + mu/sqrt(x**2 + y**2)",
                                           {"x", "y"}, {{"mu", 1.0 + 1e-9}});
    const kepler::orbit orbit(0.6, 1.0);
    const phase_state<1> pendulum_x0{vec<1>(1.5), vec<1>(0.0)};
    for (const auto kind : {galerkin::rule_kind::gauss, galerkin::rule_kind::lobatto})
        for (const int degree : {2, 3, 5, 6})
            for (const auto& [iteration, start] :
                 {std::pair{iteration_kind::fixed_point, predictor_kind::taylor},
                  std::pair{iteration_kind::fixed_point, predictor_kind::forces},
                  std::pair{iteration_kind::newton, predictor_kind::taylor}}) {
                newton_options opt;
                opt.iteration = iteration;
                opt.predictor = start;
                const std::string at = std::to_string(static_cast<int>(kind)) + "-" +
                                       std::to_string(degree) + ", " +
                                       std::to_string(static_cast<int>(iteration));
                EXPECT_EQ(batched_against_one_at_a_time<1>(pendulum, pendulum, pendulum_x0, 0.05,
                                                           kind, degree, opt),
                          0.0)
                    << "pendulum, " << at;
                EXPECT_EQ(batched_against_one_at_a_time<2>(kepler, kepler, orbit.at(0.0),
                                                           orbit.period() / 100, kind, degree, opt),
                          0.0)
                    << "Kepler, " << at;
                // Negative control: mu 1e-9 off on one side is seen.
                EXPECT_GT(batched_against_one_at_a_time<2>(kepler_off, kepler, orbit.at(0.0),
                                                           orbit.period() / 100, kind, degree, opt),
                          1e-11)
                    << "Kepler, " << at;
            }
}

TEST(ExpressionSeparable, SimpsonAndNewmarkTakeTheSameStepsWithTheJointDerivatives) {
    // Their stage equation's Newton iterations take ∇V and ∇²V from one code
    // (gradient_and_hessian): the same values as apart, so the same steps bit for bit. Kepler,
    // e = 0.6, 300 steps of 1/100 orbit; a 1e-9 change of mu as negative control.
    const kepler::orbit orbit(0.6, 1.0);
    const double h = orbit.period() / 100;
    const auto apart = [&](double mu) {
        const std::string text = "0.5*(x_dot**2 + y_dot**2) + mu/sqrt(x**2 + y**2)";
        const expression_lagrangian l(text, {"x", "y"}, {{"mu", 1.0}});
        const expression_lagrangian joint_l(text, {"x", "y"}, {{"mu", mu}});
        using single = separable_system<2, one_point_at_a_time<2>>;
        const single one(mat<2>(l.separable_mass()), {expression_potential_of<2>(l)});
        double worst = 0.0;
        for (const scheme_spec spec :
             {scheme_spec(scheme_kind::simpson), scheme_spec(scheme_kind::newmark)}) {
            phase_state<2> a = orbit.at(0.0), b = a;
            with_stepper(spec, separable_system_of<2>(joint_l), h, {}, [&](auto& joint) {
                with_stepper(spec, one, h, {}, [&](auto& alone) {
                    for (int j = 0; j < 300; ++j) {
                        EXPECT_TRUE(joint.step(a).converged);
                        EXPECT_TRUE(alone.step(b).converged);
                        worst = std::max({worst, (a.q - b.q).lpNorm<Eigen::Infinity>(),
                                          (a.p - b.p).lpNorm<Eigen::Infinity>()});
                    }
                });
            });
        }
        return worst;
    };
    EXPECT_EQ(apart(1.0), 0.0);
    EXPECT_GT(apart(1.0 + 1e-9), 1e-11);
}

TEST(ExpressionSeparable, AFailedStepNamesThePotential) {
    // V = −1/√q pulls the particle through q = 0, where V is NaN: the separable stepper's
    // failure names the potential, at the step's start or along its free motion.
    const expression_lagrangian l("0.5*q_dot**2 + 1/sqrt(q)", {"q"});
    ASSERT_TRUE(l.separable());
    simpson::stepper<expression_separable_system> st(separable_system_of(l), 0.01);
    phase_state<dynamic> x{vec<dynamic>::Constant(1, 1.0), vec<dynamic>::Zero(1)};
    try {
        integrate(st, x, 0.0, 10000, [](auto, auto, const auto&) {});
        FAIL() << "the particle went through q = 0 without a failure";
    } catch (const step_failure& e) {
        EXPECT_NE(e.cause().find("potential or its gradient is NaN"), std::string::npos)
            << e.what();
        EXPECT_GT(x.q(0), 0.0); // the last good state
    }
}

} // namespace
} // namespace varsym
