// The recursive derivatives of a multibody Lagrangian (varsym/multibody/algorithms.hpp), its
// contracted third ones (lagrangian.hpp) among them, against
// forward-mode AD of a second implementation that shares no code with them
// (reference_lagrangian.hpp: classical vectors, no spatial algebra), on a branched tree of
// revolute and prismatic joints with random placements, axes and full inertia tensors; and the
// recursive Newton–Euler bias forces and the composite-rigid-body M(q) against the Euler–Lagrange
// equations they must satisfy; mimic joints against the same tree with the coupling substituted.
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "multibody/random_tree.hpp"
#include "multibody/reference_lagrangian.hpp"
#include "varsym/multibody/lagrangian.hpp"
#include "varsym/optimal/third_order.hpp"

namespace {

using namespace varsym;
using multibody::vec3;
using test::mimic_tree;
using test::random_tree;

/// Largest |a − b| relative to max(1, |b|) over the entries.
template <class A, class B>
double relative_gap(const A& a, const B& b) {
    return (a - b).cwiseAbs().maxCoeff() / std::max(1.0, b.cwiseAbs().maxCoeff());
}

// Both sides sum O(10²) products of O(1–10) numbers in double: a few hundred ulps of the
// largest term, 1e-12 relative, is round-off; a wrong sign or term is O(1).
constexpr double tolerance = 1e-12;

TEST(MultibodyDerivatives,
     FirstAndSecondDerivativesEqualAutomaticDifferentiationOfASecondImplementation) {
    const multibody::tree m = random_tree(7);
    const multibody::robot_lagrangian l(std::make_shared<const multibody::tree>(m));
    const test::reference_lagrangian<7> ref{&m};
    std::mt19937 g(11);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    for (int k = 0; k < 5; ++k) {
        vec<7> q, v;
        for (int i = 0; i < 7; ++i) {
            q(i) = u(g);
            v(i) = u(g);
        }
        lagrangian_terms<7> expected;
        evaluate(ref, q, v, expected);
        lagrangian_terms<dynamic> got;
        l.derivatives(q, v, got);
        EXPECT_NEAR(got.value, expected.value, tolerance * std::max(1.0, std::abs(expected.value)));
        EXPECT_LT(relative_gap(got.lq, expected.lq), tolerance) << "dL/dq at state " << k;
        EXPECT_LT(relative_gap(got.lv, expected.lv), tolerance) << "dL/dqdot at state " << k;
        EXPECT_LT(relative_gap(got.lqq, expected.lqq), tolerance) << "d2L/dq2 at state " << k;
        EXPECT_LT(relative_gap(got.lqv, expected.lqv), tolerance) << "d2L/dqdqdot at state " << k;
        EXPECT_LT(relative_gap(got.lvv, expected.lvv), tolerance) << "M(q) at state " << k;
        lagrangian_terms<dynamic> first;
        l.gradient(q, v, first);
        EXPECT_EQ(first.lq, got.lq);
        EXPECT_EQ(first.lv, got.lv);
        EXPECT_DOUBLE_EQ(l(q, v), got.value);
    }
}

TEST(MultibodyDerivatives, ADifferentInertiaInTheReferenceIsSeen) {
    // Negative control: the comparison above detects a 1 % change of one off-diagonal inertia.
    const multibody::tree m = random_tree(7);
    multibody::tree changed = m;
    changed.bodies[4].inertia(0, 1) *= 1.01;
    changed.bodies[4].inertia(1, 0) *= 1.01;
    const multibody::robot_lagrangian l(std::make_shared<const multibody::tree>(m));
    const test::reference_lagrangian<7> ref{&changed};
    vec<7> q, v;
    q << 0.3, -0.7, 0.2, 1.1, -0.4, 0.5, 0.9;
    v << 1.0, 0.5, -0.3, 0.8, -1.2, 0.4, 0.7;
    lagrangian_terms<7> expected;
    evaluate(ref, q, v, expected);
    lagrangian_terms<dynamic> got;
    l.derivatives(q, v, got);
    EXPECT_GT(relative_gap(got.lvv, expected.lvv), 100 * tolerance);
    EXPECT_GT(relative_gap(got.lqq, expected.lqq), 100 * tolerance);
}

TEST(MultibodyDerivatives, ThirdDerivativesEqualAutomaticDifferentiationOfASecondImplementation) {
    // The Hessian of aᵀ ∂L/∂q + bᵀ ∂L/∂q̇ (robot_lagrangian::third: dual numbers through the
    // recursive algorithms) against the reference's by nested forward-mode AD
    // (optimal::contracted_third), on the branched tree with its prismatic joints. Third
    // derivatives sum more products than second ones: 1e-11 relative is still round-off.
    const multibody::tree m = random_tree(5);
    const multibody::robot_lagrangian l(std::make_shared<const multibody::tree>(m));
    const test::reference_lagrangian<7> ref{&m};
    std::mt19937 g(13);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    for (int k = 0; k < 3; ++k) {
        vec<7> q, v, a, b;
        for (int i = 0; i < 7; ++i) {
            q(i) = u(g);
            v(i) = u(g);
            a(i) = u(g);
            b(i) = u(g);
        }
        const mat<14> expected = optimal::contracted_third(ref, q, v, 0.0, a, b);
        mat<dynamic> got;
        l.third(q, v, a, b, got);
        EXPECT_LT(relative_gap(got, expected), 1e-11) << "state " << k;
        EXPECT_GT(expected.cwiseAbs().maxCoeff(), 1.0); // not vacuous
        // Negative control: another direction gives another Hessian.
        mat<dynamic> other;
        l.third(q, v, b, a, other);
        EXPECT_GT(relative_gap(other, expected), 1e-3);
    }
}

// velocities and subtree_sums hand a chain's values from a body to the next in registers where
// the parent is the body just before (algorithms.hpp), through memory otherwise: they must add
// exactly what the plain loops add, in the same order, on trees that mix both (random_tree: 0 ← 1
// ← 2 carried, 1 ← 3 and 0 ← 5 through memory), so the sums are equal to the bit, not to a
// tolerance. (Checked: adding a carried child's sums before its siblings' fails.)
TEST(MultibodyPasses, CarriedVelocitiesAndSubtreeSumsAreThePlainLoopsToTheBit) {
    std::mt19937 g(17);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    for (const multibody::tree& m : {random_tree(3), random_tree(8), mimic_tree(true)}) {
        const int n = m.body_count();
        vec<dynamic> q(m.dof()), v(m.dof());
        for (int i = 0; i < m.dof(); ++i) {
            q(i) = u(g);
            v(i) = u(g);
        }
        multibody::workspace w;
        multibody::kinematics(m, w, q);
        multibody::velocities(m, w, v);
        multibody::subtree_sums(m, w, true);
        std::vector<multibody::vec6> vel(static_cast<std::size_t>(n)), hc = w.h, fc = w.gravity;
        std::vector<multibody::mat6> ic = w.inertia;
        for (int i = 0; i < n; ++i) {
            const auto k = static_cast<std::size_t>(i);
            const int p = m.bodies[k].parent;
            vel[k] = w.s[k] * m.joint_rate(v, i);
            if (p >= 0) vel[k] += vel[static_cast<std::size_t>(p)];
        }
        for (int i = n - 1; i >= 0; --i) {
            const auto k = static_cast<std::size_t>(i);
            const int p = m.bodies[k].parent;
            if (p < 0) continue;
            const auto pk = static_cast<std::size_t>(p);
            hc[pk] += hc[k];
            fc[pk] += fc[k];
            ic[pk] += ic[k];
        }
        for (std::size_t k = 0; k < static_cast<std::size_t>(n); ++k) {
            EXPECT_EQ(w.v[k], vel[k]) << "body " << k;
            EXPECT_EQ(w.h_c[k], hc[k]) << "body " << k;
            EXPECT_EQ(w.gravity_c[k], fc[k]) << "body " << k;
            EXPECT_EQ(w.inertia_c[k], ic[k]) << "body " << k;
        }
    }
}

TEST(MultibodyDerivatives, NewtonEulerBiasAndCompositeMassMatrixSatisfyEulerLagrange) {
    // d/dt ∂L/∂q̇ − ∂L/∂q = M q̈ + (∂²L/∂q∂q̇)ᵀ q̇ − ∂L/∂q: the bias C q̇ + g of the recursive
    // Newton–Euler pass is (∂²L/∂q∂q̇)ᵀ q̇ − ∂L/∂q, and g(q) = −∂L/∂q(q, 0).
    const multibody::tree m = random_tree(3);
    const multibody::robot_lagrangian l(std::make_shared<const multibody::tree>(m));
    multibody::workspace w;
    vec<dynamic> q(7), v(7), bias(7), gravity(7);
    q << 0.3, -0.7, 0.2, 1.1, -0.4, 0.5, 0.9;
    v << 1.0, 0.5, -0.3, 0.8, -1.2, 0.4, 0.7;
    lagrangian_terms<dynamic> t;
    l.derivatives(q, v, t);
    multibody::bias_forces(m, w, q, v, bias);
    EXPECT_LT(relative_gap(bias, vec<dynamic>(t.lqv.transpose() * v - t.lq)), tolerance);
    multibody::bias_forces(m, w, q, vec<dynamic>::Zero(7), gravity);
    lagrangian_terms<dynamic> rest;
    l.gradient(q, vec<dynamic>::Zero(7), rest);
    EXPECT_LT(relative_gap(gravity, vec<dynamic>(-rest.lq)), tolerance);
    mat<dynamic> mass(7, 7);
    multibody::mass_matrix(m, w, q, mass);
    EXPECT_LT(relative_gap(mass, t.lvv), tolerance);
    EXPECT_EQ(mass, mass.transpose());
}

TEST(MultibodyMimic, MimicJointsAreTheirCouplingSubstitutedIntoTheFullTree) {
    // Reference: the ten-coordinate tree at θ = A q + b, θ̇ = A q̇ (no mimic: the algorithms'
    // uncoupled path), where L(q, q̇) = L10(θ, θ̇), ∂L/∂q = Aᵀ ∂L10/∂θ, ∂²L = Aᵀ ∂²L10 A, and
    // the AD of the second implementation on the coupled tree.
    const multibody::tree m = mimic_tree(true), full = mimic_tree(false);
    ASSERT_EQ(m.dof(), 7);
    const multibody::robot_lagrangian l(std::make_shared<const multibody::tree>(m));
    const multibody::robot_lagrangian l10(std::make_shared<const multibody::tree>(full));
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero(10, 7);
    a.topRows(7).setIdentity();
    a(7, 2) = -0.7;
    a(8, 0) = 1.3;
    a(9, 6) = 0.5;
    Eigen::VectorXd offset = Eigen::VectorXd::Zero(10);
    offset(7) = 0.2;
    offset(8) = -0.1;
    const test::reference_lagrangian<7> ref{&m};
    std::mt19937 g(17);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    for (int k = 0; k < 3; ++k) {
        vec<7> q, v, da, db;
        for (int i = 0; i < 7; ++i) {
            q(i) = u(g);
            v(i) = u(g);
            da(i) = u(g);
            db(i) = u(g);
        }
        lagrangian_terms<dynamic> t, t10;
        l.derivatives(q, v, t);
        l10.derivatives(a * q + offset, a * v, t10);
        EXPECT_NEAR(t.value, t10.value, tolerance * std::abs(t10.value));
        EXPECT_LT(relative_gap(t.lq, vec<dynamic>(a.transpose() * t10.lq)), tolerance);
        EXPECT_LT(relative_gap(t.lv, vec<dynamic>(a.transpose() * t10.lv)), tolerance);
        EXPECT_LT(relative_gap(t.lqq, mat<dynamic>(a.transpose() * t10.lqq * a)), tolerance);
        EXPECT_LT(relative_gap(t.lqv, mat<dynamic>(a.transpose() * t10.lqv * a)), tolerance);
        EXPECT_LT(relative_gap(t.lvv, mat<dynamic>(a.transpose() * t10.lvv * a)), tolerance);
        lagrangian_terms<7> e; // AD of the second implementation
        evaluate(ref, q, v, e);
        EXPECT_LT(relative_gap(t.lqq, e.lqq), tolerance);
        EXPECT_LT(relative_gap(t.lqv, e.lqv), tolerance);
        // Third derivatives (dual numbers through the coupled algorithms) and the classical ones.
        const mat<14> expected = optimal::contracted_third(ref, q, v, 0.0, da, db);
        mat<dynamic> got;
        l.third(q, v, da, db, got);
        EXPECT_LT(relative_gap(got, expected), 1e-11);
        multibody::workspace w;
        vec<dynamic> bias(7);
        mat<dynamic> mass(7, 7);
        multibody::bias_forces(m, w, vec<dynamic>(q), vec<dynamic>(v), bias);
        multibody::mass_matrix(m, w, vec<dynamic>(q), mass);
        EXPECT_LT(relative_gap(bias, vec<dynamic>(t.lqv.transpose() * v - t.lq)), tolerance);
        EXPECT_LT(relative_gap(mass, t.lvv), tolerance);
        // The frame on the last mimic body chain (body 8): its Jacobian is ∂(pose)/∂q.
        const multibody::frame f{"tip", 8, {}};
        Eigen::MatrixXd jac, jac10;
        multibody::kinematics(m, w, q);
        multibody::frame_jacobian(m, w, f, jac);
        multibody::workspace w10;
        multibody::kinematics(full, w10, Eigen::VectorXd(a * q + offset));
        multibody::frame_jacobian(full, w10, f, jac10);
        EXPECT_LT(relative_gap(jac, Eigen::MatrixXd(jac10 * a)), tolerance);
    }
    // Negative control: the coupling's offset matters.
    multibody::tree shifted = m;
    shifted.mimics[0].offset = 0.0;
    const multibody::robot_lagrangian ls(std::make_shared<const multibody::tree>(shifted));
    const vec<dynamic> q = vec<dynamic>::LinSpaced(7, -0.5, 0.9), v = vec<dynamic>::Ones(7);
    EXPECT_GT(std::abs(ls(q, v) - l(q, v)), 1e-3);
}

} // namespace

