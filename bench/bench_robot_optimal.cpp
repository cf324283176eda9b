// bench/bench_robot_optimal.cpp: optimal control of URDF robots through the one compiled
// transcription (`make bench-optimal`, after bench_optimal): medians of interleaved rounds.
//   1. the KUKA iiwa 14 (7 joints, tests/data/urdf) rest to rest in 2 s within its URDF torque,
//      joint and velocity limits: N = 50 and 200, Simpson and gauss-2, exact and limited-memory
//      Hessians: seconds, iterations, cost;
//   2. its flange sent to a pose (models::frame_target): N = 50 and 200, Simpson and gauss-2;
//   3. a chain of n links written as a URDF (each 1 kg, 0.3 m, a revolute joint about y):
//      milliseconds per iteration (the first 20 iterations) against N (n = 10) and against n
//      (N = 25): linear in N (banded KKT matrix); in n, the derivatives are O(n²) and the
//      KKT matrix's dense blocks per step grow as n, their factorisation as n³; and one
//      evaluation of its residual, Jacobian and Hessian against n (n = 5 … 40, N = 25).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "interleaved.hpp"
#include "varsym/models/model.hpp"
#include "varsym/models/robot.hpp"
#include "varsym/multibody/spatial.hpp"
#include "varsym/optimize/model.hpp"
#include "varsym/optimize/solve.hpp"

namespace {

using namespace varsym;

struct outcome {
    double seconds = 0.0, cost = 0.0, horizon = 0.0;
    int iterations = 0;
    std::string status;
};

outcome solve(const models::model& robot, const optimal::control_problem& given,
              optimal::hessian_kind hessian, int max_iterations = 3000) {
    optimal::control_problem p = given;
    robot.limits(robot.defaults(), {}, p);
    const auto start = std::chrono::steady_clock::now();
    const auto tr = optimal::transcribe(robot, robot.defaults(), {}, p);
    optimal::solver_options o;
    o.hessian = hessian;
    o.max_iterations = max_iterations;
    const auto r = optimal::solve(*tr, o);
    const double s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return {s, r.cost, p.free_time ? r.x(r.x.size() - 1) : p.time, r.iterations,
            optimal::status_name(r.verdict)};
}

/// A planar chain of n links as URDF text: link i of 1 kg with its centre 0.3 m below joint i.
std::string chain_urdf(int n) {
    std::string s = "<robot name=\"chain\"><link name=\"l0\"/>";
    for (int i = 1; i <= n; ++i) {
        const std::string l = "l" + std::to_string(i), p = "l" + std::to_string(i - 1);
        s += "<link name=\"" + l +
             "\"><inertial><origin xyz=\"0 0 -0.15\"/><mass value=\"1\"/><inertia ixx=\"0.01\" "
             "iyy=\"0.01\" izz=\"0.001\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial></link>"
             "<joint name=\"j" +
             std::to_string(i) + "\" type=\"revolute\"><parent link=\"" + p + "\"/><child link=\"" +
             l + "\"/><origin xyz=\"0 0 " + (i == 1 ? "0" : "-0.3") +
             "\"/><axis xyz=\"0 1 0\"/><limit lower=\"-3\" upper=\"3\" effort=\"200\" "
             "velocity=\"10\"/></joint>";
    }
    return s + "</robot>";
}

optimal::control_problem rest_to_rest(int d, int steps, const scheme_spec& scheme,
                                      const Eigen::VectorXd& to) {
    optimal::control_problem p;
    p.time = 2.0;
    p.steps = steps;
    p.scheme = scheme;
    p.q_start = p.v_start = p.v_end = Eigen::VectorXd::Zero(d);
    p.q_end = to;
    return p;
}

/// One evaluation each of the chain's transcription's residual, Jacobian and Hessian (what
/// varsym computes per IPOPT iteration; the rest is IPOPT's factorisation) against n, N = 25,
/// Simpson, at the first guess: µs per evaluation and per evaluation, step and link.
void evaluation_costs(int rounds) {
    struct timing {
        double seconds = 0.0, residual = 0.0, jacobian = 0.0, hessian = 0.0;
    };
    const std::vector<int> links{5, 10, 20, 40};
    const int steps = 25;
    std::vector<std::unique_ptr<optimal::transcription>> problems;
    std::vector<models::model> chains;
    for (const int n : links) {
        chains.push_back(models::robot_model(models::parse_urdf(chain_urdf(n), "chain.urdf")));
        optimal::control_problem p =
            rest_to_rest(n, steps, scheme_kind::simpson, Eigen::VectorXd::Constant(n, 0.3 / n));
        chains.back().limits(chains.back().defaults(), {}, p);
        problems.push_back(optimal::transcribe(chains.back(), chains.back().defaults(), {}, p));
    }
    std::vector<std::function<timing()>> cases;
    for (std::size_t i = 0; i < links.size(); ++i)
        cases.emplace_back([&, i] {
            const auto& tr = *problems[i];
            const Eigen::VectorXd x = tr.start();
            const Eigen::VectorXd lambda = Eigen::VectorXd::Constant(tr.constraints(), 0.1);
            Eigen::VectorXd e;
            std::vector<double> values;
            const int reps = std::max(4, 400 / links[i]);
            const auto time = [&](auto&& f) {
                const auto start = std::chrono::steady_clock::now();
                for (int k = 0; k < reps; ++k)
                    f();
                return std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
                           .count() /
                       reps;
            };
            timing t;
            t.residual = time([&] { tr.residual(x, e); });
            t.jacobian = time([&] { tr.jacobian(x, values); });
            t.hessian = time([&] { tr.hessian(x, 1.0, lambda, values); });
            t.seconds = t.residual + t.jacobian + t.hessian;
            return t;
        });
    const auto results = bench::interleaved<timing>(cases, rounds);
    std::printf("\n## The chain's transcription, one evaluation at N = %d, Simpson: µs (µs per "
                "step and link)\n\n| n | residual | Jacobian | Hessian |\n|---|---|---|---|\n",
                steps);
    for (std::size_t i = 0; i < links.size(); ++i) {
        const auto& t = results[i];
        const double per = 1e6 / (steps * links[i]);
        std::printf("| %d | %.0f (%.2f) | %.0f (%.2f) | %.0f (%.2f) |\n", links[i],
                    1e6 * t.residual, per * t.residual, 1e6 * t.jacobian, per * t.jacobian,
                    1e6 * t.hessian, per * t.hessian);
    }
}

} // namespace

