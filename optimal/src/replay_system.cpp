// optimal/src/replay_system.cpp: the closure check of a controlled_system (system.hpp) by default:
// the general engine (schemes/variational.hpp) steps the system's own derivatives under the
// trajectory's controls, step by step from the start state: the same discrete equations, solved
// by another code (Newton on one step's equations instead of IPOPT on the whole trajectory's),
// must give the same nodes to round-off. Compiled once here for every system of run-time size.
#include <cmath>
#include <limits>
#include <string>

#include "varsym/optimal/replay.hpp"
#include "varsym/optimal/system.hpp"
#include "varsym/schemes/variational.hpp"

namespace varsym::optimal {

namespace {

/// The system's Lagrangian as the general engine takes one of run-time dimension.
struct system_lagrangian {
    static constexpr int dim = dynamic;
    const controlled_system* s;

    [[nodiscard]] int dimension() const { return s->dimension(); }
    double operator()(const vec<dynamic>& q, const vec<dynamic>& v, double t) const {
        lagrangian_terms<dynamic> lt;
        s->gradient(q, v, t, lt);
        return lt.value;
    }
    void gradient(const vec<dynamic>& q, const vec<dynamic>& v, double t,
                  lagrangian_terms<dynamic>& out) const {
        s->gradient(q, v, t, out);
    }
    void derivatives(const vec<dynamic>& q, const vec<dynamic>& v, double t,
                     lagrangian_terms<dynamic>& out) const {
        s->derivatives(q, v, t, out);
    }
    // The replay compares positions only: the energy balance's ∂L/∂t is not needed.
    [[nodiscard]] double time_derivative(const vec<dynamic>&, const vec<dynamic>&, double) const {
        return 0.0;
    }
    [[nodiscard]] bool depends_on_time() const { return false; }
};

/// f(q, q̇, t) = F(q, q̇, t, u), u the trajectory's control at the quadrature point of the current
/// step (`step`, set before each step) nearest to t.
struct system_controls {
    static constexpr int dim = dynamic;
    const controlled_system* s;
    const trajectory* path;
    int step = 0;

    [[nodiscard]] int dimension() const { return s->dimension(); }
    [[nodiscard]] vector input(double t) const {
        const auto r = path->control_times.size() / (path->node_times.size() - 1);
        Eigen::Index best = 0;
        double gap = std::numeric_limits<double>::infinity();
        for (Eigen::Index j = 0; j < r; ++j) {
            const Eigen::Index c = step * r + j;
            if (std::abs(path->control_times(c) - t) < gap) {
                gap = std::abs(path->control_times(c) - t);
                best = c;
            }
        }
        return path->u.col(best);
    }
    vec<dynamic> operator()(const vec<dynamic>& q, const vec<dynamic>& v, double t) const {
        input_terms f;
        s->force(q, v, t, input(t), f, false);
        return f.f;
    }
    void derivatives(const vec<dynamic>& q, const vec<dynamic>& v, double t,
                     force_terms<dynamic>& r) const {
        input_terms f;
        s->force(q, v, t, input(t), f, true);
        r.f = f.f;
        r.fq = f.fq;
        r.fv = f.fv;
    }
};

} // namespace

matrix controlled_system::replay(const trajectory& path) const {
    general::stepper<system_lagrangian, system_controls> stepper(
        lagrangian_system<system_lagrangian>(system_lagrangian{this}),
        system_controls{this, &path, 0}, path.h, path.scheme, replay_newton);
    return replay_with(stepper, path);
}

} // namespace varsym::optimal
