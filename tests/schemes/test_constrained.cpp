// tests/schemes/test_constrained.cpp: holonomic constraints in the general engine
// (schemes/constrained.hpp, systems/constraints.hpp).
// References:
//  - the planar pendulum in Cartesian coordinates, |x| = ℓ, against its exact solution by Jacobi
//    elliptic functions (problems/pendulum.hpp, tested in test_pendulum_exact.cpp): the orders
//    observed for each member are measured and held;
//  - the spherical pendulum in Cartesian coordinates against the same pendulum in angles (θ, φ),
//    run by the unconstrained engine at gauss-4 with a 16× smaller step;
//  - conservation laws: the constraint and its hidden (velocity) constraint at every step, the
//    energy, and the angular momentum about the vertical (a symmetry of L and g).
#include <gtest/gtest.h>

#include <cmath>

#include "test_support.hpp"
#include "varsym/integrate.hpp"
#include "varsym/problems/pendulum.hpp"
#include "varsym/schemes/constrained.hpp"

using namespace varsym;

using test::member;

namespace {

// A point mass m on a rod of length ℓ, in Cartesian coordinates of dimension D (2: planar, 3:
// spherical), gravity g along −e_{D−1}.
template <int D>
struct point_mass {
    static constexpr int dim = D;
    double m = 1.0, g = 1.0;
    template <class T>
    T operator()(const tvec<T, D>& q, const tvec<T, D>& v) const {
        return (0.5 * m) * v.squaredNorm() - (m * g) * q(D - 1);
    }
};
template <int D>
struct rod {
    static constexpr int dim = D, count = 1;
    double length = 1.0;
    template <class T>
    tvec<T, 1> operator()(const tvec<T, D>& q) const {
        return tvec<T, 1>(q.squaredNorm() - length * length);
    }
};

using planar = general::constrained_stepper<point_mass<2>, rod<2>>;

/// The planar pendulum at angle θ with angular velocity ω in Cartesian coordinates (m = ℓ = 1).
phase_state<2> planar_state(double theta, double omega) {
    return {vec<2>{std::sin(theta), -std::cos(theta)},
            vec<2>{omega * std::cos(theta), omega * std::sin(theta)}};
}

struct run_result {
    double error = 0.0, residual = 0.0, hidden = 0.0, energy = 0.0;
};

/// n steps of the planar pendulum (g = ℓ = m = 1, so ω = 1) from θ = 2, at rest, to t = 5.
run_result planar_run(scheme_spec spec, int n) {
    const double t_end = 5.0, theta0 = 2.0;
    const lagrangian_system<point_mass<2>> sys({});
    planar st(sys, {}, t_end / n, spec);
    phase_state<2> x = planar_state(theta0, 0.0);
    st.check_initial(x);
    const double e0 = sys.energy(x);
    run_result r;
    integrate(st, x, 0.0, static_cast<std::size_t>(n), [&](auto, auto, const phase_state<2>& y) {
        r.residual = std::max(r.residual, st.residual(y.q));
        r.hidden = std::max(r.hidden, st.hidden_residual(y));
        r.energy = std::max(r.energy, std::abs(sys.energy(y) - e0));
    });
    const pendulum::exact_solution exact(1.0, 1.0, theta0, 0.0);
    const auto ref = exact.state(t_end);
    const phase_state<2> want = planar_state(ref.q, ref.p);
    r.error = std::max((x.q - want.q).lpNorm<Eigen::Infinity>(),
                       (x.p - want.p).lpNorm<Eigen::Infinity>());
    return r;
}

// The rod constraint twice (the second row is twice the first): redundant.
struct twice {
    static constexpr int dim = 2, count = 2;
    template <class T>
    tvec<T, 2> operator()(const tvec<T, 2>& q) const {
        const T g = q.squaredNorm() - 1.0;
        return tvec<T, 2>(g, 2.0 * g);
    }
};

} // namespace

