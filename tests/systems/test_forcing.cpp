// tests/systems/test_forcing.cpp: forces by the discrete Lagrange–d'Alembert principle in the
// general engine (systems/forcing.hpp, schemes/variational.hpp).
// References:
//  - the conservative engine: with a force that is identically zero the steps are the same bits;
//  - the damped, driven oscillator m q'' + c q' + k q = F cos(Ωt), solved exactly (a homogeneous
//    part e^{−γt}(A cos ω_d t + B sin ω_d t) and the steady state Re(F e^{iΩt}/(k − mΩ² + icΩ))):
//    the observed orders must be the conservative ones, 2 (Newmark), 4 (Simpson), 2s (the family);
//  - the energy balance E_N − E_0 = ∫ f·q̇ dt, with the work summed step by step (last_work);
//  - Noether with forcing: a force with no torque leaves angular momentum conserved.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>

#include "test_support.hpp"
#include "varsym/problems/double_pendulum.hpp"
#include "varsym/problems/kepler.hpp"
#include "varsym/run/state.hpp"
#include "varsym/schemes/variational.hpp"
#include "varsym/systems/forcing.hpp"

using namespace varsym;

using test::member;

namespace {

struct spring {
    static constexpr int dim = 1;
    double m = 1.0, k = 4.0;
    template <class T>
    T operator()(const tvec<T, 1>& q, const tvec<T, 1>& v) const {
        return (0.5 * m) * v(0) * v(0) - (0.5 * k) * q(0) * q(0);
    }
};

// Damping and a drive written once for automatic derivatives.
struct damped_drive {
    static constexpr int dim = 1;
    double c = 0.3, f = 0.8, omega = 1.3;
    template <class T>
    tvec<T, 1> operator()(const tvec<T, 1>&, const tvec<T, 1>& v, double t) const {
        tvec<T, 1> out;
        out(0) = -c * v(0) + f * std::cos(omega * t);
        return out;
    }
};

// The same force from the built-in pieces, with derivatives by hand.
using built_in = force_sum<rayleigh_damping<1>, prescribed_force<1>>;
built_in built_in_drive(const damped_drive& d) {
    return built_in(rayleigh_damping<1>::diagonal(vec<1>{d.c}), prescribed_force<1>{[d](double t) {
                        return vec<1>{d.f * std::cos(d.omega * t)};
                    }});
}

/// The exact (q, p) at time t from (q0, v0) at 0.
phase_state<1> exact(const spring& s, const damped_drive& d, double q0, double v0, double t) {
    using C = std::complex<double>;
    const C z = d.f / C(s.k - s.m * d.omega * d.omega, d.c * d.omega);
    auto steady = [&](double u) { return z * std::exp(C(0.0, d.omega * u)); };
    const double gamma = d.c / (2 * s.m), wd = std::sqrt(s.k / s.m - gamma * gamma);
    const double a = q0 - steady(0.0).real();
    const double b = (v0 - (C(0.0, d.omega) * steady(0.0)).real() + gamma * a) / wd;
    const double e = std::exp(-gamma * t), c = std::cos(wd * t), sn = std::sin(wd * t);
    const double q = e * (a * c + b * sn) + steady(t).real();
    const double v = e * (-gamma * (a * c + b * sn) + wd * (-a * sn + b * c)) +
                     (C(0.0, d.omega) * steady(t)).real();
    return {vec<1>{q}, vec<1>{s.m * v}};
}

/// max(|q − q_exact|, |p − p_exact|) at t = T after n steps.
double oscillator_error(scheme_spec spec, int n) {
    const spring s;
    const damped_drive d;
    const double t_end = 10.0, q0 = 1.0, v0 = 0.0;
    general::stepper<spring, damped_drive> st(lagrangian_system<spring>(s), d, t_end / n, spec);
    phase_state<1> x{vec<1>{q0}, vec<1>{s.m * v0}};
    integrate(st, x, 0.0, static_cast<std::size_t>(n), [](auto, auto, const auto&) {});
    const phase_state<1> ref = exact(s, d, q0, v0, t_end);
    return std::max(std::abs(x.q(0) - ref.q(0)), std::abs(x.p(0) - ref.p(0)));
}

// Kepler with a force that is zero, a radial drag (no torque) or a linear drag (a torque).
struct kepler_drag {
    static constexpr int dim = 2;
    enum kind { zero, radial, linear } mode = zero;
    double c = 0.005;
    template <class T>
    tvec<T, 2> operator()(const tvec<T, 2>& q, const tvec<T, 2>& v, double) const {
        if (mode == zero) return tvec<T, 2>(T(0.0), T(0.0));
        if (mode == linear) return tvec<T, 2>(-c * v(0), -c * v(1));
        const T along = -c * q.dot(v) / q.squaredNorm();
        return tvec<T, 2>(along * q(0), along * q(1));
    }
};

} // namespace

