// A published robotics optimal-control result reproduced: the robot arm of the COPS 3.0 benchmark
// (Dolan, Moré & Munson, Benchmarking optimization software with COPS 3.0, Argonne
// ANL/MCS-TM-273, 2004, problem 8), moved in minimum time. The arm's length ρ, its angle θ about
// the vertical and its elevation φ are driven by |u_i| ≤ 1 with L ρ̈ = u_ρ, I₁ θ̈ = u_θ,
// I₂ φ̈ = u_φ, I₂ = ((L − ρ)³ + ρ³)/3, I₁ = I₂ sin²φ, L = 5, from (4.5, 0, π/4) to
// (4.5, 2π/3, π/4) at rest, within 0 ≤ ρ ≤ L, |θ| ≤ π, 0 ≤ φ ≤ π. COPS reports T = 9.14138 with
// nh = 200 (the value the COPSBenchmark.jl and Dymos test suites check, to 1e-4 and 1e-3).
//
// Those equations are not Euler–Lagrange equations: they leave out the centrifugal and Coriolis
// terms of the kinetic energy T = ½(L ρ̇² + I₁ θ̇² + I₂ φ̇²). Here they are that Lagrangian under a
// force that puts them back, f = u + (d/dt ∂T/∂q̇ − ∂T/∂q − M q̈), so that the discrete
// Lagrange–d'Alembert equations discretise exactly COPS's dynamics.
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>

#include <gtest/gtest.h>

#include "varsym/optimize/solve.hpp"
#include "varsym/optimize/transcribe.hpp"

namespace {

using varsym::tvec;

constexpr double cops_length = 5.0, cops_time = 9.14138; // L; T for nh = 200 (COPS 3.0)

struct cops_arm {
    static constexpr int dim = 3; // ρ, θ, φ
    template <class T>
    static T inertia(const T& rho) { // I₂
        const T rest = cops_length - rho;
        return (rest * rest * rest + rho * rho * rho) / 3.0;
    }
    template <class T>
    T operator()(const tvec<T, 3>& q, const tvec<T, 3>& v) const {
        using std::sin;
        const T i2 = inertia(q(0)), s = sin(q(2));
        return 0.5 * (cops_length * v(0) * v(0) + i2 * s * s * v(1) * v(1) + i2 * v(2) * v(2));
    }
};

/// u plus the terms of the Euler–Lagrange equations that COPS's dynamics leave out.
struct cops_inputs {
    static constexpr int dim = 3, controls = 3;
    template <class T>
    tvec<T, 3> operator()(const tvec<T, 3>& q, const tvec<T, 3>& v, double,
                          const tvec<T, 3>& u) const {
        using std::cos, std::sin;
        const T rho = q(0), rest = cops_length - rho, i2 = cops_arm::inertia(rho);
        const T di2 = rho * rho - rest * rest, s = sin(q(2)), c = cos(q(2)); // ∂I₂/∂ρ
        const T i1_rho = di2 * s * s, i1_phi = 2.0 * i2 * s * c; // ∂I₁/∂ρ, ∂I₁/∂φ
        tvec<T, 3> f;
        f(0) = u(0) - 0.5 * (i1_rho * v(1) * v(1) + di2 * v(2) * v(2));
        f(1) = u(1) + (i1_rho * v(0) + i1_phi * v(2)) * v(1); // + İ₁ θ̇
        f(2) = u(2) + di2 * v(0) * v(2) - 0.5 * i1_phi * v(1) * v(1);
        return f;
    }
};

double cops_minimum_time(const varsym::scheme_spec& spec, int steps, int levels) {
    namespace vo = varsym::optimal;
    const double pi = std::numbers::pi;
    const auto make = [&](int n) -> std::unique_ptr<vo::transcription> {
        vo::control_problem p;
        p.time = 9.0; // the first guess
        p.free_time = true;
        p.time_lower = 0.1;
        p.time_upper = 20.0;
        p.cost = {.effort = 0.0, .time = 1.0};
        p.steps = n;
        p.scheme = spec;
        p.q_start = Eigen::Vector3d(4.5, 0.0, pi / 4);
        p.q_end = Eigen::Vector3d(4.5, 2 * pi / 3, pi / 4);
        p.v_start = p.v_end = Eigen::VectorXd::Zero(3);
        p.control_lower = Eigen::VectorXd::Constant(3, -1.0);
        p.control_upper = Eigen::VectorXd::Constant(3, 1.0);
        p.position_lower = Eigen::Vector3d(0.0, -pi, 0.0);
        p.position_upper = Eigen::Vector3d(cops_length, pi, pi);
        return vo::transcribe(cops_arm{}, cops_inputs{}, p);
    };
    const vo::refined run = vo::solve_refined(make, steps, levels);
    EXPECT_TRUE(run.result.converged()) << run.result.message;
    const vo::trajectory path = run.problem->unpack(run.result);
    const vo::closure_check closure = vo::check_closure(*run.problem, path);
    EXPECT_TRUE(closure.ok()) << closure.advice();
    const double horizon = path.node_times(path.node_times.size() - 1);
    std::printf("COPS robot arm, %s N = %d: T = %.8f (COPS nh = 200: %.5f), closure %.1e\n",
                spec.label().c_str(), steps, horizon, cops_time, closure.error);
    return horizon;
}

TEST(OptimalPublished, CopsRobotArmMinimumTime) {
    // Measured: Simpson N = 50, 100, 200, 400: 9.141605, 9.140998, 9.140906, 9.140916; Newmark
    // N = 200, 800: 9.141020, 9.140920 (the switches of the bang-bang controls fall inside steps,
    // which bounds the order); all within 6e-5 of COPS's 9.14138, the tolerance of 1e-4 the
    // COPSBenchmark.jl suite holds its solvers to.
    const double simpson = cops_minimum_time(varsym::scheme_kind::simpson, 100, 2);
    const double newmark = cops_minimum_time(varsym::scheme_kind::newmark, 200, 2);
    EXPECT_NEAR(simpson / cops_time, 1.0, 1e-4);
    EXPECT_NEAR(newmark / cops_time, 1.0, 1e-4);
    EXPECT_NEAR(simpson, newmark, 1e-4); // two members, one optimum
}

} // namespace
