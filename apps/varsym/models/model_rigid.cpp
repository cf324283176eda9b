// apps/varsym/models/model_rigid.cpp: the rigid bodies of `varsym run`, integrated on SO(3) by the Lie
// group variational integrator (lie/lgvi.hpp): `--model rigid-body` (free), `--model top` (heavy
// top, any inertia and centre of mass) and `--model pendulum-3d` (a body hanging from a pivot).
#include <array>
#include <memory>

#include "model_run.hpp"
#include "rigid_run.hpp"

namespace varsym::cli {

namespace {

const char* const rigid_common_description =
    "  State: attitude R (maps body to space; e3 of space points up) and body angular momentum\n"
    "  Pi = J Omega. --q0: Euler angles th,phi,psi (z-x-z, R = Rz(phi) Rx(th) Rz(psi), as in\n"
    "  heavy-top) or a unit quaternion w,x,y,z; --v0: Omega, or --p0: Pi, body frame. --order\n"
    "  2, 4, 6 (4). Columns: step,t,q_w,q_x,q_y,q_z (q_w >= 0),Omega_1..3,energy, then the\n"
    "  conserved quantities, orthogonality (|R^T R - I|), R_11..R_33 with --matrix.";

/// The rigid bodies' own options, shared by the three models (each lists them as its own).
struct rigid_options {
    std::string inertia, com; ///< number lists; empty: the model's default
    double weight = -1.0;     ///< < 0: the model's default
    int order = 4;
    bool matrix = false;
};

/// What differs between the three models.
struct rigid_defaults {
    lie::vec3 inertia, com;
    double weight;
    std::array<double, 3> euler; ///< default --q0: Euler angles (θ, φ, ψ) [rad]
    lie::vec3 omega;             ///< default --v0: body angular velocity Ω [rad/s]
    double time;                 ///< default --time when the motion has no period
    long long steps;             ///< default --steps then
};

lie::mat3 parse_inertia(const std::string& text, const lie::vec3& fallback) {
    const std::vector<double> v = parse_number_list(text);
    if (v.empty()) return fallback.asDiagonal().toDenseMatrix();
    lie::mat3 j = lie::mat3::Zero();
    if (v.size() == 3) {
        j.diagonal() << v[0], v[1], v[2];
    } else if (v.size() == 6) {
        j << v[0], v[3], v[4], v[3], v[1], v[5], v[4], v[5], v[2];
    } else {
        throw usage_error("--inertia needs 3 values (principal moments I1,I2,I3) or 6 (J11,J22,"
                          "J33,J12,J13,J23) [kg m^2], got " +
                          std::to_string(v.size()));
    }
    return j;
}

/// The attitude of --q0: Euler angles (θ, φ, ψ) or a unit quaternion (w, x, y, z).
lie::mat3 initial_attitude(const std::vector<double>& q0, const rigid_defaults& d) {
    if (q0.empty()) return so3::from_euler(d.euler[0], d.euler[1], d.euler[2]);
    if (q0.size() == 3) return so3::from_euler(q0[0], q0[1], q0[2]);
    if (q0.size() == 4) {
        const double n = std::sqrt(q0[0] * q0[0] + q0[1] * q0[1] + q0[2] * q0[2] + q0[3] * q0[3]);
        if (!(std::abs(n - 1.0) <= 1e-6))
            throw usage_error("--q0: a quaternion (w,x,y,z) must have norm 1, got " +
                              std::to_string(n));
        return so3::from_quaternion(q0[0] / n, q0[1] / n, q0[2] / n, q0[3] / n);
    }
    throw usage_error("--q0 needs 3 values (Euler angles th,phi,psi [rad]) or 4 (a unit "
                      "quaternion w,x,y,z), got " +
                      std::to_string(q0.size()));
}

/// The initial state: attitude from --q0, body angular momentum from --p0 or J times --v0 (the
/// body angular velocity), else J times the model's default Ω.
lie::body_state initial_body_state(const run_setup& s, const lie::rigid_body& b,
                                   const rigid_defaults& d) {
    if (!s.p0.empty() && !s.v0.empty()) throw usage_error("give --p0 or --v0, not both");
    lie::body_state x;
    x.R = initial_attitude(s.q0, d);
    if (!s.p0.empty())
        x.pi = initial_vector(s.p0, "--p0", 3, "Pi in the body frame", {});
    else
        x.pi = b.inertia() *
               lie::vec3(initial_vector(s.v0, "--v0", 3, "Omega in the body frame", d.omega));
    return x;
}

model make_rigid_model(const std::string& name, const std::string& summary,
                       const std::string& description, const std::shared_ptr<rigid_options>& opt,
                       const rigid_defaults& d, bool owns_options) {
    model m;
    m.name = name;
    m.summary = summary;
    m.description = description + "\n" + rigid_common_description;
    m.options = {"--inertia", "--order", "--matrix"};
    if (name != "rigid-body") {
        m.options.push_back("--com");
        m.options.push_back("--weight");
    }
    if (owns_options)
        m.add_options = [opt](CLI::App& cmd) {
            cmd.add_option("--inertia", opt->inertia,
                           "rigid bodies: principal moments I1,I2,I3, or J11,J22,J33,J12,J13,J23, "
                           "of inertia about the pivot in the body frame [kg m^2]")
                ->check(number_list)
                ->type_name(list_type_name);
            cmd.add_option("--com", opt->com,
                           "top, pendulum-3d: centre of mass x,y,z in the body frame, from the "
                           "pivot [m]")
                ->check(number_list)
                ->type_name(list_type_name);
            cmd.add_option("--weight", opt->weight, "top, pendulum-3d: weight m g [N]")
                ->transform(non_negative_number);
            cmd.add_option("--order", opt->order,
                           "rigid bodies: order of the Lie group integrator: 2, 4 or 6")
                ->check(CLI::IsMember({2, 4, 6}))
                ->capture_default_str();
            cmd.add_flag("--matrix", opt->matrix,
                         "rigid bodies: also write the attitude matrix R_11..R_33");
        };
    else
        m.add_options = [](CLI::App&) {};
    m.run = [opt, d, name](const run_setup& s) {
        if (s.scheme_given)
            throw usage_error("--scheme and --degree do not apply to --model " + name +
                              ": rigid bodies are integrated on SO(3) by the Lie group "
                              "variational integrator; choose its order with --order 2, 4 or 6");
        const lie::mat3 j = parse_inertia(opt->inertia, d.inertia);
        const lie::vec3 com =
            name == "rigid-body" ? lie::vec3::Zero()
                                 : lie::vec3(initial_vector(parse_number_list(opt->com), "--com", 3,
                                                            "x,y,z of the centre of mass", d.com));
        const double weight = name == "rigid-body" ? 0.0
                              : opt->weight >= 0   ? opt->weight
                                                   : d.weight;
        const lie::rigid_body body = [&] {
            try {
                return lie::rigid_body(j, com, weight);
            } catch (const std::invalid_argument& e) {
                throw usage_error(name + ": " + e.what());
            }
        }();
        run_rigid_body(s, {body, initial_body_state(s, body, d), opt->order, opt->matrix, name},
                       d.time, d.steps);
    };
    return m;
}

} // namespace

std::vector<model> make_rigid_models() {
    auto opt = std::make_shared<rigid_options>();
    // Turning near its intermediate axis: it flips over and back periodically (Dzhanibekov).
    const rigid_defaults free{{1.0, 2.0, 3.0},   {0, 0, 0}, 0.0,  {0, 0, 0},
                              {0.01, 1.0, 0.01}, 100.0,     10000};
    // The `heavy-top` model's default top and start (tilt 1 rad, φ̇ = 0.5, ψ̇ = 8 rad/s).
    const rigid_defaults top{{1.0, 1.0, 0.5},
                             {0, 0, 1.0},
                             1.0,
                             {1.0, 0, 0},
                             so3::body_rate(1.0, 0.0, 0.0, 0.5, 8.0),
                             10.0,
                             1000};
    // A body hanging 1 m below its pivot, tilted and spinning about a skew axis: a 3-D swing.
    const rigid_defaults pendulum{{1.5, 1.25, 0.5}, {0, 0, -1.0}, 9.81, {0.8, 0, 0},
                                  {0.5, 1.0, 2.0},  10.0,         10000};
    return {
        make_rigid_model(
            "rigid-body", "free rigid body on SO(3), any inertia (Lie group integrator)",
            "  L = Omega^T J Omega / 2, no potential. --inertia (1,2,3) [kg m^2] about the centre\n"
            "  of mass. Default start: R = I, Omega = (0.01, 1, 0.01) rad/s, near the "
            "intermediate\n"
            "  axis: the body flips over and back (the Dzhanibekov effect). Conserved: energy, "
            "the\n"
            "  spatial angular momentum L = R Pi (L_x, L_y, L_z) and |Pi| (Pi_norm). Exact where\n"
            "  I1 = I2 (attitude_error, rad; period: that of Pi in the body frame); else no "
            "period:\n"
            "  default --time 100 --steps 10000.",
            opt, free, true),
        make_rigid_model(
            "top", "heavy top on SO(3), any inertia and centre of mass; through the vertical",
            "  L = Omega^T J Omega / 2 - W e3.(R c): the pivot fixed, c = --com in the body frame\n"
            "  (0,0,1) [m], W = --weight (1) [N], --inertia (1,1,0.5) [kg m^2] about the pivot.\n"
            "  Default start: the heavy-top model's (Euler angles 1,0,0; Omega = (0, 0.42, "
            "8.27)).\n"
            "  Conserved: energy, L_z (vertical angular momentum), and Pi_3 (spin) when I1 = I2\n"
            "  and c is on the body's e3. Symmetric tops: theta (tilt) and theta_exact in closed\n"
            "  form, period the nutation period (100 steps each by default); no Euler-angle\n"
            "  singularity: runs through theta = 0. Else default --time 10 --steps 1000.",
            opt, top, false),
        make_rigid_model(
            "pendulum-3d", "3-D pendulum: a rigid body on a fixed pivot (Lie group integrator)",
            "  The top's equations with its centre of mass below the pivot: --com (0,0,-1) [m],\n"
            "  --weight (9.81) [N], --inertia (1.5,1.25,0.5) [kg m^2] about the pivot. Default\n"
            "  start: tilted 0.8 rad, Omega = (0.5, 1, 2) rad/s. Conserved: energy, L_z. No\n"
            "  period: default --time 10 --steps 10000.",
            opt, pendulum, false)};
}

} // namespace varsym::cli