TEST(Forcing, ExactSolutionOfTheDampedDrivenOscillatorIsSane) {
    // The reference itself: it starts where asked and satisfies the equation (differences).
    const spring s;
    const damped_drive d;
    EXPECT_NEAR(exact(s, d, 1.0, 0.0, 0.0).q(0), 1.0, 1e-15);
    EXPECT_NEAR(exact(s, d, 1.0, 0.0, 0.0).p(0), 0.0, 1e-15);
    const double t = 2.7, e = 1e-4;
    auto v = [&](double u) { return exact(s, d, 1.0, 0.0, u).p(0) / s.m; };
    const double acc = (v(t + e) - v(t - e)) / (2 * e);
    const double lhs = s.m * acc + d.c * v(t) + s.k * exact(s, d, 1.0, 0.0, t).q(0);
    EXPECT_NEAR(lhs, d.f * std::cos(d.omega * t), 1e-7);
}

TEST(Forcing, OrdersOfTheFamilyAreKept) {
    for (const member& m : test::five_members) {
        const double coarse = oscillator_error(m.spec, 100), fine = oscillator_error(m.spec, 200);
        const double observed = std::log2(coarse / fine);
        SCOPED_TRACE(m.spec.label() + ": errors " + test::sci(coarse) + ", " + test::sci(fine));
        EXPECT_NEAR(observed, m.order, 0.15);
        RecordProperty("order_" + m.spec.label(), test::sci(observed));
    }
}

TEST(Forcing, BuiltInForcesByHandTakeTheStepsOfAutomaticDerivatives) {
    const spring s;
    const damped_drive d;
    for (auto kind : {iteration_kind::newton, iteration_kind::simplified}) {
        newton_options opt;
        opt.iteration = kind;
        general::stepper<spring, damped_drive> ad(lagrangian_system<spring>(s), d, 0.05,
                                                  scheme_kind::simpson, opt);
        general::stepper<spring, built_in> hand(lagrangian_system<spring>(s), built_in_drive(d),
                                                0.05, scheme_kind::simpson, opt);
        phase_state<1> x{vec<1>{1.0}, vec<1>{0.0}}, y = x;
        for (int j = 0; j < 400; ++j) {
            ASSERT_TRUE(ad.step(x).converged);
            ASSERT_TRUE(hand.step(y).converged);
            EXPECT_NEAR(x.q(0), y.q(0), 1e-14);
            EXPECT_NEAR(x.p(0), y.p(0), 1e-14);
            EXPECT_NEAR(ad.last_work(), hand.last_work(), 1e-15);
        }
        EXPECT_NEAR(ad.time(), 400 * 0.05, 1e-12); // time advances by h without a driver
    }
}

TEST(Forcing, AZeroForceTakesTheConservativeStepsBitForBit) {
    const kepler::orbit orbit(0.6, 1.0);
    const lagrangian_system<kepler::lagrangian> sys({});
    for (auto kind : {iteration_kind::newton, iteration_kind::simplified}) {
        for (scheme_spec spec :
             {scheme_spec(scheme_kind::simpson), scheme_spec(scheme_kind::gauss, 3)}) {
            newton_options opt;
            opt.iteration = kind;
            general::stepper<kepler::lagrangian> plain(sys, orbit.period() / 100, spec, opt);
            general::stepper<kepler::lagrangian, kepler_drag> zero(sys, {}, orbit.period() / 100,
                                                                   spec, opt);
            phase_state<2> x = orbit.at(0.0), y = x;
            int differ = 0;
            for (int j = 0; j < 300; ++j) {
                const auto a = plain.step(x), b = zero.step(y);
                ASSERT_TRUE(a.converged && b.converged);
                differ += (x.q != y.q || x.p != y.p || a.iterations != b.iterations) ? 1 : 0;
            }
            EXPECT_EQ(differ, 0) << spec.label();
        }
    }
}

