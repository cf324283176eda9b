// tests/schemes/test_failure.cpp: a failed step names its cause (schemes/variational_failure.hpp,
// schemes/constrained_failure.hpp, integrate.hpp's step_failure). Each case is built so that one
// cause, known in advance, stops the run:
//  - L = ½ (1 − q²) q̇²: at q → 1 the mass matrix vanishes (the speed √(2E/(1 − q²)) diverges);
//  - L = ½ q̇² − 2√q: the particle falls into q = 0 in finite time, and √q is NaN beyond;
//  - a force that is NaN after t = 1;
//  - a pendulum whose constraint is NaN for x > 0.5;
//  - a particle sliding into the cusp of y² = x³, where ∇g = 0;
// and, the negative control, a step that fails only because Newton is given one iteration: no
// cause, and the advice to use a smaller time step.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "varsym/integrate.hpp"
#include "varsym/schemes/constrained.hpp"
#include "varsym/schemes/variational.hpp"

using namespace varsym;

namespace {

constexpr double nan_value = std::numeric_limits<double>::quiet_NaN();

// L = ½ m(q) q̇² − V(q): m = 1 − q² if `degenerate` (else 1), V = 2√q if `root_well`,
// 1 − cos q if `pendulum` (else ½ q²).
struct fragile {
    static constexpr int dim = 1;
    bool degenerate = false, root_well = false, pendulum = false;
    template <class T>
    T operator()(const tvec<T, 1>& q, const tvec<T, 1>& v) const {
        using std::cos;
        using std::sqrt;
        const T m = degenerate ? T(1.0 - q(0) * q(0)) : T(1.0);
        const T potential = root_well  ? T(2.0 * sqrt(q(0)))
                            : pendulum ? T(1.0 - cos(q(0)))
                                       : T(0.5 * q(0) * q(0));
        return 0.5 * m * v(0) * v(0) - potential;
    }
};

// A light damping, NaN after t = 1.
struct nan_after_one {
    static constexpr int dim = 1;
    template <class T>
    tvec<T, 1> operator()(const tvec<T, 1>&, const tvec<T, 1>& v, double t) const {
        return tvec<T, 1>(t > 1.0 ? T(nan_value) : T(-0.1 * v(0)));
    }
};

// A unit mass in the plane, gravity g along −y (g = 0: free).
struct planar_mass {
    static constexpr int dim = 2;
    double g = 1.0;
    template <class T>
    T operator()(const tvec<T, 2>& q, const tvec<T, 2>& v) const {
        return 0.5 * v.squaredNorm() - g * q(1);
    }
};

// The unit circle, NaN for x > 0.5 (`circle`), or the cusp y² = x³.
struct curve {
    static constexpr int dim = 2, count = 1;
    bool cusp = false;
    template <class T>
    tvec<T, 1> operator()(const tvec<T, 2>& q) const {
        if (cusp) return tvec<T, 1>(q(1) * q(1) - q(0) * q(0) * q(0));
        return tvec<T, 1>(q(0) > 0.5 ? T(nan_value) : T(q.squaredNorm() - 1.0));
    }
};

/// Runs n steps of h and returns the step_failure's what() (empty if none), with the step it
/// names and the state it left.
template <class S, int D>
std::string failure(S& st, phase_state<D>& x, int n, std::size_t* step = nullptr) {
    try {
        integrate(st, x, 0.0, static_cast<std::size_t>(n), [](auto, auto, const auto&) {});
    } catch (const step_failure& e) {
        if (step) *step = e.step();
        EXPECT_EQ(e.diagnosis().find(e.cause()) == std::string::npos, false);
        return e.what();
    }
    return {};
}

bool has(const std::string& s, const char* part) {
    return s.find(part) != std::string::npos;
}

} // namespace

