// Tests for force_with_value (systems/forcing.hpp): the built-in forces' value alone, which the
// Newton iterates that keep their Jacobian (chord updates) evaluate instead of the force's
// Jacobians. Against the same force's derivatives(): the same value, bit for bit (the same
// operations), and the Jacobians left as they were.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "varsym/systems/expression_force.hpp"
#include "varsym/systems/forcing.hpp"

namespace {

using namespace varsym;

using robot_force = force_sum<rayleigh_damping<dynamic>, pd_controller<dynamic>, expression_force>;

robot_force three_joint_force() {
    rayleigh_damping<dynamic> damping(vec<dynamic>(vec<dynamic>::Constant(3, 0.3)).asDiagonal());
    pd_controller<dynamic> pd;
    pd.kp = vec<dynamic>::Constant(3, 80.0).asDiagonal();
    pd.kd = vec<dynamic>::Constant(3, 2.0).asDiagonal();
    pd.reference = [](double t, vec<dynamic>& r, vec<dynamic>& rate) {
        r << std::sin(t), 0.8, -1.5;
        rate << std::cos(t), 0.0, 0.0;
    };
    expression_force torque({"0.5*sin(a)*b_dot", "-a*c", "t*c_dot"}, {"a", "b", "c"});
    return robot_force(std::move(damping), std::move(pd), std::move(torque));
}

TEST(ForceValue, TheBuiltInForcesGiveTheirValueAlone) {
    static_assert(force_with_value<rayleigh_damping<dynamic>>);
    static_assert(force_with_value<pd_controller<2>>);
    static_assert(force_with_value<expression_force>);
    static_assert(force_with_value<robot_force>);
    const robot_force f = three_joint_force();
    vec<dynamic> q(3), v(3);
    q << 0.3, -0.7, 1.1;
    v << 0.2, 0.5, -1.3;
    const double t = 0.37;
    force_terms<dynamic> full;
    full.f.resize(3);
    full.fq.resize(3, 3);
    full.fv.resize(3, 3);
    evaluate_force(f, q, v, t, full, true);
    // The value alone: f bit for bit, fq and fv untouched (NaN stays NaN).
    const double nan = std::numeric_limits<double>::quiet_NaN();
    force_terms<dynamic> alone;
    alone.f.setZero(3);
    alone.fq.setConstant(3, 3, nan);
    alone.fv.setConstant(3, 3, nan);
    evaluate_force(f, q, v, t, alone, false);
    EXPECT_EQ(alone.f, full.f);
    EXPECT_TRUE(alone.fq.array().isNaN().all());
    EXPECT_TRUE(alone.fv.array().isNaN().all());
    // Negative control: with its Jacobians asked for, they are written (and finite).
    evaluate_force(f, q, v, t, alone, true);
    EXPECT_TRUE(alone.fq.allFinite() && alone.fv.allFinite());
    EXPECT_EQ(alone.fq, full.fq);
    // The value is the force: against operator() (the sum of the parts' own values).
    EXPECT_LE((f(q, v, t) - full.f).lpNorm<Eigen::Infinity>(), 1e-13);
    EXPECT_GT(full.f.norm(), 1.0); // not a zero force
}

/// A two-joint arm hanging from its first joint (unit masses and lengths, g = 9.81 m/s²):
/// L = ½ |q̇|² − V(q), V = −g (2 cos q₀ + cos(q₀ + q₁)) (the kinetic term simplified: the
/// compensation sees L at q̇ = 0 only).
struct arm2 {
    static constexpr int dim = 2;
    template <class T>
    T operator()(const tvec<T, 2>& q, const tvec<T, 2>& v) const {
        using std::cos;
        return 0.5 * v.squaredNorm() + 9.81 * (2.0 * cos(q(0)) + cos(q(0) + q(1)));
    }
};

/// arm2 with its derivatives by hand (automatic ones underneath), counting which are asked for.
struct counted_arm2 : arm2 {
    static inline int gradients = 0, seconds = 0;
    void gradient(const vec<2>& q, const vec<2>& v, lagrangian_terms<2>& t) const {
        ++gradients;
        evaluate_gradient(arm2{}, q, v, t);
    }
    void derivatives(const vec<2>& q, const vec<2>& v, lagrangian_terms<2>& t) const {
        ++seconds;
        evaluate(arm2{}, q, v, t);
    }
};

} // namespace

TEST(ForceValue, TheGravityCompensationsValueTakesFirstDerivativesOnly) {
    // A PD controller compensating gravity, −∂L/∂q(q, 0): its value alone must not evaluate
    // L's second derivatives (a robot's O(n²) pass, which the Newton iterates that keep their
    // Jacobian would pay for nothing), and must equal its derivatives' f.
    static_assert(lagrangian_with_gradient<counted_arm2>);
    pd_controller<2> pd;
    pd.kp = mat<2>{{30.0, 0.0}, {0.0, 20.0}};
    pd.kd = mat<2>{{3.0, 0.0}, {0.0, 2.0}};
    pd_controller<2> bare = pd;
    pd.compensate(counted_arm2{});
    const vec<2> q{0.4, -0.9}, v{0.3, 1.2};
    counted_arm2::gradients = counted_arm2::seconds = 0;
    force_terms<2> full;
    pd.derivatives(q, v, 0.1, full);
    EXPECT_EQ(counted_arm2::seconds, 1);
    vec<2> alone;
    pd.value(q, v, 0.1, alone);
    EXPECT_EQ(counted_arm2::seconds, 1); // the value alone took no second derivatives
    EXPECT_EQ(counted_arm2::gradients, 1);
    // The same ∂L/∂q: first-order forward mode and the nested second-order one sum alike.
    EXPECT_EQ(alone, full.f);
    EXPECT_EQ(pd(q, v, 0.1), alone); // operator() is the value
    EXPECT_EQ(counted_arm2::seconds, 1);
    // Both are the PD's torques plus τ_g = −∂L/∂q(q, 0) = g (2 sin q₀ + sin(q₀ + q₁),
    // sin(q₀ + q₁)), by hand; the compensation's Jacobian −∂²L/∂q² likewise.
    const double g = 9.81, s01 = std::sin(q(0) + q(1)), c01 = std::cos(q(0) + q(1));
    const vec<2> tau{g * (2.0 * std::sin(q(0)) + s01), g * s01};
    const vec<2> expected = -pd.kp * q - pd.kd * v + tau;
    EXPECT_LE((alone - expected).lpNorm<Eigen::Infinity>(), 1e-13);
    EXPECT_LE((full.f - expected).lpNorm<Eigen::Infinity>(), 1e-13);
    const mat<2> dtau{{g * (2.0 * std::cos(q(0)) + c01), g * c01}, {g * c01, g * c01}};
    EXPECT_LE((full.fq - (dtau - pd.kp)).lpNorm<Eigen::Infinity>(), 1e-13);
    // Negative control: the compensation is there (O(10) N m against the bare controller).
    EXPECT_GT((alone - bare(q, v, 0.1)).norm(), 1.0);
}
