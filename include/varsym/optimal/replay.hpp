// varsym/optimal/replay.hpp: the closure check of an optimal trajectory. Its controls, as a
// force the general engine (schemes/variational.hpp) steps with, step by step from the start
// state: the same discrete equations, solved by another code (Newton on one step's equations
// instead of IPOPT on the whole trajectory's), must give the same nodes to round-off.
#pragma once

#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include "varsym/optimal/problem.hpp"
#include "varsym/schemes/constrained.hpp"
#include "varsym/schemes/variational.hpp"

namespace varsym::optimal {

/// The generalized force f(q, q̇, t) = F(q, q̇, t, u) with u the trajectory's control at the
/// quadrature point of the current step (`step`, set before each step) nearest to t.
template <class F>
struct scheduled_controls {
    static constexpr int dim = F::dim, M = F::controls;
    F f;
    std::shared_ptr<const trajectory> path;
    int step = 0;

    template <class T>
    tvec<T, dim> operator()(const tvec<T, dim>& q, const tvec<T, dim>& v, double t) const {
        const auto r = path->control_times.size() / (path->node_times.size() - 1);
        Eigen::Index best = 0;
        double gap = std::numeric_limits<double>::infinity();
        for (Eigen::Index j = 0; j < static_cast<Eigen::Index>(r); ++j) {
            const Eigen::Index c = step * static_cast<Eigen::Index>(r) + j;
            if (std::abs(path->control_times(c) - t) < gap) {
                gap = std::abs(path->control_times(c) - t);
                best = c;
            }
        }
        const vec<M> u = path->u.col(best);
        return f(q, v, t, tvec<T, M>(u.template cast<T>()));
    }
};

/// The nodes (q_n, p_n), n = 0 … N, of a stepper's steps under the trajectory's controls from
/// its start state (2d × (N + 1): q above p); the stepper's force is scheduled_controls. Throws
/// std::runtime_error naming the step if one fails.
template <class Stepper>
Eigen::MatrixXd replay_with(Stepper& stepper, const trajectory& path) {
    constexpr int D = Stepper::dim; // or dynamic
    const auto n = path.node_times.size() - 1;
    phase_state<D> x{vec<D>(path.q.col(0)), vec<D>(path.p.col(0))};
    Eigen::MatrixXd out(2 * x.q.size(), n + 1);
    out.col(0) << x.q, x.p;
    for (Eigen::Index k = 0; k < n; ++k) {
        stepper.force().step = static_cast<int>(k);
        const auto report = stepper.step(x);
        if (!report.converged)
            throw std::runtime_error("replay: step " + std::to_string(k) +
                                     " did not converge (residual " +
                                     std::to_string(report.residual) + ")");
        out.col(k + 1) << x.q, x.p;
    }
    return out;
}

/// Newton's iteration, up to 100 iterations: a step of a violent optimum may start far from its
/// solution.
inline constexpr newton_options replay_newton{.max_iterations = 100,
                                              .iteration = iteration_kind::newton};

/// The general engine's nodes under the trajectory's controls (replay_with).
template <lagrangian L, class F>
Eigen::MatrixXd replay(const L& l, const F& force, const trajectory& path,
                       const newton_options& newton = replay_newton) {
    general::stepper<L, scheduled_controls<F>> stepper(
        lagrangian_system<L>(l),
        scheduled_controls<F>{force, std::make_shared<const trajectory>(path), 0}, path.h,
        path.scheme, newton);
    return replay_with(stepper, path);
}

/// The constrained engine's nodes (schemes/constrained.hpp: the same discrete equations with
/// the constraint impulses at the control values, the momentum made tangent at the nodes).
template <lagrangian L, holonomic_constraint C, class F>
Eigen::MatrixXd replay(const L& l, const C& constraints, const F& force, const trajectory& path,
                       const newton_options& newton = replay_newton) {
    general::constrained_stepper<L, C, scheduled_controls<F>> stepper(
        lagrangian_system<L>(l), constraints,
        scheduled_controls<F>{force, std::make_shared<const trajectory>(path), 0}, path.h,
        path.scheme, newton);
    return replay_with(stepper, path);
}

} // namespace varsym::optimal