TEST(Constrained, PlanarPendulumKeepsItsConstraintsAndConvergesToTheExactSolution) {
    // Orders measured between n = 100 and 200 steps to t = 5 (h = 0.05, 0.025): the
    // unconstrained orders 2, 4, 2s for every member measured here.
    for (const member& m : test::five_members) {
        const run_result coarse = planar_run(m.spec, 100), fine = planar_run(m.spec, 200);
        const double observed = std::log2(coarse.error / fine.error);
        SCOPED_TRACE(m.spec.label() + ": errors " + test::sci(coarse.error) + ", " +
                     test::sci(fine.error));
        EXPECT_NEAR(observed, m.order, 0.2);
        // ℓ² = 1 is the constraint's scale; the hidden constraint's is |x| |v| ≈ 1.4.
        EXPECT_LE(std::max(coarse.residual, fine.residual), 1e-13);
        EXPECT_LE(std::max(coarse.hidden, fine.hidden), 1e-13);
        RecordProperty("order_" + m.spec.label(), test::sci(observed));
        RecordProperty("constraint_residual_" + m.spec.label(), test::sci(fine.residual));
        RecordProperty("hidden_residual_" + m.spec.label(), test::sci(fine.hidden));
        RecordProperty("energy_error_" + m.spec.label(), test::sci(fine.energy));
    }
}

TEST(Constrained, InitialDataOffTheConstraintsIsRefusedOrProjected) {
    const lagrangian_system<point_mass<2>> sys({});
    const planar st(sys, {}, 0.01, scheme_kind::simpson);
    phase_state<2> x = planar_state(0.5, 1.0);
    x.q *= 1.001; // off |x| = 1
    try {
        st.check_initial(x);
        ADD_FAILURE() << "an off-manifold position was accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("off the constraints: max |g(q0)| = 0.002"),
                  std::string::npos)
            << e.what();
    }
    phase_state<2> y = planar_state(0.5, 1.0);
    y.p += vec<2>{0.1, 0.1}; // not tangent
    EXPECT_THROW(st.check_initial(y), std::invalid_argument);
    const phase_state<2> on = st.project(x), tangent = st.project(y);
    EXPECT_LE(st.residual(on.q), 1e-15);
    EXPECT_LE(st.hidden_residual(on), 1e-15);
    EXPECT_LE(st.hidden_residual(tangent), 1e-15);
    EXPECT_NO_THROW(st.check_initial(on));
    // the projection of the momentum removes only its normal part: the tangential one stays
    EXPECT_NEAR(tangent.p.dot(vec<2>{std::cos(0.5), std::sin(0.5)}),
                1.0 + 0.1 * (std::cos(0.5) + std::sin(0.5)), 1e-15);
}

TEST(Constrained, RedundantConstraintsAreRefusedNamingTheRow) {
    vec<2> g;
    constraint_jacobian<2, 2> jac;
    evaluate_constraint(twice{}, planar_state(0.3, 0.0).q, g, jac);
    try {
        check_independent<2, 2>(jac, "at the initial state"); // as check_initial does
        ADD_FAILURE() << "dependent constraints were accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("row(s) 2 "), std::string::npos) << e.what();
    }
}

