// bench/bench_contact.cpp (`make bench-contact`): hard contact with Coulomb friction
// (varsym/contact/stepper.hpp, through the models layer's `urdf` model, --base free --contact)
// against MuJoCo 2.2.2 (Debian's libmujoco-dev, a benchmark peer only): the same bodies, ground
// and h = 1 ms. varsym: gauss-2 (Simpson measured 0.8-0.9 ms a step on the A1 against gauss-2's
// 0.6, with the same penetration and drift), hard contact: no gap below zero at a step's end,
// inelastic impacts, the exact friction cone. MuJoCo: its defaults, Euler and soft contact
// (solref 0.02 1, solimp 0.9 0.95 0.001), condim 3 (its default: sliding friction) on its
// default pyramidal cone and again on the elliptic one. Only bodies against the ground collide
// (MuJoCo: contype/conaffinity); no joint limits (varsym has none). Scenes:
//   box     a 0.2 m cube of 1 kg at rest on a plane inclined at 0.4 rad, friction 0.5 (below
//           the friction angle atan 0.5 = 0.4636: it must stick), 10 s: how far its centre moves
//           along the slope, and the largest penetration;
//   ball    a solid ball of 1 kg, radius 0.1 m, dropped from 0.3 m above its rest height
//           (friction 1): the largest penetration, and |z - r| after 1 s;
//   a1      the Unitree A1 (tests/data/urdf/a1.urdf, free base) under joint PD (kp 80, kd 2,
//           target the start's crouch; MuJoCo: the same law as qfrc_applied), floor friction 1,
//           10 s standing and 10 s dropped from 0.3 m higher: µs per step (interleaved rounds,
//           the median run; the per-step observation excluded), the largest penetration of any
//           of its shapes, the base's drift from 6 to 10 s;
//   tumble  a 0.1 x 0.2 x 0.3 m box of 1 kg spinning about its intermediate axis, no gravity or
//           contact, 10^4 steps: the largest relative change of |angular momentum|.
// Usage: varsym_bench_contact [ROUNDS] (interleaved rounds of the A1 runs, default 5).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <memory>
#include <string>
#include <vector>

#include <mujoco/mujoco.h>
#include <tinyxml2.h>

#include "interleaved.hpp"
#include "varsym/models/robot.hpp"

