// A robot with a free-floating base (varsym/multibody/floating.hpp): its Lagrangian's derivatives
// in (x, u, θ) against forward-mode AD of a second implementation written here with classical
// vectors (no spatial algebra, no chart); then the motion, by the constrained general engine:
// a torque-free rigid body against its closed form in Jacobi's elliptic functions, the total
// momenta of a floating arm in free flight (conserved to round-off by Noether's theorem) and
// under gravity (the vertical momentum falls by M g t, the vertical angular momentum stays), and
// a two-body arm whose base turns by the angle its zero angular momentum prescribes.
#include <cmath>
#include <random>

#include <boost/math/special_functions/jacobi_elliptic.hpp>
#include <gtest/gtest.h>

#include "varsym/integrate.hpp"
#include "varsym/multibody/floating.hpp"
#include "varsym/schemes/constrained.hpp"
#include "varsym/systems/expression_force.hpp"

namespace floating_test {

using namespace varsym;
using multibody::mat3;
using multibody::vec3;

/// L in (x, u, θ) by classical vectors: the root link at (R(û), x) with angular velocity
/// ω = R W(u) u̇ and velocity ẋ, each body after it as in tests/multibody/reference_lagrangian.hpp,
/// plus ½ κ (u·u̇)² (floating.hpp, Q2). `m`: the tree before with_base (its root's mass).
template <int D>
struct reference_free {
    static constexpr int dim = D;
    const multibody::tree* m = nullptr;

