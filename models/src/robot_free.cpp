// models/src/robot_free.cpp: the simulation of a robot with a free-floating base: the Lagrangian
// in the base's position, a unit quaternion and the joints (varsym/multibody/floating.hpp), run
// by the general engine with the quaternion's constraint (schemes/constrained.hpp), with the
// forces of the robot's parameters on the joints.
#include <cmath>
#include <string>
#include <vector>

#include "robot_parts.hpp"
#include "varsym/schemes/constrained.hpp"

namespace varsym::models::robot_detail {

namespace {

using free_system = lagrangian_system<multibody::free_robot>;
using multibody::unit_quaternion;

/// The start: q0 (position, a unit quaternion, joints; default the identity), and v0 or p0.
/// A quaternion whose length is not 1 to 1e-9, or a rate q̇ with u·u̇ beyond 1e-9 |u̇| (off the
/// constraint's tangent), is refused; within those, both are made exact.
phase_state<dynamic> free_start(const free_system& sys, const start& s, int n) {
    auto vector = [n](const std::vector<double>& given, const vec<dynamic>& fallback) {
        return given.empty() ? fallback
                             : vec<dynamic>(Eigen::Map<const vec<dynamic>>(given.data(), n));
    };
    vec<dynamic> identity = vec<dynamic>::Zero(n);
    identity(3) = 1.0;
    vec<dynamic> q = vector(s.q0, identity);
    const double norm = q.segment<4>(3).norm();
    if (!(std::abs(norm - 1.0) <= 1e-9))
        throw std::invalid_argument(
            "the base's quaternion (base_qw, base_qx, base_qy, base_qz) must have unit length, "
            "not " +
            std::to_string(norm) + ": give a unit quaternion");
    q.segment<4>(3) /= norm;
    vec<dynamic> v = s.p0.empty() ? vector(s.v0, vec<dynamic>::Zero(n))
                                  : sys.velocity(q, vector(s.p0, vec<dynamic>::Zero(n)));
    const double radial = q.segment<4>(3).dot(v.segment<4>(3));
    if (!(std::abs(radial) <= 1e-9 * std::max(1.0, v.segment<4>(3).norm())))
        throw std::invalid_argument(
            "the base's quaternion rate must keep its length (q . qdot = 0, here " +
            std::to_string(radial) + "): give qdot = 1/2 q * (0, w) for a body rate w");
    v.segment<4>(3) -= radial * q.segment<4>(3);
    sys.check_regular(q, v);
    return {q, sys.momentum(q, v)};
}

/// A free base is a constrained system (its unit quaternion), stepped by Newton: another iteration
/// is refused, not ignored.
void check_free_base(const step_options& o) {
    detail::check_general(o);
    detail::refuse_non_newton(o,
                              "a robot with a free base is a constrained system, solved by Newton");
}

} // namespace

problem simulate_free(const std::shared_ptr<const multibody::tree>& r,
                      const expression_force& typed, const std::vector<std::string>& names,
                      const robot_parameters& p, const start& s) {
    const int n = r->dof() + 1; // x, u, then the tree's joints after its six virtual ones
    const multibody::free_robot lag(
        std::make_shared<const multibody::tree>(r->with_gravity(p.gravity)));
    const free_system sys(lag);
    const phase_state<dynamic> x0 = free_start(sys, s, n);
    vec<dynamic> damping = vec<dynamic>::Zero(n);
    if (p.no_damping == 0.0) damping.tail(n - 7) = r->limits().damping.tail(n - 7);
    robot_forces rf = make_forces(p, typed, damping, x0.q, 7, nullptr);
    const unit_quaternion c{n};
    const double e0 = sys.energy(x0);
    // Columns: E, the forces' work W, E − E0 − W, joints out of range, |u|² − 1; the base's
    // velocity, the momenta and the centre of mass.
    std::vector<std::string> cols = {"energy", "work", "energy_balance", "limit_violations",
                                     "quaternion_residual"};
    cols.insert(cols.end(), base_columns().begin(), base_columns().end());
    const robot_contact touch = contact_of(p, r, x0.q);
    const int at = static_cast<int>(cols.size());
    if (touch.on) cols.insert(cols.end(), contact_columns().begin(), contact_columns().end());
    auto columns = [cols, sys, e0, r, names, at] {
        return detail::column_set{
            cols,
            [sys, e0, r, at](double, const phase_state<dynamic>& x, const auto& st, double* out) {
                out[0] = sys.energy(x);
                out[1] = st.total_work();
                out[2] = out[0] - e0 - out[1];
                int outside = 0;
                for (int i = 6; i < r->dof(); ++i) {
                    const multibody::joint_limits& l =
                        r->bodies[static_cast<std::size_t>(i)].limits;
                    outside += (x.q(i + 1) < l.lower || x.q(i + 1) > l.upper) ? 1 : 0;
                }
                out[3] = outside;
                out[4] = x.q.segment<4>(3).squaredNorm() - 1.0;
                fill_base(sys.lagrangian().motion(x.q, sys.velocity(x.q, x.p)), out + 5);
                fill_contact(st, out + at);
            },
            names};
    };
    problem pr = detail::make_problem(x0, 0.0, {});
    if (!rf.forced) {
        pr.simulate = [sys, c, x0, columns, touch, r](const step_options& o) {
            check_free_base(o);
            return simulate_robot(
                general::constrained_stepper<multibody::free_robot, unit_quaternion>(
                    sys, c, o.h, o.spec, o.newton),
                touch, r, x0, columns());
        };
        return pr;
    }
    pr.simulate = [sys, c, f = std::move(rf.force), x0, columns, touch, r](const step_options& o) {
        check_free_base(o);
        return simulate_robot(
            general::constrained_stepper<multibody::free_robot, unit_quaternion, robot_force>(
                sys, c, f, o.h, o.spec, o.newton),
            touch, r, x0, columns());
    };
    return pr;
}

} // namespace varsym::models::robot_detail
