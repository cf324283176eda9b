// tests/multibody/test_lagrangian.cpp: the robot Lagrangian's mass matrix and bias forces by
// hand (multibody/lagrangian.hpp; lagrangian_with_mass_matrix, lagrangian_with_bias_forces), and
// what is built on them: lagrangian_system::velocity as q̇ = M⁻¹p, and the general engine's
// predictors from M(q) and b(q, q̇).
// References: the second derivatives of the same Lagrangian (tested against AD of a second
// implementation in test_derivatives.cpp) for M and b, Newton on ∂L/∂q̇(q, q̇) = p, and the
// stepper over the same Lagrangian without the mass matrix (its predictor from two second-
// derivative evaluations), on a random branched tree and one with mimic joints.
#include <random>

#include <gtest/gtest.h>

#include "multibody/random_tree.hpp"
#include "varsym/multibody/lagrangian.hpp"
#include "varsym/schemes/variational.hpp"
#include "varsym/systems/forcing.hpp"

namespace {

using namespace varsym;

/// The robot's Lagrangian without its mass matrix: what any other Lagrangian by hand is.
struct without_mass_matrix {
    static constexpr int dim = dynamic;
    multibody::robot_lagrangian l;
    [[nodiscard]] int dimension() const { return l.dimension(); }
    double operator()(const vec<dynamic>& q, const vec<dynamic>& v) const { return l(q, v); }
    void gradient(const vec<dynamic>& q, const vec<dynamic>& v,
                  lagrangian_terms<dynamic>& t) const {
        l.gradient(q, v, t);
    }
    void derivatives(const vec<dynamic>& q, const vec<dynamic>& v,
                     lagrangian_terms<dynamic>& t) const {
        l.derivatives(q, v, t);
    }
};
static_assert(lagrangian_with_bias_forces<multibody::robot_lagrangian>);
static_assert(!lagrangian_with_mass_matrix<without_mass_matrix>);

/// The robot with a mass matrix 1 % too large: a negative control for the predictor's test.
struct wrong_mass_matrix : multibody::robot_lagrangian {
    using robot_lagrangian::robot_lagrangian;
    void mass_matrix(const vec<dynamic>& q, mat<dynamic>& out) const {
        robot_lagrangian::mass_matrix(q, out);
        out *= 1.01;
    }
};

/// The robot with a mass matrix that is not positive definite (−M): the predictor from the
/// dynamics must fall back to predict().
struct indefinite_mass_matrix : multibody::robot_lagrangian {
    using robot_lagrangian::robot_lagrangian;
    void mass_matrix(const vec<dynamic>& q, mat<dynamic>& out) const {
        robot_lagrangian::mass_matrix(q, out);
        out = -out;
    }
};

/// The Taylor predictors' increments (protected in the stepper).
template <class L, class F = unforced>
struct predictor_probe : general::stepper<L, F> {
    using general::stepper<L, F>::stepper;
    Eigen::MatrixXd from_derivatives(const phase_state<dynamic>& x) {
        this->predict(x);
        return this->x_;
    }
    Eigen::MatrixXd from_dynamics(const phase_state<dynamic>& x) {
        this->predict_dynamics(x);
        return this->x_;
    }
};

multibody::robot_lagrangian robot(const multibody::tree& m) {
    return multibody::robot_lagrangian(std::make_shared<const multibody::tree>(m));
}

Eigen::VectorXd random_vector(std::mt19937& g, int n, double size) {
    std::uniform_real_distribution<double> u(-size, size);
    Eigen::VectorXd x(n);
    for (int i = 0; i < n; ++i)
        x(i) = u(g);
    return x;
}

double relative(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    return (a - b).lpNorm<Eigen::Infinity>() / std::max(1.0, b.lpNorm<Eigen::Infinity>());
}

// Both sides are O(10²) products of O(1) numbers: 1e-13 relative is a few hundred ulps; a
// missing term or a mimic weight left out is O(1). Two solves for q̇ differ by about κ(M) ε,
// within 1e-13 for κ up to about 400 (these trees' M are well conditioned at these states).
constexpr double round_off = 1e-13;

} // namespace

TEST(RobotLagrangian, MassMatrixIsTheSecondVelocityDerivative) {
    for (const bool mimic : {false, true}) {
        const multibody::tree m = mimic ? test::mimic_tree(true) : test::random_tree(13);
        const auto l = robot(m);
        const int n = l.dimension();
        std::mt19937 g(5);
        for (int k = 0; k < 5; ++k) {
            const Eigen::VectorXd q = random_vector(g, n, 2.0), v = random_vector(g, n, 2.0);
            lagrangian_terms<dynamic> t;
            l.derivatives(q, v, t);
            Eigen::MatrixXd mass;
            l.mass_matrix(q, mass);
            EXPECT_LE((mass - t.lvv).cwiseAbs().maxCoeff(),
                      round_off * std::max(1.0, t.lvv.cwiseAbs().maxCoeff()))
                << (mimic ? "mimic" : "tree");
        }
    }
}