    template <class T>
    T operator()(const tvec<T, D>& q, const tvec<T, D>& qd) const {
        using std::cos, std::sin, std::sqrt;
        using m3 = Eigen::Matrix<T, 3, 3>;
        using v3 = Eigen::Matrix<T, 3, 1>;
        auto cross = [](const v3& a, const v3& b) {
            return v3(a(1) * b(2) - a(2) * b(1), a(2) * b(0) - a(0) * b(2),
                      a(0) * b(1) - a(1) * b(0));
        };
        const v3 x(q(0), q(1), q(2)), xd(qd(0), qd(1), qd(2));
        const T n2 = q(3) * q(3) + q(4) * q(4) + q(5) * q(5) + q(6) * q(6);
        const T n = sqrt(n2);
        const T w = q(3) / n, a = q(4) / n, b = q(5) / n, c = q(6) / n;
        m3 r;
        r << 1.0 - 2.0 * (b * b + c * c), 2.0 * (a * b - w * c), 2.0 * (a * c + w * b),
            2.0 * (a * b + w * c), 1.0 - 2.0 * (a * a + c * c), 2.0 * (b * c - w * a),
            2.0 * (a * c - w * b), 2.0 * (b * c + w * a), 1.0 - 2.0 * (a * a + b * b);
        const v3 v(q(4), q(5), q(6)), vd(qd(4), qd(5), qd(6));
        const v3 om = r * ((2.0 / n2) * (q(3) * vd - qd(3) * v - cross(v, vd)));
        const v3 g = m->gravity.cast<T>();
        T l(0.0);
        auto body_terms = [&](double mass, const Eigen::Vector3d& com, const Eigen::Matrix3d& in,
                              const m3& rot, const v3& origin, const v3& omega, const v3& vel) {
            const v3 cc = rot * com.cast<T>() + origin;
            const v3 vc = vel + cross(omega, cc - origin);
            const v3 iw = rot * (in.cast<T>() * (rot.transpose() * omega));
            l += 0.5 * mass * vc.dot(vc) + 0.5 * omega.dot(iw) + mass * g.dot(cc);
        };
        body_terms(m->root.mass, m->root.com, m->root.inertia, r, x, om, xd);
        const std::size_t nb = m->bodies.size();
        std::vector<m3> rot(nb);
        std::vector<v3> origin(nb), omega(nb), vel(nb);
        for (std::size_t i = 0; i < nb; ++i) {
            const auto& bd = m->bodies[i];
            const T th = q(7 + static_cast<int>(i)), thd = qd(7 + static_cast<int>(i));
            m3 rp = r;
            v3 pp = x, wp = om, vp = xd;
            if (bd.parent >= 0) {
                const auto p = static_cast<std::size_t>(bd.parent);
                rp = rot[p];
                pp = origin[p];
                wp = omega[p];
                vp = vel[p];
            }
            const m3 rj = rp * bd.placement.rotation.cast<T>();
            const v3 pj = rp * bd.placement.origin.cast<T>() + pp;
            const v3 ax = rj * bd.axis.cast<T>();
            const Eigen::Vector3d a0 = bd.axis;
            m3 k;
            k << T(0.0), T(-a0(2)), T(a0(1)), T(a0(2)), T(0.0), T(-a0(0)), T(-a0(1)), T(a0(0)),
                T(0.0);
            rot[i] = rj * (m3::Identity() * cos(th) + k * sin(th) +
                           (a0 * a0.transpose()).cast<T>() * (1.0 - cos(th)));
            omega[i] = wp + ax * thd;
            vel[i] = vp + cross(wp, pj - pp);
            origin[i] = pj;
            body_terms(bd.mass, bd.com, bd.inertia, rot[i], origin[i], omega[i], vel[i]);
        }
        const double kappa = 4.0 * std::max(m->root.inertia.trace() / 3.0, 1e-9 * m->root.mass);
        const T radial = q(3) * qd(3) + q(4) * qd(4) + q(5) * qd(5) + q(6) * qd(6);
        return l + 0.5 * kappa * radial * radial;
    }
};

/// A root link and three revolute joints (1 ← 0 → 2 ← …: a branch), random placements, axes,
/// masses and inertias (positive definite, triangle inequality).
multibody::tree random_arm(unsigned seed) {
    std::mt19937 g(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0), p(0.05, 1.0);
    auto inertia = [&] {
        const double a = p(g), b = p(g), c = p(g);
        const mat3 r = multibody::roll_pitch_yaw(vec3(3 * u(g), 3 * u(g), 3 * u(g)));
        return mat3(r * vec3(b + c, a + c, a + b).asDiagonal() * r.transpose());
    };
    multibody::tree m;
    m.root.link = m.root.name = "torso";
    m.root.mass = 3.0;
    m.root.com = vec3(u(g), u(g), u(g)) * 0.1;
    m.root.inertia = inertia();
    const int parents[] = {-1, 0, -1};
    for (int i = 0; i < 3; ++i) {
        multibody::body b;
        b.name = "j" + std::to_string(i);
        b.link = "l" + std::to_string(i);
        b.placement.rotation = multibody::roll_pitch_yaw(vec3(3 * u(g), 3 * u(g), 3 * u(g)));
        b.placement.origin = vec3(u(g), u(g), u(g)) * 0.5;
        b.axis = vec3(u(g), u(g), u(g)).normalized();
        b.mass = 1.0 + 0.5 * u(g);
        b.com = vec3(u(g), u(g), u(g)) * 0.3;
        b.inertia = inertia();
        m.add_body(parents[i], b);
    }
    m.gravity = vec3(0.0, 0.0, -9.81);
    return m;
}

template <class A, class B>
double gap(const A& a, const B& b) {
    return (a - b).cwiseAbs().maxCoeff() / std::max(1.0, b.cwiseAbs().maxCoeff());
}

// Both sides sum O(10²) products of O(1–10) numbers, this side's through the chart's maps and
// the chain rule, the reference's through the quaternion's rotation matrix (both normalise u):
// 1e-11 relative is round-off; a wrong term is O(1).
constexpr double chain_tolerance = 1e-11;

TEST(FloatingBase, DerivativesEqualAutomaticDifferentiationOfASecondImplementation) {
    const multibody::tree fixed = random_arm(3);
    const multibody::free_robot l(
        std::make_shared<const multibody::tree>(fixed.with_base(multibody::base_kind::free)));
    ASSERT_EQ(l.dimension(), 10);
    const reference_free<10> ref{&fixed};
    std::mt19937 g(5);
    std::uniform_real_distribution<double> u(-1.5, 1.5);
    for (int k = 0; k < 5; ++k) {
        vec<10> q, v;
        for (int i = 0; i < 10; ++i) {
            q(i) = u(g);
            v(i) = u(g);
        }
        q.segment<4>(3) *= (0.8 + 0.1 * k) / q.segment<4>(3).norm(); // off the unit sphere too
        lagrangian_terms<10> expected;
        evaluate(ref, q, v, expected);
        lagrangian_terms<dynamic> got;
        l.derivatives(q, v, got);
        EXPECT_NEAR(got.value, expected.value,
                    chain_tolerance * std::max(1.0, std::abs(expected.value)));
        EXPECT_LT(gap(got.lq, expected.lq), chain_tolerance) << "dL/dq at state " << k;
        EXPECT_LT(gap(got.lv, expected.lv), chain_tolerance) << "dL/dqdot at state " << k;
        EXPECT_LT(gap(got.lqq, expected.lqq), chain_tolerance) << "d2L/dq2 at state " << k;
        EXPECT_LT(gap(got.lqv, expected.lqv), chain_tolerance) << "d2L/dqdqdot at state " << k;
        EXPECT_LT(gap(got.lvv, expected.lvv), chain_tolerance) << "M at state " << k;
        lagrangian_terms<dynamic> first;
        l.gradient(q, v, first);
        EXPECT_LT(gap(first.lq, expected.lq), chain_tolerance);
        EXPECT_LT(gap(first.lv, expected.lv), chain_tolerance);
        EXPECT_NEAR(l(q, v), expected.value,
                    chain_tolerance * std::max(1.0, std::abs(expected.value)));
        // M(q) by the composite-rigid-body algorithm: L is quadratic in q̇, so ∂²L/∂q̇² at any q̇.
        mat<dynamic> mass;
        l.mass_matrix(q, mass);
        EXPECT_LT(gap(mass, expected.lvv), chain_tolerance) << "mass_matrix at state " << k;
        // b = (∂²L/∂q̇∂q) q̇ − ∂L/∂q by a Newton–Euler pass after it (floating_dynamics.hpp,
        // Q7): the chart's curvature and the radial term's κ|u̇|²u (u·u̇ ≠ 0 here) included.
        vec<dynamic> bias;
        l.bias_forces_after_mass_matrix(q, v, bias);
        const vec<10> want = expected.lqv.transpose() * v - expected.lq;
        EXPECT_LT(gap(bias, want), chain_tolerance) << "bias forces at state " << k;
    }
    // Negative control: the reference with the root's inertia changed by 1 % differs.
    multibody::tree changed = fixed;
    changed.root.inertia(0, 1) *= 1.01;
    changed.root.inertia(1, 0) *= 1.01;
    const reference_free<10> other{&changed};
    vec<10> q, v;
    q << 0.1, -0.2, 0.3, 0.9, 0.1, -0.3, 0.2, 0.5, -0.4, 0.7;
    v << 0.3, 0.1, -0.5, 0.2, 0.4, -0.6, 0.1, 1.0, -0.5, 0.8;
    lagrangian_terms<10> expected;
    evaluate(other, q, v, expected);
    lagrangian_terms<dynamic> got;
    l.derivatives(q, v, got);
    EXPECT_GT(gap(got.lvv, expected.lvv), 100 * chain_tolerance);
    mat<dynamic> mass;
    l.mass_matrix(q, mass);
    EXPECT_GT(gap(mass, expected.lvv), 100 * chain_tolerance);
    vec<dynamic> bias;
    l.bias_forces_after_mass_matrix(q, v, bias);
    EXPECT_GT(gap(bias, vec<10>(expected.lqv.transpose() * v - expected.lq)),
              100 * chain_tolerance);
}

using free_stepper =
    general::constrained_stepper<multibody::free_robot, multibody::unit_quaternion>;

/// A free rigid body (no joints): principal inertias (1, 2, 3) kg m², mass 2 kg.
std::shared_ptr<const multibody::tree> rigid_body(double gravity) {
    multibody::tree m;
    m.root.link = m.root.name = "body";
    m.root.mass = 2.0;
    m.root.inertia = vec3(1.0, 2.0, 3.0).asDiagonal();
    m.gravity = vec3(0.0, 0.0, -gravity);
    return std::make_shared<const multibody::tree>(m.with_base(multibody::base_kind::free));
}

/// The body rate ω(T) of the torque-free body from ω(0) = (w1, 0, w3), identity orientation,
/// by the constrained engine (gauss-2, order 4) at steps h.
vec3 body_rate_after(double w1, double w3, double t, double h) {
    const multibody::free_robot l(rigid_body(0.0));
    const lagrangian_system<multibody::free_robot> sys(l);
    vec<dynamic> q = vec<dynamic>::Zero(7), v = vec<dynamic>::Zero(7);
    q(3) = 1.0;
    v(4) = 0.5 * w1; // u̇ = ½ u ⊗ (0, ω)
    v(6) = 0.5 * w3;
    phase_state<dynamic> x{q, sys.momentum(q, v)};
    free_stepper s(sys, multibody::unit_quaternion{7}, h, {scheme_kind::gauss, 2});
    const auto steps = static_cast<std::size_t>(std::llround(t / h));
    for (std::size_t j = 0; j < steps; ++j)
        EXPECT_TRUE(s.step(x).converged) << "step " << j;
    const vec<dynamic> rate = sys.velocity(x.q, x.p);
    const Eigen::Vector4d u = x.q.segment<4>(3), ud = rate.segment<4>(3);
    return 2.0 * (u(0) * ud.tail<3>() - ud(0) * u.tail<3>() - u.tail<3>().cross(ud.tail<3>()));
}

TEST(FloatingBase, ATorqueFreeBodyFollowsJacobisEllipticSolution) {
    // Landau & Lifshitz, Mechanics, §37 (M² > 2E I₂, I₁ < I₂ < I₃), ω(0) = (w1, 0, w3):
    //   ω₁ = √((2EI₃ − M²)/(I₁(I₃ − I₁))) cn τ,  ω₂ = √((2EI₃ − M²)/(I₂(I₃ − I₂))) sn τ,
    //   ω₃ = √((M² − 2EI₁)/(I₃(I₃ − I₁))) dn τ,  τ = t √((I₃ − I₂)(M² − 2EI₁)/(I₁I₂I₃)),
    //   k² = (I₂ − I₁)(2EI₃ − M²)/((I₃ − I₂)(M² − 2EI₁)).
    const double i1 = 1.0, i2 = 2.0, i3 = 3.0, w1 = 1.0, w3 = 1.0, t = 10.0;
    const double e2 = i1 * w1 * w1 + i3 * w3 * w3, m2 = i1 * i1 * w1 * w1 + i3 * i3 * w3 * w3;
    ASSERT_GT(m2, e2 * i2);
    const double k = std::sqrt((i2 - i1) * (e2 * i3 - m2) / ((i3 - i2) * (m2 - e2 * i1)));
    const double tau = t * std::sqrt((i3 - i2) * (m2 - e2 * i1) / (i1 * i2 * i3));
    double cn = 0.0, dn = 0.0;
    const double sn = boost::math::jacobi_elliptic(k, tau, &cn, &dn);
    const vec3 exact(std::sqrt((e2 * i3 - m2) / (i1 * (i3 - i1))) * cn,
                     std::sqrt((e2 * i3 - m2) / (i2 * (i3 - i2))) * sn,
                     std::sqrt((m2 - e2 * i1) / (i3 * (i3 - i1))) * dn);
    const double coarse = (body_rate_after(w1, w3, t, 0.02) - exact).norm();
    const double fine = (body_rate_after(w1, w3, t, 0.01) - exact).norm();
    // Order 4: the error falls 16-fold when h halves (3.5 to 4.5 allows the next term); at
    // h = 0.01 over ~3 periods it is C h⁴ with C ~ 10 (measured 1.0e-9); not 0 by accident.
    const double order = std::log2(coarse / fine);
    EXPECT_GT(order, 3.5) << coarse << " " << fine;
    EXPECT_LT(order, 4.5) << coarse << " " << fine;
    EXPECT_LT(fine, 1e-8);
    EXPECT_GT(fine, 1e-13);
}

/// Steps the random floating arm with joint damping (internal forces) and gravity g for n steps
/// of h, recording the momenta (world; the angular one about the origin) at each step.
std::vector<multibody::base_motion> arm_momenta(double gravity, int n, double h,
                                                const newton_options& opt = {}) {
    multibody::tree fixed = random_arm(8);
    fixed.gravity = vec3(0.0, 0.0, -gravity);
    const auto tree =
        std::make_shared<const multibody::tree>(fixed.with_base(multibody::base_kind::free));
    const multibody::free_robot l(tree);
    const lagrangian_system<multibody::free_robot> sys(l);
    vec<dynamic> q = vec<dynamic>::Zero(10), v = vec<dynamic>::Zero(10);
    q.segment<4>(3) = Eigen::Vector4d(0.9, 0.1, -0.3, 0.2).normalized();
    const Eigen::Quaterniond uq(q(3), q(4), q(5), q(6)); // u̇ = ½ u ⊗ (0, ω)
    const Eigen::Quaterniond ud = uq * Eigen::Quaterniond(0.0, 0.2, -0.1, 0.35);
    v.segment<4>(3) = Eigen::Vector4d(ud.w(), ud.x(), ud.y(), ud.z());
    v.head<3>() = vec3(0.3, -0.1, 0.5);
    v.tail<3>() = vec3(1.0, -2.0, 1.5);
    phase_state<dynamic> x{q, sys.momentum(q, v)};
    vec<dynamic> damping = vec<dynamic>::Zero(10);
    damping.tail<3>() = vec3(0.5, 0.2, 0.3);
    general::constrained_stepper<multibody::free_robot, multibody::unit_quaternion,
                                 rayleigh_damping<dynamic>>
        s(sys, multibody::unit_quaternion{10}, rayleigh_damping<dynamic>::diagonal(damping), h,
          {scheme_kind::lobatto, 2}, opt);
    std::vector<multibody::base_motion> out{l.motion(x.q, v)};
    for (int j = 0; j < n; ++j) {
        EXPECT_TRUE(s.step(x).converged) << "step " << j;
        out.push_back(l.motion(x.q, sys.velocity(x.q, x.p)));
    }
    return out;
}

TEST(FloatingBase, InFreeFlightBothMomentaAreConservedToRoundOff) {
    // Noether: without gravity L is invariant under translations and rotations of the world,
    // which act linearly on (x, u); damping between the links is internal. |P| and |L| are
    // O(1–10); 2000 steps of round-off in momenta summed with compensation (measured 1e-15
    // relative): 1e-13.
    const auto m = arm_momenta(0.0, 2000, 1e-3);
    const double scale = std::max(m[0].momentum.norm(), m[0].angular_momentum.norm());
    double dp = 0.0, dl = 0.0;
    for (const auto& b : m) {
        dp = std::max(dp, (b.momentum - m[0].momentum).norm());
        dl = std::max(dl, (b.angular_momentum - m[0].angular_momentum).norm());
    }
    EXPECT_LT(dp, 1e-13 * scale);
    EXPECT_LT(dl, 1e-13 * scale);
    EXPECT_GT(scale, 0.1); // not conserved for being zero
}

TEST(FloatingBase, ChordUpdatesTakeTheStepsNewtonWithAFreshJacobianTakes) {
    // The default solve (chord updates once an update is below 1e-3 of the increments, the
    // momentum from the last iterate corrected to first order) against Newton with a fresh
    // Jacobian at every iterate (chord_start = 0): both converge to round-off of the same
    // equations, so 500 steps of O(1) states agree to round-off (measured 1.4e-14; 1e-12). At
    // h = 10 ms a step takes a second update, the chord's; at 1 ms the first lands within
    // round-off and the two runs are bit-identical, so the last check shows the chord was taken.
    newton_options fresh;
    fresh.chord_start = 0.0;
    const auto a = arm_momenta(9.81, 500, 1e-2), b = arm_momenta(9.81, 500, 1e-2, fresh);
    double gap = 0.0;
    for (std::size_t k = 0; k < a.size(); ++k)
        gap = std::max({gap, (a[k].centre_of_mass - b[k].centre_of_mass).norm(),
                        a[k].orientation.angularDistance(b[k].orientation),
                        (a[k].angular_velocity - b[k].angular_velocity).norm()});
    EXPECT_LT(gap, 1e-12);
    EXPECT_GT(gap, 0.0);
    EXPECT_GT((a.back().centre_of_mass - a.front().centre_of_mass).norm(), 1.0); // it fell
}

TEST(FloatingBase, UnderGravityTheVerticalMomentumFallsByMgtAndItsAngularMomentumStays) {
    // With gravity g along −z: dP/dt = −M g e_z exactly (L depends on z linearly), and the
    // angular momentum about the vertical through the origin is conserved; about x it is not
    // (the negative control: the check above can fail).
    const double g = 9.81, h = 1e-3;
    const int n = 1000;
    const auto m = arm_momenta(g, n, h);
    const double mass = 3.0 + random_arm(8).bodies[0].mass + random_arm(8).bodies[1].mass +
                        random_arm(8).bodies[2].mass;
    const vec3 expected = m[0].momentum - vec3(0.0, 0.0, mass * g * n * h);
    EXPECT_LT((m.back().momentum - expected).norm(), 1e-11 * mass * g * n * h);
    EXPECT_LT(std::abs(m.back().angular_momentum(2) - m[0].angular_momentum(2)), 1e-11);
    EXPECT_GT(std::abs(m.back().angular_momentum(0) - m[0].angular_momentum(0)), 1e-3);
}

TEST(FloatingBase, AtRestTheSolveStopsAtTheResidualsRoundOff) {
    // The damped floating arm at rest without gravity: every term of the saddle-point residual
    // is zero, so the stop (constrained.hpp, at_round_off) takes each step without an update
    // (measured: none in 1000 steps; one a step before that stop), and the arm stays at rest:
    // |p| and the move of q within 1e-15. A smoke test of the constrained stepper's stop: it
    // fails without the stop by its update count only (λ stays 0 here).
    multibody::tree fixed = random_arm(8);
    fixed.gravity.setZero();
    const multibody::free_robot l(
        std::make_shared<const multibody::tree>(fixed.with_base(multibody::base_kind::free)));
    const lagrangian_system<multibody::free_robot> sys(l);
    phase_state<dynamic> x{vec<dynamic>::Zero(10), vec<dynamic>::Zero(10)};
    x.q.segment<4>(3) = Eigen::Vector4d(0.9, 0.1, -0.3, 0.2).normalized();
    x.q.tail<3>() = vec3(0.4, -0.7, 1.1);
    const vec<dynamic> start = x.q;
    vec<dynamic> damping = vec<dynamic>::Zero(10);
    damping.tail<3>() = vec3(0.5, 0.2, 0.3);
    general::constrained_stepper<multibody::free_robot, multibody::unit_quaternion,
                                 rayleigh_damping<dynamic>>
        s(sys, multibody::unit_quaternion{10}, rayleigh_damping<dynamic>::diagonal(damping), 1e-3,
          {scheme_kind::lobatto, 2});
    const int steps = 1000;
    long updates = 0;
    for (int j = 0; j < steps; ++j) {
        const newton_report rep = s.step(x);
        ASSERT_TRUE(rep.converged) << "step " << j;
        updates += rep.iterations;
    }
    EXPECT_LT(updates, steps);
    EXPECT_LE(x.p.lpNorm<Eigen::Infinity>(), 1e-15);
    EXPECT_LE((x.q - start).lpNorm<Eigen::Infinity>(), 1e-15);
}

TEST(FloatingBase, AnArmTurnsItsBaseByTheAngleZeroAngularMomentumPrescribes) {
    // A base (mass 3 kg, I_z = 0.4 kg m², centre at its origin) and a link on a revolute joint
    // about z at a = 0.5 m along x (mass 1 kg, centre b = 0.3 m along its x, I_z = 0.05): in
    // free flight from rest, driven by a joint torque, the motion stays in the x–y plane and
    // zero angular momentum, I(φ) θ̇ + K(φ) φ̇ = 0 with μ = m₁m₂/(m₁ + m₂),
    //   I(φ) = I₁ + I₂ + μ(a² + b² + 2ab cos φ),  K(φ) = I₂ + μ(b² + ab cos φ),
    // turns the base by θ(T) = −∫₀^φ(T) K/I dφ, whatever the torque's history.
    const double m1 = 3.0, m2 = 1.0, i1 = 0.4, i2 = 0.05, a = 0.5, b = 0.3;
    multibody::tree fixed;
    fixed.root.link = fixed.root.name = "base";
    fixed.root.mass = m1;
    fixed.root.inertia = vec3(0.3, 0.35, i1).asDiagonal();
    multibody::body link;
    link.name = "elbow";
    link.link = "arm";
    link.placement.origin = vec3(a, 0.0, 0.0);
    link.mass = m2;
    link.com = vec3(b, 0.0, 0.0);
    link.inertia = vec3(0.01, 0.04, i2).asDiagonal();
    fixed.add_body(-1, link);
    fixed.gravity.setZero();
    const multibody::free_robot l(
        std::make_shared<const multibody::tree>(fixed.with_base(multibody::base_kind::free)));
    const lagrangian_system<multibody::free_robot> sys(l);
    vec<dynamic> q = vec<dynamic>::Zero(8);
    q(3) = 1.0;
    phase_state<dynamic> x{q, vec<dynamic>::Zero(8)};
    const expression_force torque({"0", "0", "0", "0", "0", "0", "0", "0.3*cos(2*t)"},
                                  {"x", "y", "z", "qw", "qx", "qy", "qz", "elbow"}, {});
    general::constrained_stepper<multibody::free_robot, multibody::unit_quaternion,
                                 expression_force>
        s(sys, multibody::unit_quaternion{8}, torque, 1e-3, {scheme_kind::gauss, 2});
    for (int j = 0; j < 3000; ++j) {
        s.set_time(j * 1e-3);
        ASSERT_TRUE(s.step(x).converged) << "step " << j;
    }
    const double phi = x.q(7);
    const double theta = 2.0 * std::atan2(x.q(6), x.q(3));
    EXPECT_LT(std::abs(x.q(4)) + std::abs(x.q(5)), 1e-12); // no turn about x or y
    const double mu = m1 * m2 / (m1 + m2);
    auto ratio = [&](double f) {
        return (i2 + mu * (b * b + a * b * std::cos(f))) /
               (i1 + i2 + mu * (a * a + b * b + 2.0 * a * b * std::cos(f)));
    };
    const int k = 2000; // composite Simpson: error ~ (φ/k)⁴, far below the tolerance
    double integral = ratio(0.0) + ratio(phi);
    for (int i = 1; i < k; ++i)
        integral += (i % 2 ? 4.0 : 2.0) * ratio(phi * i / k);
    integral *= phi / (3.0 * k);
    EXPECT_GT(std::abs(phi), 0.5); // the arm moved
    // The discrete angular momentum stays 0, so each step's turn is a Gauss quadrature of the
    // integral along the step's polynomial: an O(h⁴) error, at h = 1e-3 far below the tolerance
    // (measured 2e-15).
    EXPECT_NEAR(theta, -integral, 1e-11) << "phi = " << phi;
}

} // namespace floating_test