namespace {

using namespace varsym;
using clock_type = std::chrono::steady_clock;
constexpr double h = 1e-3, slope = 0.4;
const std::string data = VARSYM_BENCH_DATA "/urdf/";

/// One run of a scene: its time (less the observation's), steps, and what it measured.
struct outcome {
    double seconds = 0.0;
    long steps = 0;
    double penetration = 0.0; ///< largest over the run [m]
    double value = 0.0;       ///< the scene's own quantity (creep, height error, drift) [m or 1]
    std::string failure;      ///< a varsym step that failed: its message
    std::vector<double> q;    ///< the end position of a free body
};

double since(clock_type::time_point t0) {
    return std::chrono::duration<double>(clock_type::now() - t0).count();
}

std::string num(double x, const char* f = "%.2e") {
    char b[64];
    std::snprintf(b, sizeof b, f, x);
    return b;
}

// ---- varsym: the models layer's `urdf` model with a free base --------------------------------

/// A simulation of robot t by gauss-2 at h: parameters and lists by name, start s.
std::unique_ptr<models::simulation>
varsym_sim(std::shared_ptr<const multibody::tree> t,
           const std::vector<std::pair<std::string, double>>& set, const models::start& s,
           const std::vector<std::pair<std::string, std::vector<double>>>& lists = {}) {
    const models::model m = models::robot_model(std::move(t));
    std::vector<double> v = m.defaults();
    models::lists l(m.lists.size());
    for (const auto& [name, value] : set)
        for (std::size_t i = 0; i < m.parameters.size(); ++i)
            if (m.parameters[i].name == name) v[i] = value;
    for (const auto& [name, value] : lists)
        for (std::size_t i = 0; i < m.lists.size(); ++i)
            if (m.lists[i].name == name) l[i] = value;
    return m.prepare(v, s, l).simulate({scheme_spec(scheme_kind::gauss, 2), {}, h});
}

int column(const models::simulation& sim, const std::string& name) {
    const auto& c = sim.columns();
    return static_cast<int>(std::find(c.begin(), c.end(), name) - c.begin());
}

/// Steps sim n times; after each, `look` (its time excluded) sees the columns' values.
void varsym_steps(models::simulation& sim, long n, outcome& o,
                  const std::function<void(const std::vector<double>&)>& look) {
    std::vector<double> row(sim.columns().size());
    const int pen = column(sim, "penetration");
    double observed = 0.0;
    const auto t0 = clock_type::now();
    try {
        sim.advance(sim.step() + static_cast<std::size_t>(n), [&] {
            const auto s0 = clock_type::now();
            sim.values(row);
            if (pen < static_cast<int>(row.size()))
                o.penetration = std::max(o.penetration, row[static_cast<std::size_t>(pen)]);
            if (look) look(row);
            observed += since(s0);
            return false;
        });
    } catch (const step_failure& e) {
        o.failure = e.what();
    }
    o.seconds += since(t0) - observed;
    o.steps += n;
}

// ---- MuJoCo ----------------------------------------------------------------------------------

mjModel* mujoco_load(const std::string& xml, const std::string& name) {
    const std::string file = "/tmp/varsym_bench_contact_" + name + ".xml";
    std::ofstream(file) << xml;
    char err[1000] = "";
    mjModel* m = mj_loadXML(file.c_str(), nullptr, err, sizeof err);
    if (!m) {
        std::fprintf(stderr, "MuJoCo could not load %s: %s\n", name.c_str(), err);
        std::exit(1);
    }
    m->opt.timestep = h;
    m->opt.disableflags |= mjDSBL_LIMIT;
    return m;
}

/// A free body of 1 kg (geom `shape`, inertia diagonal `inertia`) over the plane `plane`.
std::string body_scene(const std::string& plane, const std::string& shape,
                       const std::string& inertia, double friction, bool gravity) {
    const std::string f = std::to_string(friction) + " 0.005 0.0001";
    return "<mujoco><option gravity=\"0 0 " + std::string(gravity ? "-9.81" : "0") +
           "\"/><worldbody>" +
           (plane.empty()
                ? ""
                : "<geom type=\"plane\" size=\"0 0 1\" " + plane + " friction=\"" + f + "\"/>") +
           "<body name=\"body\"><freejoint/><inertial pos=\"0 0 0\" "
           "mass=\"1\" diaginertia=\"" +
           inertia + "\"/><geom " + shape + " friction=\"" + f + "\"/></body></worldbody></mujoco>";
}

/// Steps n times, `control` before each step, the contacts observed after it (time excluded):
/// the penetration is MuJoCo's contact distance, negative inside.
void mujoco_steps(const mjModel* m, mjData* d, long n, outcome& o,
                  const std::function<void(mjData*)>& control = {}) {
    double observed = 0.0;
    const auto t0 = clock_type::now();
    for (long k = 0; k < n; ++k) {
        if (control) control(d);
        mj_step(m, d);
        const auto s0 = clock_type::now();
        for (int c = 0; c < d->ncon; ++c)
            o.penetration = std::max(o.penetration, -d->contact[c].dist);
        observed += since(s0);
    }
    o.seconds += since(t0) - observed;
    o.steps += n;
}

// ---- the scenes ------------------------------------------------------------------------------

/// The box's start on the incline (rotated by -slope about y, its bottom face on the plane).
std::vector<double> box_start() {
    return {-std::sin(slope) * 0.1, 0.0, std::cos(slope) * 0.1, std::cos(slope / 2), 0.0,
            -std::sin(slope / 2),   0.0};
}
/// How far the centre moved from c0 to c along the plane (its normal component taken out).
double along_slope(const double* c0, const double* c) {
    const double n[3] = {-std::sin(slope), 0.0, std::cos(slope)};
    double d[3], dn = 0.0;
    for (int i = 0; i < 3; ++i)
        dn += n[i] * (d[i] = c[i] - c0[i]);
    return std::hypot(d[0] - dn * n[0], d[1] - dn * n[1], d[2] - dn * n[2]);
}

/// A free body of 1 kg on a plane in varsym (its URDF, parameters `set`) from q0, n steps.
outcome varsym_body(const std::string& urdf, const std::vector<std::pair<std::string, double>>& set,
                    const std::vector<double>& q0, long n) {
    auto sim =
        varsym_sim(models::load_urdf(data + urdf, multibody::base_kind::free), set, {q0, {}, {}});
    outcome o;
    varsym_steps(*sim, n, o, {});
    o.q.assign(sim->q().begin(), sim->q().end());
    return o;
}

/// The same in MuJoCo (its scene `xml`) on the friction cone `cone`.
outcome mujoco_body(const std::string& xml, const std::vector<double>& q0, long n, int cone) {
    mjModel* m = mujoco_load(xml, "body");
    m->opt.cone = cone;
    mjData* d = mj_makeData(m);
    std::copy(q0.begin(), q0.end(), d->qpos);
    outcome o;
    mujoco_steps(m, d, n, o);
    o.q.assign(d->qpos, d->qpos + 7);
    mj_deleteData(d);
    mj_deleteModel(m);
    return o;
}

// The A1: the start crouch and its PD.
const std::vector<double> legs = {0, 0.8, -1.5, 0, 0.8, -1.5, 0, 0.8, -1.5, 0, 0.8, -1.5};
constexpr double kp = 80.0, kd = 2.0, stance = 0.3135, drop = 0.3;

std::vector<double> a1_start(bool dropped) {
    std::vector<double> q{0, 0, stance + (dropped ? drop : 0.0), 1, 0, 0, 0};
    q.insert(q.end(), legs.begin(), legs.end());
    return q;
}

/// The base's move from 6 to 10 s (value) over a 10 s run.
outcome varsym_a1(const std::shared_ptr<const multibody::tree>& t, bool dropped) {
    auto sim = varsym_sim(t, {{"contact", 1}, {"friction", 1}}, {a1_start(dropped), {}, {}},
                          {{"kp", std::vector<double>(12, kp)},
                           {"kd", std::vector<double>(12, kd)},
                           {"target", legs}});
    outcome o;
    varsym_steps(*sim, 6000, o, {});
    const std::vector<double> at6(sim->q().begin(), sim->q().begin() + 3);
    if (o.failure.empty()) varsym_steps(*sim, 4000, o, {});
    o.value = std::hypot(sim->q()[0] - at6[0], sim->q()[1] - at6[1], sim->q()[2] - at6[2]);
    return o;
}

/// The A1 URDF as MJCF: read by MuJoCo's URDF compiler (visuals discarded, static bodies kept),
/// saved as MJCF (numbers to 6 digits: the masses agree, printed), then a free joint on the root
/// body, static bodies fused, the robot's shapes colliding with the floor only (friction 1).
mjModel* mujoco_a1() {
    tinyxml2::XMLDocument urdf;
    urdf.LoadFile((data + "a1.urdf").c_str());
    for (auto* link = urdf.RootElement()->FirstChildElement("link"); link;
         link = link->NextSiblingElement("link"))
        while (auto* e = link->FirstChildElement("visual"))
            link->DeleteChild(e);
    auto* mj = urdf.NewElement("mujoco");
    auto* compiler = mj->InsertNewChildElement("compiler");
    compiler->SetAttribute("discardvisual", "true");
    compiler->SetAttribute("balanceinertia", "false");
    compiler->SetAttribute("fusestatic", "false");
    urdf.RootElement()->InsertFirstChild(mj);
    urdf.SaveFile("/tmp/varsym_bench_contact_a1.urdf");
    char err[1000] = "";
    mjModel* m0 = mj_loadXML("/tmp/varsym_bench_contact_a1.urdf", nullptr, err, sizeof err);
    if (!m0 || !mj_saveLastXML("/tmp/varsym_bench_contact_a1_0.xml", m0, err, sizeof err)) {
        std::fprintf(stderr, "MuJoCo could not read the A1: %s\n", err);
        std::exit(1);
    }
    mj_deleteModel(m0);
    tinyxml2::XMLDocument doc;
    doc.LoadFile("/tmp/varsym_bench_contact_a1_0.xml");
    const auto add = [&](tinyxml2::XMLElement* parent, const char* tag,
                         std::initializer_list<std::pair<const char*, const char*>> attributes) {
        auto* e = parent->InsertNewChildElement(tag);
        for (const auto& [name, value] : attributes)
            e->SetAttribute(name, value);
        return e;
    };
    auto* root = doc.RootElement();
    root->FirstChildElement("compiler")->SetAttribute("fusestatic", "true");
    add(root->FirstChildElement("default"), "geom", // the saved file sets none of these
        {{"contype", "1"}, {"conaffinity", "0"}, {"friction", "1 0.005 0.0001"}});
    auto* world = root->FirstChildElement("worldbody");
    world->FirstChildElement("body")->InsertFirstChild(doc.NewElement("freejoint"));
    add(world, "geom",
        {{"type", "plane"}, {"size", "0 0 1"}, {"contype", "0"}, {"conaffinity", "1"}});
    tinyxml2::XMLPrinter out;
    doc.Print(&out);
    mjModel* m = mujoco_load(out.CStr(), "a1");
    if (m->nv != 18) {
        std::fprintf(stderr, "MuJoCo's A1 has %d dofs, not 18\n", m->nv);
        std::exit(1);
    }
    return m;
}

outcome mujoco_a1_run(mjModel* m, int cone, bool dropped) {
    m->opt.cone = cone;
    mjData* d = mj_makeData(m);
    const std::vector<double> q0 = a1_start(dropped);
    std::copy(q0.begin(), q0.end(), d->qpos);
    const auto pd = [](mjData* x) {
        for (int i = 0; i < 12; ++i)
            x->qfrc_applied[6 + i] =
                kp * (legs[static_cast<std::size_t>(i)] - x->qpos[7 + i]) - kd * x->qvel[6 + i];
    };
    outcome o;
    mujoco_steps(m, d, 6000, o, pd);
    const std::vector<double> at6(d->qpos, d->qpos + 3);
    mujoco_steps(m, d, 4000, o, pd);
    o.value = std::hypot(d->qpos[0] - at6[0], d->qpos[1] - at6[1], d->qpos[2] - at6[2]);
    mj_deleteData(d);
    return o;
}

// The tumbling box: principal moments of a 0.1 x 0.2 x 0.3 m box of 1 kg, spun about y (the
// intermediate axis) with a small perturbation; body rates [rad/s]. |L| sampled every step.
const double inertia[3] = {(0.04 + 0.09) / 12, (0.01 + 0.09) / 12, (0.01 + 0.04) / 12};
const double spin[3] = {0.05, 4.0, 0.05};
const double l0 = std::hypot(inertia[0] * spin[0], inertia[1] * spin[1], inertia[2] * spin[2]);

outcome varsym_tumble(long n) {
    const std::string urdf = "<robot name=\"tumbler\"><link name=\"box\"><inertial><mass "
                             "value=\"1\"/><inertia ixx=\"" +
                             num(inertia[0], "%.17g") + "\" iyy=\"" + num(inertia[1], "%.17g") +
                             "\" izz=\"" + num(inertia[2], "%.17g") +
                             "\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial></link></robot>";
    // v0 of a free base: the origin's velocity and the quaternion's rate 1/2 q (0, ω_body).
    auto sim = varsym_sim(
        models::parse_urdf(urdf, "tumbler", multibody::base_kind::free), {{"gravity", 0}},
        {{0, 0, 0, 1, 0, 0, 0}, {}, {0, 0, 0, 0, spin[0] / 2, spin[1] / 2, spin[2] / 2}});
    const auto x = static_cast<std::size_t>(column(*sim, "angular_momentum_x"));
    outcome o;
    varsym_steps(*sim, n, o, [&](const std::vector<double>& row) {
        o.value = std::max(o.value, std::abs(std::hypot(row[x], row[x + 1], row[x + 2]) - l0) / l0);
    });
    return o;
}

outcome mujoco_tumble(long n) {
    mjModel* m = mujoco_load(body_scene("", "type=\"box\" size=\"0.05 0.1 0.15\"",
                                        num(inertia[0], "%.17g") + " " + num(inertia[1], "%.17g") +
                                            " " + num(inertia[2], "%.17g"),
                                        1.0, false),
                             "tumble");
    mjData* d = mj_makeData(m);
    std::copy(spin, spin + 3, d->qvel + 3); // a free joint's angular velocity: body frame
    outcome o;
    for (long k = 0; k < n; ++k) {
        mj_step(m, d);
        // |L| about the centre of mass (at rest: about the origin), MuJoCo's subtree_angmom.
        mj_forward(m, d);
        mj_subtreeVel(m, d);
        const double* l = d->subtree_angmom;
        o.value = std::max(o.value, std::abs(std::hypot(l[0], l[1], l[2]) - l0) / l0);
    }
    o.steps = n;
    mj_deleteData(d);
    mj_deleteModel(m);
    return o;
}

// ---- the table -------------------------------------------------------------------------------

void row(const std::string& scene, const std::string& what, const std::string& v,
         const std::string& m, const std::string& e, const std::string& note) {
    std::printf("| %s | %s | %s | %s | %s | %s |\n", scene.c_str(), what.c_str(), v.c_str(),
                m.c_str(), e.c_str(), note.c_str());
}

std::string failed(const outcome& o, const std::string& value) {
    return o.failure.empty() ? value : "FAILED: " + o.failure;
}

} // namespace

