// ∂L/∂t of a C++ Lagrangian whose call takes the time as a template parameter
// (systems/lagrangian_time.hpp), and the energy balance E − E0 − W it gives the general engine.
// References: ∂L/∂t by hand; the same L typed as an expression (its ∂L/∂t symbolic,
// tests/expression and docs/library.md), whose run must agree to round-off; the balance's order
// 4 under Simpson (halving h divides it by 16). Negative control: the same L with a time of type
// double has no ∂L/∂t, so no watch and no work.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "test_support.hpp"
#include "varsym/integrate.hpp"
#include "varsym/run/energy.hpp"
#include "varsym/schemes/variational.hpp"
#include "varsym/systems/expression_lagrangian.hpp"

using namespace varsym;

namespace {

// A stiffening spring: L = ½ q̇² − ½ (1 + t/2) q², ∂L/∂t = −q²/4; E = ½ q̇² + ½ (1 + t/2) q².
struct stiffening {
    static constexpr int dim = 1;
    template <class T, class S>
    T operator()(const tvec<T, 1>& q, const tvec<T, 1>& v, S t) const {
        return 0.5 * v(0) * v(0) - 0.5 * (1.0 + 0.5 * t) * q(0) * q(0);
    }
};
// The same with t of type double: ∂L/∂t cannot be had by differentiation.
struct stiffening_opaque {
    static constexpr int dim = 1;
    template <class T>
    T operator()(const tvec<T, 1>& q, const tvec<T, 1>& v, double t) const {
        return 0.5 * v(0) * v(0) - 0.5 * (1.0 + 0.5 * t) * q(0) * q(0);
    }
};

static_assert(lagrangian_differentiable_in_time<stiffening>);
static_assert(!lagrangian_differentiable_in_time<stiffening_opaque>);
static_assert(lagrangian_time_known<expression_lagrangian>);

/// max |E − E0 − W| over n Simpson steps of L from q = 1 at rest to t = 10, and the final W.
template <class L>
std::pair<double, double> time_balance(const L& l, int n) {
    general::stepper<L> st(lagrangian_system<L>(l), 10.0 / n, scheme_spec(scheme_kind::simpson));
    phase_state<L::dim> x{vec<L::dim>::Constant(1, 1.0), vec<L::dim>::Zero(1)};
    const double e0 = st.system().energy(x, 0.0);
    double worst = 0.0;
    integrate(st, x, 0.0, static_cast<std::size_t>(n), [&](auto, double t, const auto& y) {
        worst = std::max(worst, std::abs(st.system().energy(y, t) - e0 - st.total_work()));
    });
    return {worst, st.total_work()};
}

} // namespace

TEST(LagrangianTime, TimeDerivativeByDifferentiationIsExact) {
    const stiffening l;
    for (const double q : {0.3, -1.7, 2.0})
        for (const double t : {0.0, 1.25, 7.0})
            EXPECT_DOUBLE_EQ(time_derivative(l, vec<1>{q}, vec<1>{0.4}, t), -0.25 * q * q);
    EXPECT_TRUE(depends_on_time(l));
}

TEST(LagrangianTime, EnergyBalanceClosesAtOrderFourAndMatchesTheExpression) {
    const lagrangian_system<stiffening> sys{stiffening{}};
    const lagrangian_system<stiffening_opaque> opaque{stiffening_opaque{}};
    EXPECT_TRUE(conserves_energy(sys));
    EXPECT_FALSE(conserves_energy(opaque)); // negative control: no ∂L/∂t, no watch
    const auto [coarse, w_coarse] = time_balance(stiffening{}, 1000);
    const auto [fine, w_fine] = time_balance(stiffening{}, 2000);
    // The energy grows from 0.5 to about 1.26: the balance must hold far below that change.
    EXPECT_GT(std::abs(w_fine), 0.1);
    EXPECT_LE(fine, 1e-9);
    EXPECT_NEAR(coarse / fine, 16.0, 3.0);
    RecordProperty("balance_1000", test::sci(coarse));
    RecordProperty("balance_2000", test::sci(fine));
    // The expression Lagrangian's ∂L/∂t is symbolic: the same work to round-off.
    const expression_lagrangian typed("0.5*x_dot**2 - 0.5*(1 + t/2)*x**2", {"x"});
    const auto [e_fine, e_w] = time_balance(typed, 2000);
    EXPECT_NEAR(e_w, w_fine, 1e-12);
    RecordProperty("work_apart", test::sci(std::abs(e_w - w_fine)));
    EXPECT_NEAR(e_fine, fine, 1e-12);
    // Without ∂L/∂t the engine puts nothing into W.
    EXPECT_EQ(time_balance(stiffening_opaque{}, 100).second, 0.0);
}