int main(int argc, char** argv) {
    const int rounds = argc > 1 ? std::atoi(argv[1]) : 3;
    std::setvbuf(stdout, nullptr, _IOLBF, 0);
    std::printf("# URDF robots: optimal control (medians of %d interleaved rounds)\n\n", rounds);
    const auto iiwa =
        models::robot_model(models::load_urdf(VARSYM_BENCH_DATA "/urdf/iiwa14_no_collision.urdf"));
    const Eigen::VectorXd to =
        (Eigen::VectorXd(7) << 0.4, 0.3, 0.2, -0.3, 0.2, 0.3, 0.2).finished();
    std::printf(
        "## KUKA iiwa 14, rest to rest in 2 s, effort, URDF torque, joint and velocity limits\n\n"
        "| N | scheme | Hessian | time [s] | iterations | ms / iteration | cost | "
        "status |\n|---|---|---|---|---|---|---|---|\n");
    struct config {
        int n;
        scheme_spec scheme;
        optimal::hessian_kind hessian;
    };
    std::vector<config> configs;
    for (const int n : {50, 200})
        for (const scheme_spec s :
             {scheme_spec(scheme_kind::simpson), scheme_spec(scheme_kind::gauss, 2)})
            for (const auto h :
                 {optimal::hessian_kind::exact, optimal::hessian_kind::limited_memory})
                configs.push_back({n, s, h});
    std::vector<std::function<outcome()>> cases;
    for (const auto& c : configs)
        cases.emplace_back(
            [&, c] { return solve(iiwa, rest_to_rest(7, c.n, c.scheme, to), c.hessian); });
    const auto results = bench::interleaved<outcome>(cases, rounds);
    for (std::size_t i = 0; i < configs.size(); ++i) {
        const auto& r = results[i];
        std::printf("| %d | %s | %s | %.3f | %d | %.1f | %.6f | %s |\n", configs[i].n,
                    configs[i].scheme.label().c_str(),
                    configs[i].hessian == optimal::hessian_kind::exact ? "exact" : "limited-memory",
                    r.seconds, r.iterations, 1e3 * r.seconds / r.iterations, r.cost,
                    r.status.c_str());
    }
    // The target: N = 200, exact Hessian, every limit, under 1 s.
    for (std::size_t i = 0; i < configs.size(); ++i)
        if (configs[i].n == 200 && configs[i].hessian == optimal::hessian_kind::exact)
            std::printf("\nTarget, N = 200 under 1 s: %s %.3f s (%s)",
                        configs[i].scheme.label().c_str(), results[i].seconds,
                        results[i].seconds < 1.0 ? "met" : "missed");
    std::printf("\n");

    std::printf("\n## KUKA iiwa 14, its flange to a pose in 2 s (--reach iiwa_link_ee "
                "--reach-position 0.5,0,0.5 --reach-rpy 0,pi/2,0), exact Hessian, URDF limits\n\n"
                "| N | scheme | time [s] | iterations | ms / iteration | cost | status |\n"
                "|---|---|---|---|---|---|---|\n");
    const auto tree = models::load_urdf(VARSYM_BENCH_DATA "/urdf/iiwa14_no_collision.urdf");
    const auto pose =
        models::frame_target(tree, "iiwa_link_ee", {0.5, 0.0, 0.5},
                             multibody::roll_pitch_yaw({0.0, std::numbers::pi / 2, 0.0}));
    std::vector<std::pair<int, scheme_spec>> reaches{{50, scheme_kind::simpson},
                                                     {50, {scheme_kind::gauss, 2}},
                                                     {200, scheme_kind::simpson},
                                                     {200, {scheme_kind::gauss, 2}}};
    std::vector<std::function<outcome()>> reach_cases;
    for (const auto& reach : reaches)
        reach_cases.emplace_back([&, reach] {
            auto p = rest_to_rest(7, reach.first, reach.second, Eigen::VectorXd::Zero(7));
            p.end_target = pose;
            return solve(iiwa, p, optimal::hessian_kind::exact);
        });
    const auto reach_results = bench::interleaved<outcome>(reach_cases, rounds);
    for (std::size_t i = 0; i < reaches.size(); ++i) {
        const auto& r = reach_results[i];
        std::printf("| %d | %s | %.3f | %d | %.1f | %.6f | %s |\n", reaches[i].first,
                    reaches[i].second.label().c_str(), r.seconds, r.iterations,
                    1e3 * r.seconds / r.iterations, r.cost, r.status.c_str());
    }

    std::printf("\n## KUKA iiwa 14 in minimum time (--cost time,effort=0.001, the first guess "
                "2 s), Simpson, URDF limits: the exact Hessian (its row of T) against limited "
                "memory\n\n| N | Hessian | time [s] | iterations | T [s] | cost | status |\n"
                "|---|---|---|---|---|---|---|\n");
    std::vector<std::pair<int, optimal::hessian_kind>> timed;
    for (const int n : {25, 50, 100})
        for (const auto h : {optimal::hessian_kind::exact, optimal::hessian_kind::limited_memory})
            timed.emplace_back(n, h);
    std::vector<std::function<outcome()>> timed_cases;
    for (const auto& c : timed)
        timed_cases.emplace_back([&, c] {
            auto p = rest_to_rest(7, c.first, scheme_kind::simpson, to);
            p.free_time = true;
            p.cost = {.effort = 0.001, .time = 1.0};
            return solve(iiwa, p, c.second);
        });
    const auto timed_results = bench::interleaved<outcome>(timed_cases, rounds);
    for (std::size_t i = 0; i < timed.size(); ++i) {
        const auto& r = timed_results[i];
        std::printf("| %d | %s | %.3f | %d | %.6f | %.6f | %s |\n", timed[i].first,
                    timed[i].second == optimal::hessian_kind::exact ? "exact" : "limited-memory",
                    r.seconds, r.iterations, r.horizon, r.cost, r.status.c_str());
    }

    std::printf("\n## A chain of n links (URDF), rest to rest in 2 s, Simpson, exact Hessian, "
                "the first 20 iterations\n\n"
                "| n | N | time [s] | iterations | ms / iteration | µs / iteration / step / "
                "link | status |\n|---|---|---|---|---|---|---|\n");
    std::vector<std::pair<int, int>> sizes{{10, 25},  {10, 50}, {10, 100},
                                           {10, 200}, {5, 25},  {20, 25}};
    std::vector<models::model> chains;
    for (const auto& [n, steps] : sizes) {
        (void)steps;
        chains.push_back(models::robot_model(models::parse_urdf(chain_urdf(n), "chain.urdf")));
    }
    std::vector<std::function<outcome()>> chain_cases;
    for (std::size_t i = 0; i < sizes.size(); ++i)
        chain_cases.emplace_back([&, i] {
            const int n = sizes[i].first;
            return solve(chains[i],
                         rest_to_rest(n, sizes[i].second, scheme_kind::simpson,
                                      Eigen::VectorXd::Constant(n, 0.3 / n)),
                         optimal::hessian_kind::exact, 20);
        });
    const auto chain_results = bench::interleaved<outcome>(chain_cases, rounds);
    for (std::size_t i = 0; i < sizes.size(); ++i) {
        const auto& r = chain_results[i];
        const auto [n, steps] = sizes[i];
        std::printf("| %d | %d | %.3f | %d | %.2f | %.2f | %s |\n", n, steps, r.seconds,
                    r.iterations, 1e3 * r.seconds / r.iterations,
                    1e6 * r.seconds / r.iterations / steps / n, r.status.c_str());
    }
    // The targets: the 20-link chain under 40 ms an iteration, and at most 2.5 times the 10-link
    // chain's (both at N = 25).
    const auto per_iteration = [&](int n, int steps) {
        const auto i = static_cast<std::size_t>(
            std::find(sizes.begin(), sizes.end(), std::pair{n, steps}) - sizes.begin());
        return chain_results[i].seconds / chain_results[i].iterations;
    };
    const double ms20 = 1e3 * per_iteration(20, 25), growth = ms20 / (1e3 * per_iteration(10, 25));
    std::printf("\nTargets at N = 25: 20 links %.1f ms an iteration (under 40: %s); 20 against 10 "
                "links %.2f times (at most 2.5: %s)\n",
                ms20, ms20 < 40.0 ? "met" : "missed", growth, growth <= 2.5 ? "met" : "missed");
    evaluation_costs(rounds);
}