int main(int argc, char** argv) {
    const int rounds = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
    std::printf("varsym gauss-2 (hard contact) against MuJoCo %d (Euler, soft contact, condim 3; "
                "pyramidal and elliptic cones), h = 1 ms\n",
                mj_version());
    // The box: its scene (the plane and the box turned by -slope about y), creep along the slope.
    const std::string turn = "quat=\"" + num(std::cos(-slope / 2), "%.17g") + " 0 " +
                             num(std::sin(-slope / 2), "%.17g") + " 0\"",
                      sixth = num(0.2 * 0.2 / 6, "%.17g");
    const std::string box = body_scene(turn, "type=\"box\" size=\"0.1 0.1 0.1\"",
                                       sixth + " " + sixth + " " + sixth, 0.5, true);
    const std::vector<double> q0 = box_start();
    outcome vb = varsym_body("contact_box.urdf",
                             {{"contact", 1}, {"friction", 0.5}, {"ground_slope", slope}}, q0,
                             10000),
            mb = mujoco_body(box, q0, 10000, mjCONE_PYRAMIDAL),
            eb = mujoco_body(box, q0, 10000, mjCONE_ELLIPTIC);
    for (outcome* o : {&vb, &mb, &eb})
        o->value = along_slope(q0.data(), o->q.data());
    // The ball, dropped from z = 0.4: |z - r| at the end.
    const std::string ball =
        body_scene("pos=\"0 0 0\"", "type=\"sphere\" size=\"0.1\"", "0.004 0.004 0.004", 1.0, true);
    const std::vector<double> b0{0, 0, 0.4, 1, 0, 0, 0};
    outcome vl = varsym_body("contact_ball.urdf", {{"contact", 1}, {"friction", 1}}, b0, 1000),
            ml = mujoco_body(ball, b0, 1000, mjCONE_PYRAMIDAL),
            el = mujoco_body(ball, b0, 1000, mjCONE_ELLIPTIC);
    for (outcome* o : {&vl, &ml, &el})
        o->value = std::abs(o->q[2] - 0.1);
    const outcome vt = varsym_tumble(10000), mt = mujoco_tumble(10000);

    // The A1 runs, interleaved: every case once per round, the median run's time kept.
    const auto a1 = models::load_urdf(data + "a1.urdf", multibody::base_kind::free);
    mjModel* ma1 = mujoco_a1();
    // The same robot on both sides: its mass and shapes (varsym: with the base fixed, the root
    // link's merged mass and the bodies').
    const auto fixed = models::load_urdf(data + "a1.urdf");
    double mass = fixed->root.mass;
    for (const multibody::body& b : fixed->bodies)
        mass += b.mass;
    std::printf("A1: varsym %.4f kg, %zu shapes; MuJoCo %.4f kg, %d shapes and the floor\n", mass,
                fixed->collisions.size(), mj_getTotalmass(ma1), ma1->ngeom - 1);
    std::vector<std::function<outcome()>> cases;
    for (const bool dropped : {false, true}) {
        cases.push_back([&a1, dropped] { return varsym_a1(a1, dropped); });
        for (const int cone : {mjCONE_PYRAMIDAL, mjCONE_ELLIPTIC})
            cases.push_back([ma1, cone, dropped] { return mujoco_a1_run(ma1, cone, dropped); });
    }
    std::fprintf(stderr, "A1: %d interleaved rounds of %zu runs of 10 s...\n", rounds,
                 cases.size());
    const std::vector<outcome> r = bench::interleaved(cases, rounds);
    mj_deleteModel(ma1);

    std::printf("\n| scene | quantity | varsym gauss-2 | MuJoCo pyramidal | MuJoCo elliptic | "
                "ratio varsym/MuJoCo (pyramidal) or target |\n|---|---|---|---|---|---|\n");
    row("box on 0.4 rad incline, mu 0.5", "creep along the slope over 10 s [m]",
        failed(vb, num(vb.value)), num(mb.value), num(eb.value), "target < 1e-6");
    row("box on 0.4 rad incline, mu 0.5", "largest penetration [m]", num(vb.penetration),
        num(mb.penetration), num(eb.penetration), "target < 1e-6");
    row("ball dropped 0.3 m", "largest penetration [m]", failed(vl, num(vl.penetration)),
        num(ml.penetration), num(el.penetration), "target < 1e-6");
    row("ball dropped 0.3 m", "\\|z - r\\| at 1 s [m]", num(vl.value), num(ml.value), num(el.value),
        "");
    for (int k = 0; k < 2; ++k) {
        const outcome &v = r[3 * k], &p = r[3 * k + 1], &e = r[3 * k + 2];
        const std::string scene = k == 0 ? "A1 standing, PD, 10 s" : "A1 dropped 0.3 m, PD, 10 s";
        const auto us = [](const outcome& o) { return o.seconds / double(o.steps) * 1e6; };
        row(scene, "cost per step [µs] (median of " + std::to_string(rounds) + ")",
            failed(v, num(us(v), "%.1f")), num(us(p), "%.1f"), num(us(e), "%.1f"),
            num(us(v) / us(p), "%.1fx") + " (target <= 3x)");
        row(scene, "largest penetration [m]", num(v.penetration), num(p.penetration),
            num(e.penetration), "target < 1e-6");
        row(scene, "base drift, 6 to 10 s [m]", num(v.value), num(p.value), num(e.value), "");
    }
    row("tumbling box, no gravity, 10^4 steps", "max relative drift of \\|L\\|",
        failed(vt, num(vt.value)), num(mt.value), "", "");
}