TEST(Forcing, AForceWithoutTorqueConservesAngularMomentum) {
    // Forced Noether (Marsden & West 2001, Thm 3.2.1): the discrete forces at the nodes,
    // h Σ_k w_k φ_ik f_k, have no component along the rotations when every f_k ∥ q_k.
    const kepler::orbit orbit(0.6, 1.0);
    const lagrangian_system<kepler::lagrangian> sys({});
    auto drift = [&](kepler_drag::kind mode, scheme_spec spec) {
        general::stepper<kepler::lagrangian, kepler_drag> st(sys, kepler_drag{mode},
                                                             orbit.period() / 200, spec);
        phase_state<2> x = orbit.at(0.0);
        const double l0 = kepler::angular_momentum(x);
        double worst = 0.0, energy0 = sys.energy(x);
        for (int j = 0; j < 2000; ++j) {
            EXPECT_TRUE(st.step(x).converged);
            worst = std::max(worst, std::abs(kepler::angular_momentum(x) - l0) / std::abs(l0));
        }
        EXPECT_LT(sys.energy(x), energy0 - 1e-3)
            << mode << " " << spec.label(); // the drag did work
        return worst;
    };
    for (scheme_spec spec :
         {scheme_spec(scheme_kind::simpson), scheme_spec(scheme_kind::gauss, 3)}) {
        const double radial = drift(kepler_drag::radial, spec);
        EXPECT_LE(radial, 2e-14) << spec.label();
        RecordProperty("angular_momentum_drift_radial_drag_" + spec.label(), test::sci(radial));
        EXPECT_GT(drift(kepler_drag::linear, spec), 1e-3) << spec.label(); // negative control
    }
}

namespace {
// Joint damping and a PD controller (with gravity compensation) tracking a moving reference,
// on a double pendulum: the energy balance and step Jacobian tests' force.
using pd_pendulum_force = force_sum<rayleigh_damping<2>, pd_controller<2>>;
pd_pendulum_force pd_pendulum_force_of(const double_pendulum::lagrangian& l) {
    pd_controller<2> pd;
    pd.kp = mat<2>{{20.0, 0.0}, {0.0, 10.0}};
    pd.kd = mat<2>{{2.0, 0.0}, {0.0, 1.0}};
    pd.reference = [](double t, vec<2>& r, vec<2>& rate) {
        r = vec<2>{0.5 * std::sin(t), -0.3 * std::cos(2 * t)};
        rate = vec<2>{0.5 * std::cos(t), 0.6 * std::sin(2 * t)};
    };
    pd.compensate(l);
    return pd_pendulum_force(rayleigh_damping<2>::diagonal(vec<2>{0.2, 0.1}), pd);
}
} // namespace

TEST(Forcing, EnergyBalanceHoldsToTheSchemesOrder) {
    // A double pendulum with joint damping and a PD controller (with gravity compensation)
    // tracking a moving reference: E_N − E_0 − Σ_j W_j → 0 as h^p.
    const auto sys = double_pendulum::make_system({});
    const pd_pendulum_force f = pd_pendulum_force_of(sys.lagrangian());
    using force = pd_pendulum_force;
    auto imbalance = [&](scheme_spec spec, int n, double* work) {
        general::stepper<double_pendulum::lagrangian, force> st(sys, f, 4.0 / n, spec);
        run_state<2> s = run_state<2>::start({vec<2>{1.0, -0.5}, vec<2>{0.0, 0.0}});
        const double e0 = sys.energy(s.x);
        double w = 0.0;
        integrate_from(st, s, static_cast<std::size_t>(n),
                       [&](const auto&) { w += st.last_work(); });
        *work = w;
        return sys.energy(s.x) - e0 - w;
    };
    for (const member& m : {member{scheme_kind::newmark, 2}, member{scheme_kind::simpson, 4},
                            member{{scheme_kind::gauss, 3}, 6}}) {
        double work = 0.0;
        const double coarse = imbalance(m.spec, 200, &work), fine = imbalance(m.spec, 400, &work);
        SCOPED_TRACE(m.spec.label() + ": imbalance " + test::sci(coarse) + ", " + test::sci(fine) +
                     ", work " + test::sci(work));
        EXPECT_GT(std::abs(work), 1.0);                   // the forces did work
        EXPECT_LT(std::abs(fine), 1e-3 * std::abs(work)); // and it is accounted for
        EXPECT_NEAR(std::log2(std::abs(coarse / fine)), m.order, 0.3);
        RecordProperty("energy_balance_order_" + m.spec.label(),
                       test::sci(std::log2(std::abs(coarse / fine))));
    }
}