namespace {

// The spherical pendulum (m = ℓ = 1, g = 1) with an anharmonic term κ x⁴/4 in its potential
// (κ = 0: the symmetric pendulum): in Cartesian coordinates with |x| = 1, and in the angles
// (θ from the downward vertical, φ the azimuth), x = (sin θ cos φ, sin θ sin φ, −cos θ).
struct spherical_cartesian {
    static constexpr int dim = 3;
    double kappa = 0.0;
    template <class T>
    T operator()(const tvec<T, 3>& q, const tvec<T, 3>& v) const {
        const T x2 = q(0) * q(0);
        return 0.5 * v.squaredNorm() - q(2) - (0.25 * kappa) * x2 * x2;
    }
};
struct spherical_angles {
    static constexpr int dim = 2;
    double kappa = 0.0;
    template <class T>
    T operator()(const tvec<T, 2>& q, const tvec<T, 2>& v) const {
        using std::cos, std::sin;
        const T s = sin(q(0)), x = s * cos(q(1)), x2 = x * x;
        return 0.5 * (v(0) * v(0) + s * s * v(1) * v(1)) + cos(q(0)) - (0.25 * kappa) * x2 * x2;
    }
};

/// (θ, φ, θ', φ') to Cartesian (x, p = ẋ).
phase_state<3> to_cartesian(const vec<2>& a, const vec<2>& rate) {
    const double st = std::sin(a(0)), ct = std::cos(a(0)), sp = std::sin(a(1)), cp = std::cos(a(1));
    return {vec<3>{st * cp, st * sp, -ct},
            vec<3>{ct * cp * rate(0) - st * sp * rate(1), ct * sp * rate(0) + st * cp * rate(1),
                   st * rate(0)}};
}

const vec<2> angle0{1.0, 0.0}, rate0{0.0, 1.2};

/// The Cartesian state at t = 3 from the angles' reference run (gauss-4, h = 3/2000).
phase_state<3> spherical_reference(double kappa) {
    const lagrangian_system<spherical_angles> sys({kappa});
    general::stepper<spherical_angles> st(sys, 3.0 / 2000, {scheme_kind::gauss, 4});
    phase_state<2> x{angle0, sys.momentum(angle0, rate0)};
    integrate(st, x, 0.0, 2000, [](auto, auto, const auto&) {});
    return to_cartesian(x.q, sys.velocity(x.q, x.p));
}

/// Error at t = 3 after n Cartesian steps; `lz` gets the worst drift of x p_y − y p_x.
double spherical_error(double kappa, scheme_spec spec, int n, const phase_state<3>& ref,
                       double* lz = nullptr) {
    using stepper_type = general::constrained_stepper<spherical_cartesian, rod<3>>;
    stepper_type st(lagrangian_system<spherical_cartesian>({kappa}), {}, 3.0 / n, spec);
    phase_state<3> x = to_cartesian(angle0, rate0);
    st.check_initial(x);
    auto spin = [](const phase_state<3>& y) { return y.q(0) * y.p(1) - y.q(1) * y.p(0); };
    const double l0 = spin(x);
    double drift = 0.0;
    integrate(st, x, 0.0, static_cast<std::size_t>(n), [&](auto, auto, const phase_state<3>& y) {
        drift = std::max(drift, std::abs(spin(y) - l0));
        EXPECT_LE(st.residual(y.q), 1e-13);
        EXPECT_LE(st.hidden_residual(y), 1e-13);
    });
    if (lz) *lz = drift;
    return std::max((x.q - ref.q).lpNorm<Eigen::Infinity>(),
                    (x.p - ref.p).lpNorm<Eigen::Infinity>());
}

} // namespace

TEST(Constrained, SphericalPendulumMatchesTheAnglesAndConservesItsSpin) {
    const phase_state<3> ref = spherical_reference(0.0);
    double lz = 0.0;
    const double err = spherical_error(0.0, scheme_kind::simpson, 300, ref, &lz);
    EXPECT_LE(err, 1e-9); // Simpson, h = 0.01: measured 7.9e-11 (C h⁴, orders held below)
    EXPECT_LE(lz, 1e-14); // the rotations about the vertical leave L and g invariant
    RecordProperty("simpson_error_h0.01", test::sci(err));
    RecordProperty("spin_drift", test::sci(lz));
}

TEST(Constrained, OrdersWhereTheQuadratureIsNotExact) {
    // With κ x⁴/4 the action's integrand is not a polynomial the rules integrate exactly, so
    // Gauss and Lobatto members differ; orders measured between h = 0.05 and 0.025.
    const double kappa = 2.0;
    const phase_state<3> ref = spherical_reference(kappa);
    for (const member& m : test::five_members) {
        const double coarse = spherical_error(kappa, m.spec, 60, ref),
                     fine = spherical_error(kappa, m.spec, 120, ref);
        const double observed = std::log2(coarse / fine);
        SCOPED_TRACE(m.spec.label() + ": errors " + test::sci(coarse) + ", " + test::sci(fine));
        EXPECT_NEAR(observed, m.order, 0.25);
        RecordProperty("order_anharmonic_" + m.spec.label(), test::sci(observed));
    }
}

