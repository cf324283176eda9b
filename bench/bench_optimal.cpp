// bench/bench_optimal.cpp: optimal control (DMOC + IPOPT) timings, printed as tables
// (`make bench-optimal`). Each case runs `rounds` times, interleaved with the others, and the
// median is shown (a shared machine). Cases:
//   1. a fully actuated two-link arm swung from hanging to upright in 2 s (effort, Simpson):
//      time, IPOPT iterations and time per iteration at N = 50 … 400 (linear in N: the KKT
//      system is banded; IPOPT's linear solver here is MUMPS);
//   2. the same at N = 100, exact Hessian against limited-memory BFGS;
//   3. a six-link arm rest to rest with torque bounds, N = 200 (refined from N = 25);
//   4. accuracy per second: the pendulum swing-up's optimal cost against a gauss-4 reference
//      at N = 400, for Newmark (the midpoint rule of DMOC tools), Simpson, gauss-2 and gauss-3.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include "interleaved.hpp"
#include "varsym/optimize/solve.hpp"
#include "varsym/optimize/transcribe.hpp"
#include "varsym/problems/linked_pendulum.hpp"

namespace {

using namespace varsym;
constexpr double pi = std::numbers::pi;

struct two_link {
    static constexpr int dim = 2;
    template <class T>
    T operator()(const tvec<T, 2>& q, const tvec<T, 2>& v) const {
        using std::cos;
        const double m = 1.0, l = 1.0, lc = 0.5, i = 1.0 / 12.0, g = 9.81;
        const T c2 = cos(q(1));
        const T m11 = m * lc * lc + m * (l * l + lc * lc + 2.0 * l * lc * c2) + 2.0 * i;
        const T m12 = m * (lc * lc + l * lc * c2) + i;
        const double m22 = m * lc * lc + i;
        return 0.5 * m11 * v(0) * v(0) + m12 * v(0) * v(1) + 0.5 * m22 * v(1) * v(1) +
               (m * lc + m * l) * g * cos(q(0)) + m * lc * g * cos(q(0) + q(1));
    }
};
template <int N>
struct joint_torques { // f = Bᵀu for relative joint torques on absolute angles
    static constexpr int dim = N, controls = N;
    template <class T>
    tvec<T, N> operator()(const tvec<T, N>&, const tvec<T, N>&, double, const tvec<T, N>& u) const {
        tvec<T, N> f;
        for (int i = 0; i < N; ++i)
            f(i) = i + 1 < N ? T(u(i) - u(i + 1)) : u(i);
        return f;
    }
};
struct relative_torques { // the two-link arm's q2 is already relative: f = u
    static constexpr int dim = 2, controls = 2;
    template <class T>
    tvec<T, 2> operator()(const tvec<T, 2>&, const tvec<T, 2>&, double, const tvec<T, 2>& u) const {
        return u;
    }
};
struct pendulum {
    static constexpr int dim = 1;
    template <class T>
    T operator()(const tvec<T, 1>& q, const tvec<T, 1>& v) const {
        using std::cos;
        return 0.5 * v(0) * v(0) + 9.81 * cos(q(0));
    }
};
struct torque {
    static constexpr int dim = 1, controls = 1;
    template <class T>
    tvec<T, 1> operator()(const tvec<T, 1>&, const tvec<T, 1>&, double, const tvec<T, 1>& u) const {
        return u;
    }
};

struct outcome {
    double seconds = 0, cost = 0, closure = 0;
    int iterations = 0;
    std::string status;
};

/// Solves p (with `levels` of mesh refinement: solve_refined), timing the whole.
template <class L, class F>
outcome run(const L& l, const F& f, const optimal::control_problem& p,
            optimal::hessian_kind hessian = optimal::hessian_kind::automatic, int levels = 0) {
    const auto start = std::chrono::steady_clock::now();
    optimal::solver_options o;
    o.hessian = hessian;
    const auto r = optimal::solve_refined(
        [&](int n) {
            auto q = p;
            q.steps = n;
            return std::unique_ptr<optimal::transcription>(optimal::transcribe(l, f, q));
        },
        p.steps, levels, o);
    const double s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    int iterations = 0;
    for (const int i : r.iterations)
        iterations += i;
    const auto closure = optimal::check_closure(*r.problem, r.problem->unpack(r.result));
    return {s, r.result.cost, closure.error, iterations, optimal::status_name(r.result.verdict)};
}

optimal::control_problem arm_problem(int steps) {
    optimal::control_problem p;
    p.time = 2.0;
    p.steps = steps;
    p.q_start = p.v_start = p.v_end = Eigen::VectorXd::Zero(2);
    p.q_end = Eigen::Vector2d(pi, 0.0);
    return p;
}

} // namespace