namespace {

/// Central differences of the step map (each column: a step from x ± ε e_c, Newton, fresh
/// steppers made by `make`), 2d × 2d.
template <int D, class Make>
Eigen::MatrixXd finite_difference_jacobian(Make&& make, const phase_state<D>& x, double eps) {
    const int d = static_cast<int>(x.q.size());
    Eigen::MatrixXd j(2 * d, 2 * d);
    for (int c = 0; c < 2 * d; ++c) {
        phase_state<D> plus = x, minus = x;
        (c < d ? plus.q(c) : plus.p(c - d)) += eps;
        (c < d ? minus.q(c) : minus.p(c - d)) -= eps;
        auto a = make(), b = make();
        EXPECT_TRUE(a.step(plus).converged && b.step(minus).converged);
        j.col(c) << (plus.q - minus.q) / (2 * eps), (plus.p - minus.p) / (2 * eps);
    }
    return j;
}

/// max |JᵀΩJ − Ω|, Ω = [[0, I], [−I, 0]].
double symplectic_defect(const Eigen::MatrixXd& j) {
    const auto d = j.rows() / 2;
    Eigen::MatrixXd omega = Eigen::MatrixXd::Zero(2 * d, 2 * d);
    omega.topRightCorner(d, d).setIdentity();
    omega.bottomLeftCorner(d, d) = -Eigen::MatrixXd::Identity(d, d);
    return (j.transpose() * omega * j - omega).lpNorm<Eigen::Infinity>();
}

} // namespace

TEST(StepJacobian, ForcedStepMatchesFiniteDifferences) {
    // The damped, PD-controlled double pendulum of the energy balance test, gauss-3, h = 0.02;
    // central differences with ε = 1e-5 are accurate to ~ε² |∂³Φ| ~ 1e-9.
    const auto sys = double_pendulum::make_system({});
    const pd_pendulum_force f = pd_pendulum_force_of(sys.lagrangian());
    using force = pd_pendulum_force;
    newton_options opt;
    opt.iteration = iteration_kind::newton;
    auto make = [&] {
        general::stepper<double_pendulum::lagrangian, force> st(sys, f, 0.02,
                                                                {scheme_kind::gauss, 3}, opt);
        st.set_time(0.7);
        return st;
    };
    const phase_state<2> x{vec<2>{1.0, -0.5}, vec<2>{0.3, -0.2}};
    auto st = make();
    phase_state<2> y = x;
    ASSERT_TRUE(st.step(y).converged);
    Eigen::MatrixXd j;
    st.step_jacobian(x, j);
    const Eigen::MatrixXd fd = finite_difference_jacobian<2>(make, x, 1e-5);
    EXPECT_LE((j - fd).lpNorm<Eigen::Infinity>(), 1e-8 * fd.lpNorm<Eigen::Infinity>());
    RecordProperty("jacobian_vs_fd_forced", test::sci((j - fd).lpNorm<Eigen::Infinity>()));
    // Damping contracts phase space: the forced map is not symplectic (a negative control for
    // the check below).
    EXPECT_GT(symplectic_defect(j), 1e-4);
}

TEST(StepJacobian, ConservativeStepIsSymplectic) {
    const kepler::orbit orbit(0.6, 1.0);
    const lagrangian_system<kepler::lagrangian> sys({});
    for (scheme_spec spec :
         {scheme_spec(scheme_kind::simpson), scheme_spec(scheme_kind::gauss, 3)}) {
        general::stepper<kepler::lagrangian> st(sys, orbit.period() / 50, spec);
        phase_state<2> x = orbit.at(0.0);
        double worst = 0.0;
        Eigen::MatrixXd j;
        for (int n = 0; n < 50; ++n) { // around the orbit, pericentre included
            const phase_state<2> from = x;
            ASSERT_TRUE(st.step(x).converged);
            st.step_jacobian(from, j);
            worst = std::max(worst, symplectic_defect(j));
        }
        EXPECT_LE(worst, 1e-12) << spec.label();
        RecordProperty("symplectic_defect_" + spec.label(), test::sci(worst));
    }
}