TEST(MultibodyFrames, FrameJacobianIsTheDerivativeOfTheFramePose) {
    // ∂(origin)/∂q_j and the angular velocity per joint rate (ω̂_j = ∂R/∂q_j Rᵀ) by central
    // differences of frame_pose (step 1e-6: truncation and round-off about 1e-10) on the
    // branched tree: the frame on body 4 sees joints 4, 3, 1, 0 and not 2, 5, 6, whose columns
    // must be exactly zero.
    const multibody::tree m = random_tree(11);
    multibody::frame f{
        "tool", 4, {multibody::roll_pitch_yaw(vec3(0.3, -0.2, 0.9)), vec3(0.1, 0.2, -0.3)}};
    const Eigen::VectorXd q = Eigen::VectorXd::LinSpaced(7, -0.8, 1.1);
    multibody::workspace w;
    multibody::kinematics(m, w, q);
    Eigen::MatrixXd jac;
    multibody::frame_jacobian(m, w, f, jac);
    const multibody::mat3 r0 = multibody::frame_pose(w, f).rotation;
    Eigen::MatrixXd fd(6, 7);
    const double eps = 1e-6;
    for (int j = 0; j < 7; ++j) {
        multibody::pose x[2];
        for (int k = 0; k < 2; ++k) {
            Eigen::VectorXd qs = q;
            qs(j) += k == 0 ? eps : -eps;
            multibody::kinematics(m, w, qs);
            x[k] = multibody::frame_pose(w, f);
        }
        const multibody::mat3 dr = (x[0].rotation - x[1].rotation) / (2 * eps);
        const multibody::mat3 omega = dr * r0.transpose();
        fd.col(j) << omega(2, 1), omega(0, 2), omega(1, 0), (x[0].origin - x[1].origin) / (2 * eps);
    }
    EXPECT_LT(relative_gap(jac, fd), 1e-8);
    for (const int j : {2, 5, 6})
        EXPECT_EQ(jac.col(j).norm(), 0.0);
    EXPECT_GT(jac.col(0).norm(), 0.1); // not vacuous
}
