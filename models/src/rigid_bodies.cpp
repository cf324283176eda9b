// models/src/rigid_bodies.cpp: the rigid bodies, integrated on SO(3) by the Lie group variational
// integrator (rigid_simulation.hpp): rigid-body (free), top (heavy top, any inertia and centre of
// mass) and pendulum-3d (a body hanging from a pivot). They share their parameters and their
// rules for the start; what differs is the data of rigid_defaults.
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "rigid_simulation.hpp"
#include "varsym/lie/so3.hpp"
#include "varsym/lie/symmetric_top.hpp"
#include "varsym/models/model.hpp"
#include "varsym/models/parameters.hpp"

namespace varsym::models::defs {

namespace {

const char* const rigid_description =
    "  State: attitude R (maps body to space; e3 of space points up) and body angular momentum\n"
    "  Pi = J Omega. q0: Euler angles th,phi,psi (z-x-z, R = Rz(phi) Rx(th) Rz(psi), as in\n"
    "  heavy-top) or a unit quaternion w,x,y,z; v0: Omega, or p0: Pi, body frame. Run columns:\n"
    "  step,t,q_w,q_x,q_y,q_z (q_w >= 0),Omega_1..3,energy, then the conserved quantities,\n"
    "  orthogonality (|R^T R - I|), R_11..R_33 with matrix. Ensembles and Python: q = the\n"
    "  Euler angles, p = Pi. Integrator: lgvi of `order` (not the schemes); no tangent map\n"
    "  (lambda and MEGNO are nan), no dense output (no sections).";

/// What differs between the three models.
struct rigid_defaults {
    std::vector<double> inertia, com;
    double weight;
    std::array<double, 3> euler; ///< default q0: Euler angles (θ, φ, ψ) [rad]
    lie::vec3 omega;             ///< default v0: body angular velocity Ω [rad/s]
    double time;                 ///< default run when the motion has no period
    long long steps;
};

/// The parameters of the three models: weight and com only where there is gravity (else 0 and
/// empty: not declared).
struct rigid_parameters {
    double weight, order, matrix;
    std::vector<double> inertia, com;
};

/// J from the inertia list i: the principal moments I1,I2,I3 or J11,J22,J33,J12,J13,J23.
lie::mat3 inertia_of(const std::vector<double>& i) {
    lie::mat3 j = lie::mat3::Zero();
    if (i.size() == 3) {
        j.diagonal() << i[0], i[1], i[2];
    } else if (i.size() == 6) {
        j << i[0], i[3], i[4], i[3], i[1], i[5], i[4], i[5], i[2];
    } else {
        throw std::invalid_argument("inertia needs 3 values (principal moments I1,I2,I3) or 6 "
                                    "(J11,J22,J33,J12,J13,J23) [kg m^2], got " +
                                    std::to_string(i.size()));
    }
    return j;
}

/// The attitude of q0: Euler angles (θ, φ, ψ) or a unit quaternion (w, x, y, z).
lie::mat3 attitude_of(const std::vector<double>& q0, const rigid_defaults& d) {
    if (q0.empty()) return so3::from_euler(d.euler[0], d.euler[1], d.euler[2]);
    if (q0.size() == 3) return so3::from_euler(q0[0], q0[1], q0[2]);
    const double n = std::sqrt(q0[0] * q0[0] + q0[1] * q0[1] + q0[2] * q0[2] + q0[3] * q0[3]);
    if (!(std::abs(n - 1.0) <= 1e-6))
        throw std::invalid_argument("q0: a quaternion (w,x,y,z) must have norm 1, got " +
                                    std::to_string(n));
    return so3::from_quaternion(q0[0] / n, q0[1] / n, q0[2] / n, q0[3] / n);
}

list_parameter inertia_parameter(const std::vector<double>& value, const char* about) {
    return {.name = "inertia",
            .value = value,
            .unit = "kg m^2",
            .doc = std::string("principal moments I1,I2,I3, or J11,J22,J33,J12,J13,J23, of "
                               "inertia about ") +
                   about + " in the body frame"};
}

model make_rigid(const std::string& name, const std::string& summary,
                 const std::string& description, const rigid_defaults& d, bool gravity) {
    model m;
    m.name = name;
    m.summary = summary;
    m.description = description + "\n" + rigid_description;
    m.dim = 3;
    m.coordinates = "th, phi, psi";
    m.short_start = {4};
    m.short_start_doc = "4 (a unit quaternion w,x,y,z)";
    m.integrator_note = "rigid bodies are integrated on SO(3) by the Lie group variational "
                        "integrator; choose its order with --order 2, 4 or 6";
    m.integrator_parameter = "order";
    using set_type = parameter_set<rigid_parameters>;
    std::vector<set_type::scalar> scalars;
    std::vector<set_type::list> several{
        {&rigid_parameters::inertia,
         inertia_parameter(d.inertia, gravity ? "the pivot" : "the centre of mass")}};
    if (gravity) {
        several.push_back({&rigid_parameters::com,
                           {.name = "com",
                            .value = d.com,
                            .unit = "m",
                            .doc = "centre of mass x,y,z in the body frame, from the pivot"}});
        scalars.push_back({&rigid_parameters::weight,
                           {.name = "weight",
                            .value = d.weight,
                            .unit = "N",
                            .doc = "weight m g",
                            .lower = 0.0}});
    }
    scalars.push_back({&rigid_parameters::order,
                       {.name = "order",
                        .value = 4,
                        .doc = "order of the Lie group integrator: 2, 4 or 6",
                        .lower = 2,
                        .upper = 6,
                        .integer = true}});
    scalars.push_back({&rigid_parameters::matrix,
                       {.name = "matrix",
                        .value = 0,
                        .doc = "also show the attitude matrix R_11..R_33",
                        .lower = 0,
                        .upper = 1,
                        .integer = true,
                        .flag = true}});
    const set_type set(std::move(scalars), std::move(several));
    set.declare(m);
    m.steps_per_period = 100;
    m.time = d.time;
    m.steps = d.steps;
    m.ensemble_time = d.time;
    m.ensemble_steps = d.steps;
    m.make = set.make([d, gravity](const rigid_parameters& par, const start& s) {
        const int order = static_cast<int>(par.order);
        if (order != 2 && order != 4 && order != 6)
            throw std::invalid_argument("order must be 2, 4 or 6, got " + std::to_string(order));
        // An empty com given is d.com, of 3 values.
        if (gravity && par.com.size() != 3)
            throw std::invalid_argument("com needs 3 values (x,y,z of the centre of mass), got " +
                                        std::to_string(par.com.size()));
        const std::vector<double> com = gravity ? par.com : std::vector<double>{0, 0, 0};
        detail::rigid_setup r{lie::rigid_body(inertia_of(par.inertia),
                                              lie::vec3(com[0], com[1], com[2]),
                                              gravity ? par.weight : 0.0),
                              {},
                              order,
                              par.matrix != 0.0,
                              {},
                              {}};
        if (s.v0.size() == 4) throw std::invalid_argument("v0 needs 3 values (Omega), got 4");
        r.x0.R = attitude_of(s.q0, d);
        r.x0.pi = !s.p0.empty() ? lie::vec3(s.p0[0], s.p0[1], s.p0[2])
                  : s.v0.empty()
                      ? lie::vec3(r.body.inertia() * d.omega)
                      : lie::vec3(r.body.inertia() * lie::vec3(s.v0[0], s.v0[1], s.v0[2]));
        if (!std::isfinite(r.body.energy(r.x0)))
            throw std::invalid_argument("the energy of the initial state is not a finite number "
                                        "(check v0/p0, inertia, com and weight)");
        // The closed forms, where they exist, give the period and the exact columns.
        const lie::rigid_body& b = r.body;
        double period = 0.0;
        if (!b.has_gravity() && b.symmetric_about_e3()) {
            r.free.emplace(b, r.x0);
            period = r.free->period();
        } else if (b.has_gravity() && b.symmetric_about_e3() && b.weight() * b.com()(2) > 0.0) {
            try {
                r.nutation.emplace(lie::nutation_of(b, r.x0));
                period = r.nutation->period();
            } catch (const std::invalid_argument&) { // the axis reaches the vertical
            }
        }
        problem pr;
        const auto angles = s.q0.size() == 3 ? std::array<double, 3>{s.q0[0], s.q0[1], s.q0[2]}
                            : s.q0.empty()   ? d.euler
                                             : so3::euler_angles(r.x0.R);
        pr.q0.assign(angles.begin(), angles.end());
        pr.p0.assign(r.x0.pi.data(), r.x0.pi.data() + 3);
        pr.period = period;
        pr.integrator = detail::lgvi_integrator(order);
        pr.simulate = [r](const step_options& o) { return detail::simulate_rigid(r, o); };
        return pr;
    });
    m.drawing = set.drawing([gravity](const rigid_parameters& par) {
        const lie::vec3 c = gravity && par.com.size() == 3
                                ? lie::vec3(par.com[0], par.com[1], par.com[2])
                                : lie::vec3::Zero();
        figure f = rigid_figure(inertia_of(par.inertia), c);
        if (c.norm() == 0.0)
            f.scale = "drawn as the box of uniform density with its inertia, 1 m long";
        return f;
    });
    return m;
}

} // namespace

model rigid_body() {
    // Turning near its intermediate axis: it flips over and back periodically (Dzhanibekov).
    return make_rigid(
        "rigid-body", "free rigid body on SO(3), any inertia (Lie group integrator)",
        "  L = Omega^T J Omega / 2, no potential; J (inertia) about the centre of mass. Default\n"
        "  start: R = I, Omega = (0.01, 1, 0.01) rad/s, near the intermediate axis: the body\n"
        "  flips over and back (the Dzhanibekov effect). Conserved: energy, the spatial angular\n"
        "  momentum L = R Pi (L_x, L_y, L_z) and |Pi| (Pi_norm). Exact where I1 = I2\n"
        "  (attitude_error, rad; period: that of Pi in the body frame); else no period.",
        {{1.0, 2.0, 3.0}, {}, 0.0, {0, 0, 0}, {0.01, 1.0, 0.01}, 100.0, 10000}, false);
}

model top() {
    // The `heavy-top` model's default top and start (tilt 1 rad, φ̇ = 0.5, ψ̇ = 8 rad/s).
    return make_rigid(
        "top", "heavy top on SO(3), any inertia and centre of mass; through the vertical",
        "  L = Omega^T J Omega / 2 - W e3.(R c): the pivot fixed, c = com in the body frame,\n"
        "  W = weight, J (inertia) about the pivot. Default start: the heavy-top model's (Euler\n"
        "  angles 1,0,0; Omega = (0, 0.42, 8.27)). Conserved: energy, L_z (vertical angular\n"
        "  momentum), and Pi_3 (spin) when I1 = I2 and c is on the body's e3. Symmetric tops:\n"
        "  theta (tilt) and theta_exact in closed form, period the nutation period; no\n"
        "  Euler-angle singularity: runs through theta = 0. Else no period.",
        {{1.0, 1.0, 0.5},
         {0, 0, 1.0},
         1.0,
         {1.0, 0, 0},
         so3::body_rate(1.0, 0.0, 0.0, 0.5, 8.0),
         10.0,
         1000},
        true);
}

model pendulum_3d() {
    // A body hanging 1 m below its pivot, tilted and spinning about a skew axis: a 3-D swing.
    return make_rigid(
        "pendulum-3d", "3-D pendulum: a rigid body on a fixed pivot (Lie group integrator)",
        "  The top's equations with its centre of mass below the pivot. Default start: tilted\n"
        "  0.8 rad, Omega = (0.5, 1, 2) rad/s. Conserved: energy, L_z. No period.",
        {{1.5, 1.25, 0.5}, {0, 0, -1.0}, 9.81, {0.8, 0, 0}, {0.5, 1.0, 2.0}, 10.0, 10000}, true);
}

} // namespace varsym::models::defs
