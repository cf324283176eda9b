// optimal/src/replay_system.cpp: the closure check of a controlled_system (system.hpp) by default:
// the general engine (schemes/variational.hpp) steps the system's own derivatives under the
// trajectory's controls, step by step from the start state: the same discrete equations, solved
// by another code (Newton on one step's equations instead of IPOPT on the whole trajectory's),
// must give the same nodes to round-off; with constraints the constrained engine
// (schemes/constrained.hpp). Compiled once here for every system of run-time size.
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "varsym/optimal/replay.hpp"
#include "varsym/optimal/system.hpp"
#include "varsym/optimize/transcription.hpp"
#include "varsym/schemes/constrained.hpp"
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

/// The system's holonomic constraints as the constrained engine takes them (run-time size,
/// derivatives by the system's own means).
struct system_constraint {
    static constexpr int dim = dynamic, count = dynamic;
    const controlled_system* s;

    [[nodiscard]] int dimension() const { return s->dimension(); }
    [[nodiscard]] int size() const { return s->constraint_count(); }
    vec<dynamic> operator()(const vec<dynamic>& q) const {
        vector g;
        matrix jac;
        s->constraint(q, g, jac);
        return g;
    }
    void jacobian(const vec<dynamic>& q, Eigen::MatrixXd& jac) const {
        vector g;
        s->constraint(q, g, jac);
    }
    void curvature(const vec<dynamic>& q, const vec<dynamic>& lambda, mat<dynamic>& h) const {
        s->constraint_curvature(q, lambda, h);
    }
};

} // namespace

matrix replay(const controlled_system& s, const trajectory& path) {
    if (auto own = s.own_replay(path)) return *std::move(own);
    const lagrangian_system<system_lagrangian> l(system_lagrangian{&s});
    if (s.constraint_count() > 0) { // the constrained engine: impulses at the control values
        general::constrained_stepper<system_lagrangian, system_constraint, system_controls> stepper(
            l, system_constraint{&s}, system_controls{&s, &path, 0}, path.h, path.scheme,
            replay_newton);
        return replay_with(stepper, path);
    }
    general::stepper<system_lagrangian, system_controls> stepper(
        l, system_controls{&s, &path, 0}, path.h, path.scheme, replay_newton);
    return replay_with(stepper, path);
}

} // namespace varsym::optimal