TEST(RobotLagrangian, BiasForcesCloseTheEulerLagrangeEquations) {
    // b(q, q̇) by Newton–Euler against (∂²L/∂q̇∂q) q̇ − ∂L/∂q from the second derivatives, on a
    // branched tree and one with mimic joints. A gravity term or a mimic weight left out is O(1).
    for (const bool mimic : {false, true}) {
        const auto l = robot(mimic ? test::mimic_tree(true) : test::random_tree(21));
        const int n = l.dimension();
        std::mt19937 g(9);
        for (int k = 0; k < 5; ++k) {
            const Eigen::VectorXd q = random_vector(g, n, 2.0), v = random_vector(g, n, 2.0);
            lagrangian_terms<dynamic> t;
            l.derivatives(q, v, t);
            Eigen::VectorXd b;
            l.bias_forces(q, v, b);
            const Eigen::VectorXd want = t.lqv.transpose() * v - t.lq;
            EXPECT_LE(relative(b, want), round_off) << (mimic ? "mimic" : "tree");
            EXPECT_GT(want.lpNorm<Eigen::Infinity>(), 0.1); // not vacuous
        }
    }
}

TEST(RobotLagrangian, PredictorFromTheDynamicsIsTheTaylorPredictor) {
    // Newton's predictor from M (composite rigid bodies) and b (Newton–Euler) gives the
    // increments X_l = τ_l q̇ + ½ τ_l² q̈ of the one from second derivatives (predict(): q̇ by a
    // Newton step on ∂L/∂q̇ = p, q̈ from L_vv q̈ = L_q − L_vq q̇) to round-off. At h = 0.1 the
    // acceleration's part is a twentieth of the velocity's. Negative control: a mass matrix 1 %
    // off moves the increments by about 1 %.
    const auto l = robot(test::mimic_tree(true));
    const int n = l.dimension();
    const scheme_spec spec(scheme_kind::gauss, 2);
    predictor_probe<multibody::robot_lagrangian> fast(
        lagrangian_system<multibody::robot_lagrangian>(l), 0.1, spec);
    predictor_probe<without_mass_matrix> plain(
        lagrangian_system<without_mass_matrix>(without_mass_matrix{l}), 0.1, spec);
    predictor_probe<wrong_mass_matrix> wrong(
        lagrangian_system<wrong_mass_matrix>(wrong_mass_matrix(l.shared())), 0.1, spec);
    std::mt19937 g(11);
    for (int k = 0; k < 5; ++k) {
        const phase_state<dynamic> x{random_vector(g, n, 2.0), random_vector(g, n, 3.0)};
        const Eigen::MatrixXd want = plain.from_derivatives(x), got = fast.from_dynamics(x);
        const double size = want.lpNorm<Eigen::Infinity>();
        EXPECT_LE((got - want).lpNorm<Eigen::Infinity>(), round_off * size);
        EXPECT_GT((wrong.from_dynamics(x) - want).lpNorm<Eigen::Infinity>(), 1e-3 * size);
    }
}

TEST(RobotLagrangian, PredictorFromTheDynamicsWithAForceAndItsFallback) {
    // With a force f (Rayleigh damping, f = −C q̇), q̈ = M⁻¹(f − b) against predict()'s, whose
    // L_vv q̈ = L_q + f − L_vq q̇ holds the same f: equal to round-off; without the force the
    // increments move by more than 1 % (negative control). Where M is not positive definite
    // the predictor is predict() itself, bit for bit.
    const auto l = robot(test::mimic_tree(true));
    const int n = l.dimension();
    const scheme_spec spec(scheme_kind::gauss, 2);
    using damping = rayleigh_damping<dynamic>;
    const damping c = damping::diagonal(Eigen::VectorXd::LinSpaced(n, 2.0, 6.0));
    predictor_probe<multibody::robot_lagrangian, damping> fast(
        lagrangian_system<multibody::robot_lagrangian>(l), c, 0.1, spec);
    predictor_probe<without_mass_matrix, damping> plain(
        lagrangian_system<without_mass_matrix>(without_mass_matrix{l}), c, 0.1, spec);
    predictor_probe<multibody::robot_lagrangian> free(
        lagrangian_system<multibody::robot_lagrangian>(l), 0.1, spec);
    predictor_probe<indefinite_mass_matrix, damping> indefinite(
        lagrangian_system<indefinite_mass_matrix>(indefinite_mass_matrix(l.shared())), c, 0.1,
        spec);
    std::mt19937 g(13);
    for (int k = 0; k < 5; ++k) {
        const phase_state<dynamic> x{random_vector(g, n, 2.0), random_vector(g, n, 3.0)};
        const Eigen::MatrixXd want = plain.from_derivatives(x), got = fast.from_dynamics(x);
        const double size = want.lpNorm<Eigen::Infinity>();
        EXPECT_LE((got - want).lpNorm<Eigen::Infinity>(), round_off * size);
        EXPECT_GT((free.from_dynamics(x) - want).lpNorm<Eigen::Infinity>(), 1e-2 * size);
        const Eigen::MatrixXd fallback = indefinite.from_dynamics(x);
        EXPECT_TRUE(fallback.allFinite());
        EXPECT_EQ((fallback - indefinite.from_derivatives(x)).cwiseAbs().maxCoeff(), 0.0);
    }
}

