// tests/numeric/test_symplecticity.cpp: the step maps preserve the symplectic form,
// det ∂(q_{j+1}, p_{j+1})/∂(q_j, p_j) = 1 for d = 1 and Jᵀ Ω J = Ω for d = 2 (paper eq.
// newmark-symplectic and §4), measured by finite differences of the step map alone.
#include <gtest/gtest.h>

#include <numbers>

#include "test_support.hpp"
#include "varsym/diagnostics/symplecticity.hpp"
#include "varsym/problems/pendulum.hpp"
#include "varsym/schemes/newmark.hpp"
#include "varsym/schemes/simpson.hpp"

using namespace varsym;
using std::numbers::pi;

namespace {

// Richardson-extrapolated central differences with δ = 1e-3: truncation ~δ⁴|∂⁵Φ| ≲ 1e-12 and
// round-off ~ε|Φ|/δ ≈ 1e-12 for states of size ≤ 10; the bound 1e-10 is two orders above both.
constexpr double map_tol = 1e-10;

template <class Stepper>
double defect(const typename Stepper::system_type& sys, double h,
              const phase_state<Stepper::dim>& x) {
    auto step = [&](phase_state<Stepper::dim>& y) {
        Stepper s(sys, h);
        if (!s.step(y).converged) throw std::runtime_error("step did not converge");
    };
    return symplecticity_defect(tangent_map<Stepper::dim>(step, x));
}

} // namespace

TEST(Symplecticity, PendulumBothSchemesSeveralStatesAndSteps) {
    const auto sys = pendulum::make_system(1.0, 2 * pi);
    using sys_t = decltype(sys);
    const phase_state<1> states[] = {{vec<1>{pi / 2}, vec<1>{0.0}},
                                     {vec<1>{0.3}, vec<1>{-2.0}},
                                     {vec<1>{2.5}, vec<1>{1.0}},
                                     {vec<1>{-1.0}, vec<1>{5.0}},
                                     {vec<1>{3.0}, vec<1>{9.0}}};
    for (double h : {0.118, 0.0236, 0.0059}) {
        for (const auto& x : states) {
            EXPECT_LE(defect<newmark::stepper<sys_t>>(sys, h, x), map_tol) << "newmark h = " << h;
            EXPECT_LE(defect<simpson::stepper<sys_t>>(sys, h, x), map_tol) << "simpson h = " << h;
        }
    }
}

TEST(Symplecticity, CoupledPendulumsJtOmegaJ) {
    const auto sys = test::coupled_system();
    using sys_t = decltype(sys);
    const phase_state<2> x{vec<2>{1.0, -0.5}, vec<2>{0.3, 1.2}};
    for (double h : {0.2, 0.05}) {
        EXPECT_LE(defect<newmark::stepper<sys_t>>(sys, h, x), map_tol) << "h = " << h;
        EXPECT_LE(defect<simpson::stepper<sys_t>>(sys, h, x), map_tol) << "h = " << h;
    }
}

TEST(Symplecticity, TheCheckCanFail) {
    // Negative control: explicit Euler, q += h p/m, p −= h V'(q), has det J = 1 + h²ω² cos q ≠ 1.
    const auto sys = pendulum::make_system(1.0, 2 * pi);
    auto euler = [&](phase_state<1>& y) {
        const double h = 0.0236;
        const vec<1> g = sys.potential().gradient(y.q);
        y.q += h * y.p;
        y.p -= h * g;
    };
    const phase_state<1> x{vec<1>{0.3}, vec<1>{-2.0}};
    EXPECT_GT(symplecticity_defect(tangent_map<1>(euler, x)), 1e-3);
}