TEST(StepFailure, SingularMassMatrixIsNamed) {
    fragile l;
    l.degenerate = true;
    general::stepper<fragile> st(lagrangian_system<fragile>(l), 0.01, scheme_kind::simpson);
    // The exact motion reaches q = 1 at t = π/4 with an infinite speed; the steps fail there,
    // or creep up to q = 1 and fail a little later (measured: t = 0.79 or 1.01, by rounding).
    phase_state<1> x{vec<1>{0.0}, vec<1>{1.0}};
    const std::string what = failure(st, x, 300);
    EXPECT_TRUE(has(what, "the mass matrix d2L/dqdot2 is singular or not positive definite"))
        << what;
    EXPECT_NEAR(x.q(0), 1.0, 0.05); // the last good state
    EXPECT_FALSE(has(what, "use a smaller time step")) << what;
}

TEST(StepFailure, NaNFromTheLagrangianIsNamed) {
    fragile l;
    l.root_well = true;
    general::stepper<fragile> st(lagrangian_system<fragile>(l), 0.01, scheme_kind::simpson);
    phase_state<1> x{vec<1>{1.0}, vec<1>{0.0}};
    const std::string what = failure(st, x, 300);
    EXPECT_TRUE(has(what, "the Lagrangian or its derivatives are NaN or infinite")) << what;
}

TEST(StepFailure, NaNFromTheForceIsNamedWithItsTime) {
    general::stepper<fragile, nan_after_one> st(lagrangian_system<fragile>({}), {}, 0.1,
                                                scheme_kind::simpson);
    phase_state<1> x{vec<1>{1.0}, vec<1>{0.0}};
    std::size_t step = 0;
    const std::string what = failure(st, x, 30, &step);
    // Step 11 (t = 1 → 1.1) is the first with a node after t = 1: its midpoint, t = 1.05.
    EXPECT_EQ(step, 11U) << what;
    EXPECT_TRUE(has(what, "the force or its Jacobians are NaN or infinite")) << what;
    EXPECT_TRUE(has(what, "t = 1.05")) << what;
}

TEST(StepFailure, NaNFromTheConstraintIsNamed) {
    curve c;
    general::constrained_stepper<planar_mass, curve> st(lagrangian_system<planar_mass>({}), c, 0.01,
                                                        scheme_kind::simpson);
    // A pendulum from θ = −1 at rest: it swings to x = sin 1 > 0.5.
    phase_state<2> x{vec<2>{-std::sin(1.0), -std::cos(1.0)}, vec<2>{0.0, 0.0}};
    st.check_initial(x);
    const std::string what = failure(st, x, 1000);
    EXPECT_TRUE(has(what, "the constraint or its Jacobian is NaN or infinite")) << what;
    EXPECT_LE(x.q(0), 0.5);
}

TEST(StepFailure, SingularConstraintJacobianMidRunIsNamed) {
    curve c;
    c.cusp = true;
    planar_mass free;
    free.g = 0.0;
    for (double h : {0.1, 0.01, 0.001}) {
        general::constrained_stepper<planar_mass, curve> st(lagrangian_system<planar_mass>(free), c,
                                                            h, scheme_kind::simpson);
        // From (1, 1) towards the cusp at unit speed, along the tangent (1, 3/2 √x).
        const vec<2> tangent = vec<2>(1.0, 1.5).normalized();
        phase_state<2> x{vec<2>{1.0, 1.0}, -tangent};
        st.check_initial(x);
        const std::string what = failure(st, x, static_cast<int>(3.0 / h));
        EXPECT_TRUE(has(what, "the constraint Jacobian is singular or nearly so")) << what;
    }
}

TEST(StepFailure, AStepTooHardForNewtonNamesNoCause) {
    // The negative control: a regular pendulum step with one Newton iteration allowed (the
    // pendulum's, not the oscillator's: one Newton update solves a linear step's equations to
    // round-off, and the residual's stop takes it).
    newton_options opt;
    opt.iteration = iteration_kind::newton;
    opt.max_iterations = 1;
    fragile l;
    l.pendulum = true;
    general::stepper<fragile> st(lagrangian_system<fragile>(l), 0.5, scheme_kind::simpson, opt);
    phase_state<1> x{vec<1>{1.0}, vec<1>{0.0}};
    const std::string what = failure(st, x, 10);
    ASSERT_FALSE(what.empty());
    EXPECT_TRUE(has(what, "use a smaller time step")) << what;
    EXPECT_FALSE(has(what, "NaN")) << what;
    EXPECT_FALSE(has(what, "singular")) << what;
}