TEST(RobotLagrangian, VelocityFromTheMassMatrixSolvesTheMomentum) {
    // q̇ = M⁻¹p against Newton on ∂L/∂q̇(q, q̇) = p (the path of every other Lagrangian), and
    // the residual ∂L/∂q̇(q, q̇) − p itself.
    const auto l = robot(test::random_tree(17));
    const lagrangian_system<multibody::robot_lagrangian> hand(l);
    const lagrangian_system<without_mass_matrix> newton(without_mass_matrix{l});
    const int n = l.dimension();
    std::mt19937 g(3);
    for (int k = 0; k < 5; ++k) {
        const Eigen::VectorXd q = random_vector(g, n, 2.0), p = random_vector(g, n, 5.0);
        const Eigen::VectorXd v = hand.velocity(q, p), w = newton.velocity(q, p);
        EXPECT_LE(relative(v, w), round_off);
        EXPECT_LE(relative(hand.momentum(q, v), p), round_off);
        // The energy is T + V with q̇ = M⁻¹p, whichever path found it.
        EXPECT_NEAR(hand.energy({q, p}), newton.energy({q, p}),
                    round_off * std::max(1.0, std::abs(newton.energy({q, p}))));
    }
}

TEST(RobotLagrangian, SingularMassMatrixIsRefused) {
    // A body without mass or inertia on the last joint: M is singular, and velocity says so
    // rather than return a garbage q̇.
    multibody::tree m = test::random_tree(19);
    ASSERT_EQ(m.bodies[6].parent, 5); // a leaf
    m.bodies[6].mass = 0.0;
    m.bodies[6].inertia.setZero();
    const lagrangian_system<multibody::robot_lagrangian> sys(robot(m));
    const Eigen::VectorXd q = Eigen::VectorXd::Constant(7, 0.3), p = Eigen::VectorXd::Ones(7);
    EXPECT_THROW((void)sys.velocity(q, p), std::domain_error);
}

TEST(RobotLagrangian, StepsFromTheMassMatrixPredictorAreNewtonsSteps) {
    // The predictor only starts the iteration: from every state of a run, one step with the
    // mass matrix's predictor equals the step from the predictor of second derivatives to
    // round-off (two Newton solves that stop at the floor from different starts).
    const auto l = robot(test::mimic_tree(true));
    const lagrangian_system<multibody::robot_lagrangian> hand(l);
    const lagrangian_system<without_mass_matrix> plain(without_mass_matrix{l});
    for (const scheme_spec spec :
         {scheme_spec(scheme_kind::gauss, 2), scheme_spec(scheme_kind::simpson)}) {
        general::stepper<multibody::robot_lagrangian> a(hand, 1e-3, spec);
        general::stepper<without_mass_matrix> b(plain, 1e-3, spec);
        phase_state<dynamic> x{Eigen::VectorXd::Constant(l.dimension(), 0.4),
                               Eigen::VectorXd::Zero(l.dimension())};
        double worst = 0.0;
        for (int j = 0; j < 300; ++j) {
            phase_state<dynamic> y = x;
            ASSERT_TRUE(a.step(x).converged);
            ASSERT_TRUE(b.step(y).converged);
            worst = std::max({worst, relative(x.q, y.q), relative(x.p, y.p)});
        }
        EXPECT_LE(worst, round_off) << spec.label();
        EXPECT_GT(x.p.lpNorm<Eigen::Infinity>(), 0.1) << "the tree did not move"; // not vacuous
    }
}
