// models/src/spherical_pendulum.cpp: the spherical pendulum in Cartesian coordinates with the
// constraint |x| = l (problems/mechanisms.hpp), run by the general engine.
#include <cmath>

#include <Eigen/Geometry>

#include "constrained_of.hpp"
#include "varsym/models/parameters.hpp"

namespace varsym::models::defs {

namespace {

struct spherical_pendulum_parameters {
    double mass, length, gravity, project;
};

} // namespace

model spherical_pendulum() {
    model m;
    m.name = "spherical-pendulum";
    m.summary = "spherical pendulum in Cartesian coordinates with the constraint |x| = l";
    m.description =
        "  L = m |x'|^2/2 - m g z, constraint (|x|^2 - l^2)/(2 l) = 0; q = (x, y, z) [m], z up.\n"
        "  q0: x,y,z, or th,phi [rad] (polar angle from the downward vertical, azimuth; default\n"
        "  1, 0); v0: x',y',z' or th',phi' (default 0, 1.2 sqrt(g/l)). Conserved: energy and\n"
        "  spin = x p_y - y p_x (the angular momentum about the vertical, to round-off).\n";
    m.description += detail::constrained_columns;
    m.description += "\n  Last column: spin.";
    m.dim = 3;
    m.coordinates = "x, y, z";
    m.short_start = {2};
    m.short_start_doc = "2 (th, phi)";
    const parameter_set<spherical_pendulum_parameters> set{
        {{&spherical_pendulum_parameters::mass,
          detail::positive_value("mass", 1.0, "kg", "mass m of the bob", "masses", 0)},
         {&spherical_pendulum_parameters::length,
          detail::positive_value("length", 1.0, "m", "length l of the rod", "lengths", 0)},
         {&spherical_pendulum_parameters::gravity, detail::gravity_parameter(9.81)},
         {&spherical_pendulum_parameters::project, detail::project_parameter()}}};
    set.declare(m);
    m.time = 10.0;
    m.steps = 2000;
    m.ensemble_time = 10.0;
    m.ensemble_steps = 2000;
    m.ensemble_note = "The bob rises above the pivot: --event 'q3'.";
    m.make = set.make([](const spherical_pendulum_parameters& par, const start& s) {
        mechanisms::spherical_pendulum p;
        p.m = par.mass, p.length = par.length, p.g = par.gravity;
        p.validate();
        auto pick = [](const std::vector<double>& given, std::vector<double> fallback) {
            return given.size() == 2 ? given : fallback;
        };
        const auto angles = pick(s.q0, {1.0, 0.0});
        const auto rates = pick(s.v0, {0.0, 1.2 * std::sqrt(p.g / p.length)});
        auto [q, qdot] = p.state(angles[0], angles[1], rates[0], rates[1]);
        if (s.q0.size() == 3) q = vec<3>(s.q0[0], s.q0[1], s.q0[2]);
        if (s.v0.size() == 3) qdot = vec<3>(s.v0[0], s.v0[1], s.v0[2]);
        const lagrangian_system<mechanisms::spherical_lagrangian> sys({p});
        return detail::constrained_problem(
            sys, mechanisms::spherical_rod{p}, unforced{}, detail::state_of(sys, s, q, qdot),
            par.project != 0.0,
            detail::column_set{{"spin"}, [](const phase_state<3>& x, double* out) {
                                   out[0] = mechanisms::spherical_pendulum::spin(x);
                               }});
    });
    m.drawing = set.drawing([](const spherical_pendulum_parameters& par) {
        // One body at the pivot, its z along the rod to the bob at q.
        using namespace figure_colour;
        const double l = par.length;
        figure f;
        f.coordinates = 3;
        f.parts = {figure_solid("sphere", 0, Eigen::Vector3d(0.04 * l, 0, 0),
                                Eigen::Vector3d::Zero(), rod),
                   figure_solid("cylinder", 0, Eigen::Vector3d(0.015 * l, l, 0),
                                Eigen::Vector3d(0, 0, l / 2), rod),
                   figure_solid("sphere", 0, Eigen::Vector3d(0.08 * l, 0, 0),
                                Eigen::Vector3d(0, 0, l), red)};
        f.place = [](std::span<const double> q, std::span<multibody::pose> poses) {
            const Eigen::Vector3d x(q[0], q[1], q[2]);
            poses[0].origin.setZero();
            poses[0].rotation =
                Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), x).toRotationMatrix();
        };
        f.floor = -1.1 * l;
        return f;
    });
    return m;
}

} // namespace varsym::models::defs