TEST(Constrained, AStepStartedNearTheLastEndsWhereAFreshStepEnds) {
    // start_next_near (the contact step's retakes): from the same q_j with p_j changed by dp, the
    // step starts from the last one's increments and multipliers moved to first order and
    // iterates by chord updates on the kept LU. It solves the same equations as a fresh stepper's
    // step from (q_j, p_j + dp), so it must end there to round-off (1e-13 of |q| = 1; measured
    // below 1e-15). An unchanged momentum takes no update; a change of 0.1 (against |p| near 1),
    // far outside the linear start's reach, still ends there. The quartic term (κ = 2) makes
    // L_qq, and so the saddle-point matrix, change along the step.
    using stepper_type = general::constrained_stepper<spherical_cartesian, rod<3>>;
    const lagrangian_system<spherical_cartesian> sys({2.0});
    auto make = [&] { return stepper_type(sys, {}, 0.05, {scheme_kind::gauss, 2}); };
    const phase_state<3> x = to_cartesian(vec<2>{1.0, 0.3}, vec<2>{0.4, 1.2});
    for (const double size : {0.0, 1e-10, 1e-6, 1e-3, 1e-1}) {
        SCOPED_TRACE("|dp| = " + test::sci(size));
        stepper_type st = make();
        phase_state<3> y = x;
        ASSERT_TRUE(st.step(y).converged);
        const vec<3> dp = size * vec<3>(0.3, -0.5, 0.2);
        st.start_next_near(dp);
        st.set_time(0.0);
        phase_state<3> a{x.q, x.p + dp}, b{x.q, x.p + dp};
        const newton_report near = st.step(a);
        stepper_type fresh = make();
        ASSERT_TRUE(near.converged);
        const newton_report plain = fresh.step(b);
        ASSERT_TRUE(plain.converged);
        EXPECT_LE((a.q - b.q).lpNorm<Eigen::Infinity>(), 1e-13);
        EXPECT_LE((a.p - b.p).lpNorm<Eigen::Infinity>(), 1e-13);
        // Near the last step's answer the chord updates take fewer solves than the fresh step's
        // Newton (measured 0, 0, 1 and 2 against 3 at |dp| = 0, 1e-10, 1e-6, 1e-3). At 1e-10 the
        // start, within O(|dp|²) of the answer, is it to round-off: no update. From the last
        // answer unmoved, or moved with the wrong sign, one update is needed there and two at
        // 1e-6 with the wrong sign (both measured).
        if (size <= 1e-10) {
            EXPECT_EQ(near.iterations, 0);
        }
        if (size == 1e-6) {
            EXPECT_LE(near.iterations, 1);
        }
        if (size <= 1e-3) {
            EXPECT_LT(near.iterations, plain.iterations);
        }
    }
}