namespace {
// Joint torques u with a cross term in q, and a damping that changes with time (so that the
// force's Jacobians depend on t: the step's Jacobian must take them at the step's own times).
struct torque_input {
    static constexpr int dim = 2, controls = 2;
    template <class T>
    tvec<T, 2> operator()(const tvec<T, 2>& q, const tvec<T, 2>& v, double t,
                          const tvec<T, 2>& u) const {
        const double c = 0.3 + 0.2 * std::sin(3.0 * t);
        return tvec<T, 2>(u(0) - c * v(0) + 0.1 * u(1) * q(1), u(1) - c * v(1));
    }
};
} // namespace

TEST(StepJacobian, ControlSensitivityMatchesFiniteDifferences) {
    // ∂(q_{j+1}, p_{j+1})/∂(q_j, p_j) and ∂/∂u_j against central differences (ε = 1e-5), gauss-2,
    // h = 0.05, from t = 0.7 (the damping's rate there is 0.6 cos 2.1 ≠ 0).
    const auto sys = double_pendulum::make_system({});
    using force = controlled<torque_input>;
    newton_options opt;
    opt.iteration = iteration_kind::newton;
    const vec<2> u0{0.4, -0.2};
    auto make = [&](const vec<2>& u) {
        general::stepper<double_pendulum::lagrangian, force> st(sys, force{}, 0.05,
                                                                {scheme_kind::gauss, 2}, opt);
        st.force().u = u;
        st.set_time(0.7);
        return st;
    };
    const phase_state<2> x{vec<2>{0.8, -0.3}, vec<2>{0.5, 0.1}};
    auto st = make(u0);
    phase_state<2> y = x;
    ASSERT_TRUE(st.step(y).converged);
    // The block ∂q_{j+1}/∂p_j alone (what the contact step linearises with), taken right after
    // the step as the contact step takes it: against the differences, relative to the block,
    // and to the whole map's block, which the same factors give to round-off. The stepper's
    // time and work are left as the step left them.
    const double t1 = st.time(), w1 = st.last_work(), total1 = st.total_work();
    Eigen::MatrixXd sq;
    st.position_sensitivity(x, sq);
    EXPECT_EQ(st.time(), t1);
    EXPECT_EQ(st.last_work(), w1);
    EXPECT_EQ(st.total_work(), total1);
    Eigen::MatrixXd j, ju;
    st.step_jacobian(x, j, &ju);
    const Eigen::MatrixXd fd = finite_difference_jacobian<2>([&] { return make(u0); }, x, 1e-5);
    EXPECT_LE((j - fd).lpNorm<Eigen::Infinity>(), 1e-8 * fd.lpNorm<Eigen::Infinity>());
    ASSERT_EQ(sq.rows(), 2);
    ASSERT_EQ(sq.cols(), 2);
    const Eigen::MatrixXd fd_block = fd.block(0, 2, 2, 2);
    EXPECT_LE((sq - fd_block).lpNorm<Eigen::Infinity>(), 1e-7 * fd_block.lpNorm<Eigen::Infinity>());
    EXPECT_LE((sq - j.block(0, 2, 2, 2)).lpNorm<Eigen::Infinity>(),
              1e-14 * fd_block.lpNorm<Eigen::Infinity>());
    RecordProperty(
        "position_sensitivity_vs_fd",
        test::sci((sq - fd_block).lpNorm<Eigen::Infinity>() / fd_block.lpNorm<Eigen::Infinity>()));
    Eigen::MatrixXd fdu(4, 2);
    for (int c = 0; c < 2; ++c) {
        vec<2> up = u0, um = u0;
        up(c) += 1e-5;
        um(c) -= 1e-5;
        phase_state<2> a = x, b = x;
        auto sa = make(up), sb = make(um);
        ASSERT_TRUE(sa.step(a).converged && sb.step(b).converged);
        fdu.col(c) << (a.q - b.q) / 2e-5, (a.p - b.p) / 2e-5;
    }
    EXPECT_LE((ju - fdu).lpNorm<Eigen::Infinity>(), 1e-8 * fdu.lpNorm<Eigen::Infinity>());
    EXPECT_GT(fdu.lpNorm<Eigen::Infinity>(), 1e-3); // the input moves the state
    RecordProperty("jacobian_vs_fd_time_dependent", test::sci((j - fd).lpNorm<Eigen::Infinity>()));
    RecordProperty("control_jacobian_vs_fd", test::sci((ju - fdu).lpNorm<Eigen::Infinity>()));
}