int main(int argc, char** argv) {
    const int rounds = argc > 1 ? std::atoi(argv[1]) : 3;
    std::printf("# varsym optimal control benchmark (medians of %d interleaved rounds)\n\n",
                rounds);

    std::printf("## Two-link arm swing-up, T = 2 s, effort, Simpson, exact Hessian\n\n");
    std::printf("From the interpolated boundary states (direct), and by mesh refinement from N/8 "
                "(refined; iterations summed over the levels).\n\n");
    std::printf("| N | start | time [s] | iterations | ms / iteration | µs / iteration / step | "
                "cost | status | closure |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|\n");
    const std::vector<int> sizes{50, 100, 200, 400};
    std::vector<std::function<outcome()>> cases;
    for (const int n : sizes)
        cases.emplace_back([n] { return run(two_link{}, relative_torques{}, arm_problem(n)); });
    for (const int n : sizes)
        cases.emplace_back([n] {
            return run(two_link{}, relative_torques{}, arm_problem(n),
                       optimal::hessian_kind::automatic, 3);
        });
    cases.emplace_back([] {
        return run(two_link{}, relative_torques{}, arm_problem(100),
                   optimal::hessian_kind::limited_memory);
    });
    cases.emplace_back([] {
        optimal::control_problem p;
        p.time = 3.0;
        p.steps = 200;
        p.q_start = p.v_start = p.v_end = Eigen::VectorXd::Zero(6);
        p.q_end = Eigen::VectorXd::LinSpaced(6, 0.3, 1.8);
        p.control_lower = Eigen::VectorXd::Constant(6, -40.0);
        p.control_upper = Eigen::VectorXd::Constant(6, 40.0);
        const linked_pendulum::lagrangian<6> arm(std::vector<double>(6, 1.0),
                                                 std::vector<double>(6, 0.5), 9.81);
        return run(arm, joint_torques<6>{}, p, optimal::hessian_kind::automatic, 3);
    });
    const auto results = bench::interleaved<outcome>(cases, rounds);
    for (std::size_t i = 0; i < 2 * sizes.size(); ++i) {
        const auto& r = results[i];
        const int n = sizes[i % sizes.size()];
        std::printf("| %d | %s | %.3f | %d | %.2f | %.2f | %.6f | %s | %.1e |\n", n,
                    i < sizes.size() ? "direct" : "refined", r.seconds, r.iterations,
                    1e3 * r.seconds / r.iterations, 1e6 * r.seconds / r.iterations / n, r.cost,
                    r.status.c_str(), r.closure);
    }
    const auto& exact = results[1];
    const auto& bfgs = results[2 * sizes.size()];
    std::printf("\n## Exact Hessian against limited-memory BFGS (two-link arm, N = 100)\n\n");
    std::printf("| Hessian | time [s] | iterations | cost | status |\n|---|---|---|---|---|\n");
    std::printf("| exact | %.3f | %d | %.8f | %s |\n", exact.seconds, exact.iterations, exact.cost,
                exact.status.c_str());
    std::printf("| limited-memory | %.3f | %d | %.8f | %s |\n", bfgs.seconds, bfgs.iterations,
                bfgs.cost, bfgs.status.c_str());
    const auto& six = results.back();
    std::printf("\n## Six-link arm rest to rest, |tau| <= 40 N m, T = 3 s, N = 200, Simpson, "
                "refined from N = 25\n\n");
    std::printf("time %.3f s, %d iterations, cost %.6f, %s, closure %.1e\n", six.seconds,
                six.iterations, six.cost, six.status.c_str(), six.closure);

    std::printf("\n## Accuracy per second: pendulum swing-up (T = 2, effort), cost error against "
                "gauss-4 at N = 400\n\n");
    const auto swing = [](const scheme_spec& spec, int n) {
        optimal::control_problem p;
        p.time = 2.0;
        p.steps = n;
        p.scheme = spec;
        p.q_start = p.v_start = p.v_end = Eigen::VectorXd::Zero(1);
        p.q_end = Eigen::VectorXd::Constant(1, pi);
        return run(pendulum{}, torque{}, p);
    };
    const double reference = swing({scheme_kind::gauss, 4}, 400).cost;
    std::printf("reference cost %.15f\n\n| scheme | N | time [s] | |cost error| | closure |\n"
                "|---|---|---|---|---|\n",
                reference);
    std::vector<std::pair<scheme_spec, int>> runs;
    for (const scheme_spec spec :
         {scheme_spec(scheme_kind::newmark), scheme_spec(scheme_kind::simpson),
          scheme_spec(scheme_kind::gauss, 2), scheme_spec(scheme_kind::gauss, 3)})
        for (const int n : {10, 20, 40, 80, 160, 320})
            runs.emplace_back(spec, n);
    std::vector<std::function<outcome()>> swings;
    for (const auto& [spec, n] : runs)
        swings.emplace_back([spec = spec, n = n, &swing] { return swing(spec, n); });
    const auto sw = bench::interleaved<outcome>(swings, rounds);
    for (std::size_t i = 0; i < runs.size(); ++i)
        std::printf("| %s | %d | %.4f | %.2e | %.1e |\n", runs[i].first.label().c_str(),
                    runs[i].second, sw[i].seconds, std::abs(sw[i].cost - reference), sw[i].closure);
}