TEST(Constrained, TheKeptSensitivityComesFromTheLastFactorisedMatrix) {
    // kept_position_sensitivity (the contact step's warm start): ∂q_{j+1}/∂p_j from the
    // saddle-point matrix of the step's last Newton iterate, without second derivatives at the
    // converged point. Against position_sensitivity (tested against finite differences below).
    // The predictor leaves out the rod's tension T (about 1.5 here): its first update is about
    // h T / (2|q̇|) of the increments. At h = 0.05 and 0.005 that is above chord_start (1e-3),
    // so Newton iterates again with Λ ≠ 0 and the kept matrix is within the square of that of
    // the converged one (measured 4.5e-7 and 4.6e-11 of |S|: bound 1e-3 h²). At h = 1e-4 chord
    // updates follow at once and the kept matrix is the predictor's, Λ = 0: it lacks the
    // curvature term H = 2Λ I, Λ ≈ h T, which moves S by at most about h² T of itself (measured
    // 1.5e-9; bound h²).
    // After position_sensitivity has factorised the converged matrix, the kept block is the
    // same solve: equal to round-off. The quartic term (κ = 2) makes the matrix change along the
    // step.
    using stepper_type = general::constrained_stepper<spherical_cartesian, rod<3>>;
    const lagrangian_system<spherical_cartesian> sys({2.0});
    const phase_state<3> x = to_cartesian(vec<2>{1.0, 0.3}, vec<2>{0.4, 1.2});
    for (const double h : {0.05, 0.005, 1e-4}) {
        SCOPED_TRACE("h = " + test::sci(h));
        stepper_type st(sys, {}, h, {scheme_kind::gauss, 2});
        phase_state<3> y = x;
        ASSERT_TRUE(st.step(y).converged);
        Eigen::MatrixXd kept, exact, again;
        st.kept_position_sensitivity(kept);
        st.position_sensitivity(x, exact);
        st.kept_position_sensitivity(again);
        ASSERT_EQ(kept.rows(), 3);
        ASSERT_EQ(kept.cols(), 3);
        const double scale = exact.lpNorm<Eigen::Infinity>(),
                     off = (kept - exact).lpNorm<Eigen::Infinity>() / scale;
        RecordProperty("kept_sensitivity_off_h" + test::sci(h), test::sci(off));
        EXPECT_LE(off, h > 1e-3 ? 1e-3 * h * h : h * h);
        EXPECT_GT(off, 1e-13); // not the converged matrix
        EXPECT_LE((again - exact).lpNorm<Eigen::Infinity>(), 1e-14 * scale);
    }
}

TEST(Constrained, AStepReusingTheLastMatrixEndsWhereAFreshStepEnds) {
    // reuse_next() (the contact step's warm take): the next step iterates by chord updates on
    // the LU of the matrix an earlier step assembled. The same equations to the same tolerance,
    // so against a twin stepper without it: the same end over five steps to about the Newton
    // tolerance (measured 2.8e-16; bound 1e-10). It iterated on the kept matrix alone (a no-op
    // reuse_next() fails here, mutation-checked): the kept S is the same solve as before the
    // steps, bit for bit, where the twin's (a matrix at its new iterates) moved (the negative
    // control, > 1e-12).
    using stepper_type = general::constrained_stepper<spherical_cartesian, rod<3>>;
    const lagrangian_system<spherical_cartesian> sys({2.0});
    const phase_state<3> x = to_cartesian(vec<2>{1.0, 0.3}, vec<2>{0.4, 1.2});
    stepper_type reused(sys, {}, 1e-3, {scheme_kind::gauss, 2}),
        fresh(sys, {}, 1e-3, {scheme_kind::gauss, 2});
    phase_state<3> a = x, b = x;
    ASSERT_TRUE(reused.step(a).converged && fresh.step(b).converged);
    Eigen::MatrixXd before, after, twin_before, twin_after;
    reused.kept_position_sensitivity(before);
    fresh.kept_position_sensitivity(twin_before);
    for (int j = 0; j < 5; ++j) {
        reused.reuse_next();
        ASSERT_TRUE(reused.step(a).converged && fresh.step(b).converged);
    }
    const double off =
        std::max((a.q - b.q).lpNorm<Eigen::Infinity>(), (a.p - b.p).lpNorm<Eigen::Infinity>());
    RecordProperty("reused_step_off", test::sci(off));
    EXPECT_LE(off, 1e-10);
    reused.kept_position_sensitivity(after);
    fresh.kept_position_sensitivity(twin_after);
    EXPECT_EQ(after, before);
    EXPECT_GT((twin_after - twin_before).lpNorm<Eigen::Infinity>(), 1e-12);
}

