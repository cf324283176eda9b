// The free base's predictor (schemes/constrained.hpp, predict_start;
// multibody/floating_dynamics.hpp): a constrained step of a free-floating robot starts from its
// mass matrix and bias forces, and its increments are the Taylor predictor's, which takes second
// derivatives, to round-off.
#include <memory>
#include <random>

#include <gtest/gtest.h>

#include "multibody/random_tree.hpp"
#include "varsym/multibody/floating.hpp"
#include "varsym/schemes/constrained.hpp"
#include "varsym/systems/forcing.hpp"

namespace floating_predictor_test {

using namespace varsym;

/// free_robot counting its second-derivative evaluations (the count shared by its copies).
struct counted_free : multibody::free_robot {
    using multibody::free_robot::free_robot;
    std::shared_ptr<int> second = std::make_shared<int>(0);
    void derivatives(const vec<dynamic>& q, const vec<dynamic>& v,
                     lagrangian_terms<dynamic>& t) const {
        ++*second;
        multibody::free_robot::derivatives(q, v, t);
    }
};

/// The constrained step's start (protected), and the Taylor predictor's.
template <class F = unforced>
struct start_probe : general::constrained_stepper<counted_free, multibody::unit_quaternion, F> {
    using general::constrained_stepper<counted_free, multibody::unit_quaternion,
                                       F>::constrained_stepper;
    Eigen::MatrixXd start(const phase_state<dynamic>& x) {
        this->predict_start(x);
        return this->x_;
    }
    Eigen::MatrixXd taylor(const phase_state<dynamic>& x) {
        this->predict(x);
        return this->x_;
    }
};

TEST(FloatingBase, TheStepStartsFromTheMassMatrixAndBiasForcesWithoutSecondDerivatives) {
    // A free base's step starts from q̇ = M⁻¹p and q̈ = M⁻¹(f − b) (predict_dynamics, with
    // bias_forces_after_mass_matrix), where the Taylor predictor solves L_vv q̈ = L_q + f − L_vq q̇
    // with second derivatives: with joint damping f, the same increments to 1e-11 of their size
    // (two algorithms for the same terms: round-off of O(10²) products), and no second derivative
    // evaluated. Negative controls: the Taylor predictor's count moves, and the undamped start
    // differs by more than 1e-3 of the size (the force is in it).
    std::mt19937 g(17);
    multibody::tree fixed = test::random_tree(19); // seven joints, two of them prismatic
    fixed.root.mass = 2.0;
    fixed.root.inertia = test::random_inertia(g);
    const counted_free l(
        std::make_shared<const multibody::tree>(fixed.with_base(multibody::base_kind::free)));
    ASSERT_EQ(l.dimension(), 14);
    const lagrangian_system<counted_free> sys(l);
    vec<dynamic> damping = vec<dynamic>::Zero(14);
    damping.tail<7>() = vec<dynamic>::LinSpaced(7, 0.5, 2.0);
    const scheme_spec spec(scheme_kind::gauss, 2);
    start_probe<rayleigh_damping<dynamic>> damped(sys, multibody::unit_quaternion{14},
                                                  rayleigh_damping<dynamic>::diagonal(damping), 0.1,
                                                  spec);
    start_probe<> free(sys, multibody::unit_quaternion{14}, 0.1, spec);
    std::uniform_real_distribution<double> u(-1.5, 1.5);
    for (int k = 0; k < 5; ++k) {
        vec<dynamic> q(14), v(14);
        for (int i = 0; i < 14; ++i) {
            q(i) = u(g);
            v(i) = u(g);
        }
        q.segment<4>(3).normalize();
        const phase_state<dynamic> x{q, sys.momentum(q, v)};
        *l.second = 0;
        const Eigen::MatrixXd got = damped.start(x);
        EXPECT_EQ(*l.second, 0) << "state " << k;
        const Eigen::MatrixXd want = damped.taylor(x);
        EXPECT_GT(*l.second, 0) << "state " << k;
        const double size = want.lpNorm<Eigen::Infinity>();
        EXPECT_LE((got - want).lpNorm<Eigen::Infinity>(), 1e-11 * size) << "state " << k;
        EXPECT_GT((free.start(x) - want).lpNorm<Eigen::Infinity>(), 1e-3 * size) << "state " << k;
    }
}

} // namespace floating_predictor_test
