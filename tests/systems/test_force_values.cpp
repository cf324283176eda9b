// Tests for force_with_value (systems/forcing.hpp): the built-in forces' value alone, which the
// Newton iterates that keep their Jacobian (chord updates) evaluate instead of the force's
// Jacobians. Against the same force's derivatives(): the same value, bit for bit (the same
// operations), and the Jacobians left as they were.
#include <gtest/gtest.h>

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

} // namespace