TEST(Constrained, StepJacobianMatchesFiniteDifferencesAndIsSymplecticOnTheManifold) {
    // The spherical pendulum, gauss-2, h = 0.05. Central differences of the step map (which is
    // defined off the manifold too) with ε = 1e-5 check the Jacobian to ~1e-9. Symplecticity
    // holds for vectors tangent to T*M: a basis of the kernel of the linearized constraints
    // g(q) = 0 and G(q) q̇(q, p) = 0 (here q̇ = p). Negative control: on all of R⁶ it fails.
    using stepper_type = general::constrained_stepper<spherical_cartesian, rod<3>>;
    const lagrangian_system<spherical_cartesian> sys({0.0});
    newton_options opt;
    auto make = [&] { return stepper_type(sys, {}, 0.05, {scheme_kind::gauss, 2}, opt); };
    const phase_state<3> x = to_cartesian(vec<2>{1.0, 0.3}, vec<2>{0.4, 1.2});
    stepper_type st = make();
    phase_state<3> y = x;
    ASSERT_TRUE(st.step(y).converged);
    Eigen::MatrixXd j;
    st.step_jacobian(x, j);
    Eigen::MatrixXd fd(6, 6);
    for (int c = 0; c < 6; ++c) {
        phase_state<3> plus = x, minus = x;
        (c < 3 ? plus.q(c) : plus.p(c - 3)) += 1e-5;
        (c < 3 ? minus.q(c) : minus.p(c - 3)) -= 1e-5;
        stepper_type a = make(), b = make();
        ASSERT_TRUE(a.step(plus).converged && b.step(minus).converged);
        fd.col(c) << (plus.q - minus.q) / 2e-5, (plus.p - minus.p) / 2e-5;
    }
    EXPECT_LE((j - fd).lpNorm<Eigen::Infinity>(), 1e-8 * fd.lpNorm<Eigen::Infinity>());
    RecordProperty("jacobian_vs_fd_constrained", test::sci((j - fd).lpNorm<Eigen::Infinity>()));
    // The block ∂q_{j+1}/∂p_j alone (the contact step's linearisation), without the projection,
    // taken straight after a step as the contact step takes it: against the differences relative
    // to the block, and to the whole map's block (the same factors: equal to round-off).
    stepper_type again = make();
    phase_state<3> z = x;
    ASSERT_TRUE(again.step(z).converged);
    Eigen::MatrixXd sq;
    again.position_sensitivity(x, sq);
    ASSERT_EQ(sq.rows(), 3);
    ASSERT_EQ(sq.cols(), 3);
    const Eigen::MatrixXd fd_block = fd.block(0, 3, 3, 3);
    EXPECT_LE((sq - fd_block).lpNorm<Eigen::Infinity>(), 1e-7 * fd_block.lpNorm<Eigen::Infinity>());
    EXPECT_LE((sq - j.block(0, 3, 3, 3)).lpNorm<Eigen::Infinity>(),
              1e-14 * fd_block.lpNorm<Eigen::Infinity>());
    RecordProperty(
        "position_sensitivity_vs_fd",
        test::sci((sq - fd_block).lpNorm<Eigen::Infinity>() / fd_block.lpNorm<Eigen::Infinity>()));
    // Tangent vectors at x: 2 q·δq = 0 and δ(q·p) = p·δq + q·δp = 0.
    Eigen::MatrixXd c(2, 6);
    c << 2 * x.q.transpose(), Eigen::RowVector3d::Zero(), x.p.transpose(), x.q.transpose();
    const Eigen::MatrixXd basis = c.fullPivLu().kernel(); // 6 × 4
    ASSERT_EQ(basis.cols(), 4);
    Eigen::MatrixXd omega = Eigen::MatrixXd::Zero(6, 6);
    omega.topRightCorner(3, 3).setIdentity();
    omega.bottomLeftCorner(3, 3) = -Eigen::Matrix3d::Identity();
    const double on =
        (basis.transpose() * (j.transpose() * omega * j - omega) * basis).lpNorm<Eigen::Infinity>();
    const double off = (j.transpose() * omega * j - omega).lpNorm<Eigen::Infinity>();
    EXPECT_LE(on, 1e-12);
    EXPECT_GT(off, 1e-3);
    RecordProperty("symplectic_defect_on_manifold", test::sci(on));
    RecordProperty("symplectic_defect_off_manifold", test::sci(off));
}
