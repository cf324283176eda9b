// tests/numeric/test_allocations.cpp: a step allocates nothing on the heap once its stepper is
// built. Counts calls to operator new (standard containers, std::function, …) and turns Eigen's
// run-time no-malloc check into an exception (Eigen allocates through its own aligned_malloc,
// not operator new). Its own executable: it replaces the global operator new.
#include <atomic>
#include <cstdlib>
#include <new>
#include <numbers>
#include <stdexcept>
#include <vector>

#define EIGEN_RUNTIME_NO_MALLOC
#define eigen_assert(x)                                                                            \
    do {                                                                                           \
        if (!(x)) throw std::runtime_error("Eigen: " #x);                                          \
    } while (false)

#include <gtest/gtest.h>

#include "schemes/nbody.hpp"
#include "test_support.hpp"
#include "varsym/multibody/lagrangian.hpp"
#include "varsym/problems/arm.hpp"
#include "varsym/problems/chain.hpp"
#include "varsym/problems/double_pendulum.hpp"
#include "varsym/problems/kepler.hpp"
#include "varsym/problems/linked_pendulum.hpp"
#include "varsym/problems/oscillator.hpp"
#include "varsym/problems/pendulum.hpp"
#include "varsym/reference/paper_schemes.hpp"
#include "varsym/schemes/composition.hpp"
#include "varsym/schemes/galerkin.hpp"
#include "varsym/schemes/newmark.hpp"
#include "varsym/schemes/simpson.hpp"
#include "varsym/schemes/variational.hpp"
#include "varsym/systems/expression_separable.hpp"

namespace {
std::atomic<long> allocations{0};
}

// The replacement operator new below takes memory from malloc, so its operator delete must give
// it back with free; GCC 12, seeing library code call ::operator new, flags that as mismatched.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"

void* operator new(std::size_t n) {
    ++allocations;
    if (void* p = std::malloc(n == 0 ? 1 : n)) return p;
    throw std::bad_alloc();
}
void* operator new[](std::size_t n) {
    return operator new(n);
}
void operator delete(void* p) noexcept {
    std::free(p);
}
void operator delete[](void* p) noexcept {
    std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
    std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
    std::free(p);
}

using namespace varsym;

namespace {

// Steps `stepper` once to warm up, then 1000 times with allocation forbidden; returns the
// number of operator new calls in those 1000 steps (an Eigen allocation throws).
template <class Stepper, int D>
long allocations_in_steps(Stepper& stepper, phase_state<D> x) {
    EXPECT_TRUE(stepper.step(x).converged);
    const long before = allocations.load();
    Eigen::internal::set_is_malloc_allowed(false);
    try {
        for (int j = 0; j < 1000; ++j)
            EXPECT_TRUE(stepper.step(x).converged);
    } catch (...) {
        Eigen::internal::set_is_malloc_allowed(true);
        throw;
    }
    Eigen::internal::set_is_malloc_allowed(true);
    return allocations.load() - before;
}

const auto sys = pendulum::make_system(1.0, 2 * std::numbers::pi);
const phase_state<1> x0{vec<1>{std::numbers::pi / 2}, vec<1>{0.0}};
constexpr double h = 1.18 / 50;

} // namespace

TEST(Allocations, TheCounterSeesAllocations) {
    // Negative control: the check can fail. (The vector's buffer comes from operator new; the
    // new-expression itself may be elided by the compiler, as C++14 allows.)
    const long before = allocations.load();
    std::vector<double> v(100);
    EXPECT_GE(allocations.load() - before, 1);
    EXPECT_EQ(v.size(), 100u);
    Eigen::internal::set_is_malloc_allowed(false);
    EXPECT_THROW(Eigen::VectorXd(100).setZero(), std::runtime_error);
    Eigen::internal::set_is_malloc_allowed(true);
}

TEST(Allocations, PaperSchemesStepWithoutAllocating) {
    simpson::stepper s(sys, h);
    newmark::stepper n(sys, h);
    paper_reference::simpson_stepper sp(sys, h);
    EXPECT_EQ(allocations_in_steps(s, x0), 0);
    EXPECT_EQ(allocations_in_steps(n, x0), 0);
    EXPECT_EQ(allocations_in_steps(sp, x0), 0);
}

TEST(Allocations, FamilyStepsWithoutAllocating) {
    // One compiled stepper for every (rule, degree): its storage is sized in the constructor.
    for (auto kind : {galerkin::rule_kind::lobatto, galerkin::rule_kind::gauss})
        for (int s = 1; s <= galerkin::max_degree; ++s) {
            galerkin::stepper st(sys, h, kind, s);
            EXPECT_EQ(allocations_in_steps(st, x0), 0) << "s = " << s;
        }
    const auto sys2 = test::coupled_system();
    for (int s = 1; s <= galerkin::max_degree; ++s) {
        galerkin::stepper st2(sys2, 0.05, galerkin::rule_kind::gauss, s);
        EXPECT_EQ(allocations_in_steps(st2, phase_state<2>{vec<2>{1.0, -0.5}, vec<2>{0.3, 1.2}}), 0)
            << "s = " << s;
    }
}

TEST(Allocations, LargeFixedDimensionStepsWithoutAllocating) {
    // d = 18: the family's Jacobian (up to 144 × 144) is on the heap, allocated once.
    const test::planetary_start start(6);
    const separable_system<18, test::gravity<18>> nbody(mat<18>(start.mass_diagonal().asDiagonal()),
                                                        test::gravity<18>{start.masses});
    const phase_state<18> y0{vec<18>(start.q), vec<18>(start.p)};
    for (int s : {1, 3, 8}) {
        galerkin::stepper st(nbody, 0.5, galerkin::rule_kind::lobatto, s);
        EXPECT_EQ(allocations_in_steps(st, y0), 0) << "s = " << s;
    }
    using lag = separable_lagrangian<decltype(nbody)>;
    general::stepper<lag> g(lagrangian_system<lag>({nbody}), 0.5, {scheme_kind::gauss, 4});
    EXPECT_EQ(allocations_in_steps(g, y0), 0);
}

TEST(Allocations, GeneralEngineStepsWithoutAllocating) {
    // Automatic derivatives (double pendulum, d = 2), by the default simplified iteration (its
    // kept Jacobian refreshed now and then) and by Newton, and derivatives by hand (the pendulum).
    for (auto kind : {iteration_kind::simplified, iteration_kind::newton}) {
        newton_options opt;
        opt.iteration = kind;
        general::stepper dp(double_pendulum::make_system({}), 1e-3, {scheme_kind::lobatto, 3}, opt);
        EXPECT_EQ(allocations_in_steps(dp, phase_state<2>{vec<2>{1.0, 0.5}, vec<2>{0.0, 0.1}}), 0);
    }
    using lag = separable_lagrangian<pendulum::system>;
    general::stepper<lag> g(lagrangian_system<lag>({sys}), h, {scheme_kind::gauss, 5});
    EXPECT_EQ(allocations_in_steps(g, x0), 0);
}

TEST(Allocations, RunTimeDimensionStepsWithoutAllocating) {
    // d known at run time only: the chain (its own O(n) stage solve and in-place ∇V; at n = 10⁵
    // a step's allocations, 800 kB each, were trimmed and faulted back by glibc at every step),
    // and a typed separable Kepler problem (the dense stage Newton, ∇V and ∇²V from one code).
    const chain::system chain(1000, 1.0);
    const phase_state<dynamic> c0 = chain.lowest_mode(1.0);
    simpson::stepper cs(chain, 0.1);
    newmark::stepper cn(chain, 0.1);
    composition::stepper cc(chain, 0.1, composition::method::kahan_li8);
    galerkin::stepper cg(chain, 0.1, galerkin::rule_kind::gauss, 4);
    EXPECT_EQ(allocations_in_steps(cs, c0), 0);
    EXPECT_EQ(allocations_in_steps(cn, c0), 0);
    EXPECT_EQ(allocations_in_steps(cc, c0), 0);
    EXPECT_EQ(allocations_in_steps(cg, c0), 0);
    const auto kepler = separable_system_of(
        expression_lagrangian("0.5*(x_dot**2 + y_dot**2) + 1/sqrt(x**2 + y**2)", {"x", "y"}));
    const phase_state<dynamic> k0{vec<dynamic>(vec<2>{0.4, 0.0}), vec<dynamic>(vec<2>{0.0, 2.0})};
    simpson::stepper ks(kepler, 0.01);
    newmark::stepper kn(kepler, 0.01);
    galerkin::stepper kg(kepler, 0.01, galerkin::rule_kind::gauss, 4);
    EXPECT_EQ(allocations_in_steps(ks, k0), 0);
    EXPECT_EQ(allocations_in_steps(kn, k0), 0);
    EXPECT_EQ(allocations_in_steps(kg, k0), 0);
    // A mass matrix at a run-time d (a 3-d oscillator with coupled M and K): the dense stage
    // Newton's M δ and the refined M⁻¹ of Simpson's update.
    const auto osc = oscillator::make_system(
        (Eigen::MatrixXd(3, 3) << 2, 0.3, 0, 0.3, 1, 0.1, 0, 0.1, 1.5).finished(),
        (Eigen::MatrixXd(3, 3) << 5, -2, 0, -2, 4, -1, 0, -1, 3).finished());
    const phase_state<dynamic> o0{Eigen::Vector3d{1.0, -0.5, 0.2}, Eigen::Vector3d{0.0, 0.3, -0.1}};
    simpson::stepper os(osc, 0.05);
    newmark::stepper on(osc, 0.05);
    EXPECT_EQ(allocations_in_steps(os, o0), 0);
    EXPECT_EQ(allocations_in_steps(on, o0), 0);
}

namespace {
// The arm at a run-time number of links (6), with damping and PD control with gravity
// compensation.
const arm::lagrangian arm6(std::vector<double>(6, 1.0), std::vector<double>(6, 1.0 / 6), 9.81);
arm::force arm6_control() {
    arm::control c;
    c.kp.assign(6, 100.0);
    c.kd.assign(6, 40.0);
    c.damping.assign(6, 0.5);
    c.reference = {vec<dynamic>::Zero(6), vec<dynamic>::Constant(6, 0.5), 2.0};
    return arm::make_force(arm6, c);
}
} // namespace

TEST(Allocations, ArmDerivativesWithoutAllocating) {
    // The arm's Lagrangian's hand derivatives and its force keep their matrices per thread.
    const arm::lagrangian& l = arm6;
    const arm::force f = arm6_control();
    const vec<dynamic> q = vec<dynamic>::LinSpaced(6, -0.4, 0.9);
    const vec<dynamic> v = vec<dynamic>::LinSpaced(6, 0.3, -0.2);
    lagrangian_terms<dynamic> t;
    force_terms<dynamic> r;
    vec<dynamic> alone(6);
    l.derivatives(q, v, t); // sizes t, r and the scratch
    f.derivatives(q, v, 0.5, r);
    f.value(q, v, 0.5, alone); // and the value's (the compensation's gradient)
    Eigen::internal::set_is_malloc_allowed(false);
    try {
        l.derivatives(q, v, t);
        l.gradient(q, v, t);
        f.derivatives(q, v, 0.7, r);
        f.value(q, v, 0.7, alone);
    } catch (...) {
        Eigen::internal::set_is_malloc_allowed(true);
        throw;
    }
    Eigen::internal::set_is_malloc_allowed(true);
    EXPECT_TRUE(t.lqq.allFinite() && r.fq.allFinite());
}

TEST(Allocations, GeneralEngineAtRunTimeDimensionStepsWithoutAllocating) {
    // The arm on the general engine (the tool's path for it), by the simplified iteration (its
    // full Taylor predictor taken at each refresh of the kept Jacobian) and by Newton (the full
    // predictor at every step), with and without its force.
    const lagrangian_system<arm::lagrangian> robot(arm6);
    const arm::force f = arm6_control();
    const phase_state<dynamic> y0{vec<dynamic>::LinSpaced(6, -0.4, 0.9), vec<dynamic>::Zero(6)};
    for (auto kind : {iteration_kind::simplified, iteration_kind::newton}) {
        newton_options opt;
        opt.iteration = kind;
        general::stepper<arm::lagrangian> free(robot, 1e-3, {scheme_kind::gauss, 2}, opt);
        general::stepper<arm::lagrangian, arm::force> forced(robot, f, 1e-3,
                                                             {scheme_kind::gauss, 2}, opt);
        EXPECT_EQ(allocations_in_steps(free, y0), 0);
        EXPECT_EQ(allocations_in_steps(forced, y0), 0);
    }
}

TEST(Allocations, MultibodyRobotStepsWithoutAllocating) {
    // A six-joint tree (a branch at body 1, one prismatic joint) as a run-time multibody model:
    // its recursive derivatives reuse the thread's workspace, and the general engine's Newton
    // steps on it allocate nothing once sized (the tool's path for URDF robots).
    auto tree = std::make_shared<multibody::tree>();
    const int parents[] = {-1, 0, 1, 2, 1, 4};
    for (int i = 0; i < 6; ++i) {
        multibody::body b;
        b.name = b.link = "b" + std::to_string(i);
        b.parent = parents[i];
        b.kind = i == 3 ? multibody::joint_kind::prismatic : multibody::joint_kind::revolute;
        b.placement.origin = multibody::vec3(0.1 * i, 0.0, -0.3);
        b.axis = (i % 2 ? multibody::vec3(0, 1, 1) : multibody::vec3(1, 0, 0.5)).normalized();
        b.mass = 1.0 + 0.1 * i;
        b.com = multibody::vec3(0.0, 0.05, -0.15);
        b.inertia = multibody::vec3(0.02, 0.03, 0.04).asDiagonal();
        tree->bodies.push_back(b);
    }
    const multibody::robot_lagrangian l(tree);
    const vec<dynamic> q = vec<dynamic>::LinSpaced(6, -0.4, 0.9);
    const vec<dynamic> v = vec<dynamic>::LinSpaced(6, 0.3, -0.2);
    lagrangian_terms<dynamic> t;
    l.derivatives(q, v, t); // sizes t and the workspace
    Eigen::internal::set_is_malloc_allowed(false);
    try {
        l.derivatives(q, v, t);
        l.gradient(q, v, t);
    } catch (...) {
        Eigen::internal::set_is_malloc_allowed(true);
        throw;
    }
    Eigen::internal::set_is_malloc_allowed(true);
    EXPECT_TRUE(t.lqq.allFinite());
    const lagrangian_system<multibody::robot_lagrangian> robot(l);
    newton_options opt;
    opt.iteration = iteration_kind::newton;
    general::stepper<multibody::robot_lagrangian> step(robot, 1e-3, {scheme_kind::gauss, 2}, opt);
    EXPECT_EQ(allocations_in_steps(step, phase_state<dynamic>{q, vec<dynamic>::Zero(6)}), 0);
}
