// bench/bench_robots.cpp (`make bench-robots`): URDF robots, varsym against MuJoCo (Debian's
// libmujoco-dev, a benchmark peer only) on the same files, stripped the same way: no contacts,
// no joint limits, no damping (MuJoCo: those constraints and passive forces disabled; varsym:
// --no-damping, and it has no limits or contacts). Sections, each printed as a table:
//   check      M(q) of both at random states (they must agree before anything is compared);
//   steps      ns per step at h = 1 ms, every family member and Simpson against MuJoCo's RK4 and
//              semi-implicit Euler, interleaved over rounds (medians);
//   precision  CPU per simulated second against the error at t = 1 s (a gauss-4 run at
//              h = 1/4000 s as reference), from 1e-3 to 1e-10;
//   energy     the relative energy error over 10⁶ steps of 1 ms (data for docs/figures);
//   scaling    ns per step on a generated chain of 7 to 100 links.
// Usage: varsym_bench_robots [check|steps|precision|energy FILE|scaling]... (default: all but
// energy).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <mujoco/mujoco.h>
#include <tinyxml2.h>

#include "varsym/models/robot.hpp"
#include "varsym/multibody/algorithms.hpp"

namespace {

using namespace varsym;
using clock_type = std::chrono::steady_clock;

/// The URDF at `path` without visual and collision elements (MuJoCo would load their meshes),
/// written to `out`; a <mujoco> compiler block keeps the file's inertias as given.
void strip(const std::string& text, const std::string& out) {
    tinyxml2::XMLDocument doc;
    doc.Parse(text.c_str());
    auto* robot = doc.RootElement();
    for (auto* link = robot->FirstChildElement("link"); link;
         link = link->NextSiblingElement("link"))
        for (const char* tag : {"visual", "collision"})
            while (auto* e = link->FirstChildElement(tag))
                link->DeleteChild(e);
    auto* mj = doc.NewElement("mujoco");
    auto* compiler = doc.NewElement("compiler");
    compiler->SetAttribute("discardvisual", "true");
    compiler->SetAttribute("balanceinertia", "false");
    compiler->SetAttribute("fusestatic", "true");
    mj->InsertEndChild(compiler);
    robot->InsertFirstChild(mj);
    doc.SaveFile(out.c_str());
}

std::string read(const std::string& path) {
    std::ifstream f(path);
    return {std::istreambuf_iterator<char>(f), {}};
}

/// One robot on both sides.
struct pair {
    std::string name;
    std::shared_ptr<const multibody::tree> tree;
    mjModel* mj = nullptr;
};

pair load(const std::string& name, const std::string& text) {
    pair p{name, models::parse_urdf(text, name), nullptr};
    const std::string tmp = "/tmp/varsym_bench_" + name + ".urdf";
    strip(text, tmp);
    char err[1000] = "";
    p.mj = mj_loadXML(tmp.c_str(), nullptr, err, sizeof err);
    if (!p.mj) {
        std::fprintf(stderr, "MuJoCo could not load %s: %s\n", name.c_str(), err);
        std::exit(1);
    }
    p.mj->opt.disableflags |= mjDSBL_CONTACT | mjDSBL_LIMIT | mjDSBL_PASSIVE | mjDSBL_CONSTRAINT;
    p.mj->opt.enableflags |= mjENBL_ENERGY;
    if (p.mj->nv != p.tree->dof()) {
        std::fprintf(stderr, "%s: MuJoCo has %d dofs, varsym %d\n", name.c_str(), p.mj->nv,
                     p.tree->dof());
        std::exit(1);
    }
    return p;
}

/// A chain of n links along alternating y and x axes, 0.3 m, 1 kg each.
std::string chain(int n) {
    std::string s = "<robot name=\"chain" + std::to_string(n) + "\"><link name=\"base\"/>";
    for (int i = 0; i < n; ++i) {
        s += "<link name=\"l" + std::to_string(i) +
             "\"><inertial><origin xyz=\"0 0 -0.15\"/><mass value=\"1\"/><inertia ixx=\"0.008\" "
             "iyy=\"0.008\" izz=\"0.001\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial></link>";
        s += "<joint name=\"j" + std::to_string(i) + "\" type=\"continuous\"><parent link=\"" +
             (i == 0 ? std::string("base") : "l" + std::to_string(i - 1)) + "\"/><child link=\"l" +
             std::to_string(i) + "\"/><origin xyz=\"0 0 " + (i == 0 ? "0" : "-0.3") +
             "\"/><axis xyz=\"" + (i % 2 ? "1 0 0" : "0 1 0") + "\"/></joint>";
    }
    return s + "</robot>";
}

/// A varsym simulation of the robot without damping from q0 at rest.
std::unique_ptr<models::simulation> varsym_run(const pair& p, const scheme_spec& spec, double h,
                                               const std::vector<double>& q0,
                                               iteration_kind iteration = {}) {
    const models::model m = models::robot_model(p.tree);
    std::vector<double> v = m.defaults();
    v[1] = 1.0; // no_damping
    newton_options o;
    o.iteration = iteration;
    return m.prepare(v, {q0, {}, {}}).simulate({spec, o, h});
}

/// MuJoCo's data at q0, at rest, with integrator `kind` and step h.
mjData* mujoco_run(const pair& p, int kind, double h, const std::vector<double>& q0) {
    p.mj->opt.integrator = kind;
    p.mj->opt.timestep = h;
    mjData* d = mj_makeData(p.mj);
    std::copy(q0.begin(), q0.end(), d->qpos);
    mj_forward(p.mj, d);
    return d;
}

std::vector<double> start_of(const pair& p) {
    std::vector<double> q(static_cast<std::size_t>(p.tree->dof()));
    for (std::size_t i = 0; i < q.size(); ++i)
        q[i] = 0.4 + 0.3 * std::sin(1.7 * static_cast<double>(i));
    return q;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

struct method {
    std::string label;
    bool mujoco;
    int kind;
    scheme_spec spec;
    iteration_kind iteration = iteration_kind::automatic; ///< varsym's; automatic is the default
};

std::vector<method> methods() {
    constexpr auto newton = iteration_kind::newton, simplified = iteration_kind::simplified;
    std::vector<method> out{{"mujoco-euler", true, mjINT_EULER, {}},
                            {"mujoco-rk4", true, mjINT_RK4, {}},
                            {"newmark", false, 0, scheme_spec(scheme_kind::newmark), newton},
                            {"simpson", false, 0, scheme_spec(scheme_kind::simpson), newton}};
    for (int s = 1; s <= 4; ++s)
        out.push_back(
            {"gauss-" + std::to_string(s), false, 0, scheme_spec(scheme_kind::gauss, s), newton});
    for (int s = 2; s <= 4; ++s)
        out.push_back({"lobatto-" + std::to_string(s), false, 0,
                       scheme_spec(scheme_kind::lobatto, s), newton});
    // The articulated iteration: the mass term alone, solved in O(n).
    out.push_back(
        {"simpson-art", false, 0, scheme_spec(scheme_kind::simpson), iteration_kind::articulated});
    out.push_back(
        {"gauss-2-art", false, 0, scheme_spec(scheme_kind::gauss, 2), iteration_kind::articulated});
    // The simplified iteration: one Jacobian kept across steps, first derivatives per sweep.
    out.push_back({"simpson-simpl", false, 0, scheme_spec(scheme_kind::simpson), simplified});
    for (int s = 1; s <= 4; ++s)
        out.push_back({"gauss-" + std::to_string(s) + "-simpl", false, 0,
                       scheme_spec(scheme_kind::gauss, s), simplified});
    return out;
}

/// Seconds for `steps` steps of method m from q0 at step h.
double time_steps(const pair& p, const method& m, double h, long steps,
                  const std::vector<double>& q0) {
    if (m.mujoco) {
        mjData* d = mujoco_run(p, m.kind, h, q0);
        const auto t0 = clock_type::now();
        for (long k = 0; k < steps; ++k)
            mj_step(p.mj, d);
        const double s = std::chrono::duration<double>(clock_type::now() - t0).count();
        mj_deleteData(d);
        return s;
    }
    auto sim = varsym_run(p, m.spec, h, q0, m.iteration);
    const auto t0 = clock_type::now();
    sim->advance(static_cast<std::size_t>(steps));
    return std::chrono::duration<double>(clock_type::now() - t0).count();
}

void check(const std::vector<pair>& robots) {
    std::printf("\nM(q) of varsym against MuJoCo's mj_fullM, 5 random states each\n");
    std::mt19937 g(1);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    for (const pair& p : robots) {
        const int n = p.tree->dof();
        double worst = 0.0;
        for (int k = 0; k < 5; ++k) {
            std::vector<double> q(static_cast<std::size_t>(n));
            for (double& x : q)
                x = u(g);
            mjData* d = mujoco_run(p, mjINT_RK4, 1e-3, q);
            std::vector<double> full(static_cast<std::size_t>(n * n));
            mj_fullM(p.mj, full.data(), d->qM);
            mj_deleteData(d);
            multibody::workspace w;
            mat<dynamic> m(n, n);
            multibody::mass_matrix(*p.tree, w, Eigen::Map<const vec<dynamic>>(q.data(), n), m);
            const Eigen::Map<const Eigen::Matrix<double, -1, -1, Eigen::RowMajor>> mm(full.data(),
                                                                                      n, n);
            worst = std::max(worst, (m - mm).cwiseAbs().maxCoeff() / m.cwiseAbs().maxCoeff());
        }
        std::printf("  %-10s %d joints: largest difference %.1e of the largest entry\n",
                    p.name.c_str(), n, worst);
    }
}

void steps(const std::vector<pair>& robots, int rounds) {
    std::printf("\nns per step at h = 1 ms (2000 steps from rest, median of %d interleaved "
                "rounds; ratio to MuJoCo RK4)\n%-14s",
                rounds, "method");
    for (const pair& p : robots)
        std::printf(" %20s", p.name.c_str());
    std::printf("\n");
    const auto all = methods();
    std::vector<std::vector<std::vector<double>>> t(robots.size(),
                                                    std::vector<std::vector<double>>(all.size()));
    for (int r = 0; r < rounds; ++r)
        for (std::size_t i = 0; i < robots.size(); ++i)
            for (std::size_t k = 0; k < all.size(); ++k)
                t[i][k].push_back(time_steps(robots[i], all[k], 1e-3, 2000, start_of(robots[i])) /
                                  2000 * 1e9);
    for (std::size_t k = 0; k < all.size(); ++k) {
        std::printf("%-14s", all[k].label.c_str());
        for (std::size_t i = 0; i < robots.size(); ++i) {
            const double ns = median(t[i][k]), rk4 = median(t[i][1]);
            std::printf(" %12.0f (%4.2fx)", ns, ns / rk4);
        }
        std::printf("\n");
    }
}

/// (q, q̇) after 1 s: q from the run, q̇ = M(q)⁻¹p for varsym.
std::vector<double> final_q(const pair& p, const method& m, double h, double* seconds) {
    const std::vector<double> q0 = start_of(p);
    const auto steps = std::lround(1.0 / h);
    std::vector<double> q(q0.size());
    if (m.mujoco) {
        mjData* d = mujoco_run(p, m.kind, h, q0);
        const auto t0 = clock_type::now();
        for (long k = 0; k < steps; ++k)
            mj_step(p.mj, d);
        *seconds = std::chrono::duration<double>(clock_type::now() - t0).count();
        std::copy(d->qpos, d->qpos + q.size(), q.begin());
        mj_deleteData(d);
        return q;
    }
    auto sim = varsym_run(p, m.spec, h, q0, m.iteration);
    const auto t0 = clock_type::now();
    try {
        sim->advance(static_cast<std::size_t>(steps));
    } catch (const step_failure&) { // Newton diverged: this step is too long for the member
        *seconds = std::chrono::duration<double>(clock_type::now() - t0).count();
        return std::vector<double>(q.size(), std::numeric_limits<double>::infinity());
    }
    *seconds = std::chrono::duration<double>(clock_type::now() - t0).count();
    std::copy(sim->q().begin(), sim->q().end(), q.begin());
    return q;
}

double distance(const std::vector<double>& a, const std::vector<double>& b) {
    double d = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i)
        d = std::max(d, std::abs(a[i] - b[i]));
    return d;
}

void precision(const std::vector<pair>& robots) {
    const double hs[] = {1.0 / 25,  1.0 / 50,   1.0 / 100,  1.0 / 200,  1.0 / 400,
                         1.0 / 800, 1.0 / 1600, 1.0 / 3200, 1.0 / 6400, 1.0 / 12800};
    const char* chosen[] = {"mujoco-euler",  "mujoco-rk4",   "simpson",       "gauss-2",
                            "gauss-3",       "gauss-4",      "simpson-simpl", "gauss-2-simpl",
                            "gauss-3-simpl", "gauss-4-simpl"};
    for (const pair& p : robots) {
        double s = 0.0;
        const auto ref =
            final_q(p, {"gauss-4", false, 0, scheme_spec(scheme_kind::gauss, 4)}, 1.0 / 4000, &s);
        const auto rk = final_q(p, methods()[1], 1.0 / 25600, &s);
        std::printf("\n%s: max |q(1 s) - reference| (gauss-4, h = 1/4000 s; MuJoCo RK4 at "
                    "h = 1/25600 s differs from it by %.1e) and CPU ms per simulated second\n",
                    p.name.c_str(), distance(rk, ref));
        std::vector<std::vector<std::pair<double, double>>> runs; // (error, seconds) per method
        for (const char* label : chosen) {
            const auto all = methods();
            const method& m = *std::find_if(all.begin(), all.end(),
                                            [&](const method& x) { return x.label == label; });
            std::printf("  %-13s", label);
            runs.emplace_back();
            for (double h : hs) {
                double best = 1e300;
                std::vector<double> q;
                for (int r = 0; r < 3; ++r) { // the fastest of three
                    q = final_q(p, m, h, &s);
                    best = std::min(best, s);
                }
                const double e = distance(q, ref);
                runs.back().push_back({e, best});
                std::printf(" %7.1e/%-7.2f", e, best * 1e3);
            }
            std::printf("\n");
        }
        std::printf("  least CPU ms per simulated second reaching each error:\n  %-13s", "error");
        const double targets[] = {1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10};
        for (double t : targets)
            std::printf(" %8.0e", t);
        std::printf("\n");
        for (std::size_t k = 0; k < runs.size(); ++k) {
            std::printf("  %-13s", chosen[k]);
            for (double t : targets) {
                double best = 1e300;
                for (const auto& [e, sec] : runs[k])
                    if (e <= t) best = std::min(best, sec);
                if (best < 1e300)
                    std::printf(" %8.2f", best * 1e3);
                else
                    std::printf(" %8s", "-");
            }
            std::printf("\n");
        }
    }
}

void energy(const pair& p, const std::string& file, long steps) {
    std::ofstream out(file);
    out << "step,t,varsym_gauss2,mujoco_rk4,mujoco_euler\n";
    const std::vector<double> q0 = start_of(p);
    auto sim = varsym_run(p, scheme_spec(scheme_kind::gauss, 2), 1e-3, q0);
    // Two MuJoCo models: the integrator is the model's option, and both step side by side.
    pair euler = p;
    euler.mj = mj_copyModel(nullptr, p.mj);
    mjData* rk = mujoco_run(p, mjINT_RK4, 1e-3, q0);
    mjData* eu = mujoco_run(euler, mjINT_EULER, 1e-3, q0);
    // The energy at the current state: mj_forward recomputes what mj_step left at its last
    // stage (with mjENBL_ENERGY set it fills d->energy: potential, kinetic).
    auto mj_energy = [](const mjModel* m, mjData* d) {
        mj_forward(m, d);
        return d->energy[0] + d->energy[1];
    };
    const double e0 = sim->watched_energy(), r0 = mj_energy(p.mj, rk), u0 = mj_energy(euler.mj, eu);
    double worst[3] = {0, 0, 0};
    for (long k = 0; k <= steps; k += 1000) {
        const double a = (sim->watched_energy() - e0) / std::abs(e0);
        const double b = (mj_energy(p.mj, rk) - r0) / std::abs(r0),
                     c = (mj_energy(euler.mj, eu) - u0) / std::abs(u0);
        worst[0] = std::max(worst[0], std::abs(a));
        worst[1] = std::max(worst[1], std::abs(b));
        worst[2] = std::max(worst[2], std::abs(c));
        out << k << ',' << static_cast<double>(k) * 1e-3 << ',' << a << ',' << b << ',' << c
            << '\n';
        if (k == steps) break;
        sim->advance(static_cast<std::size_t>(k + 1000)); // to step k + 1000
        for (int j = 0; j < 1000; ++j) {
            mj_step(p.mj, rk);
            mj_step(euler.mj, eu);
        }
    }
    std::printf("\n%s, %ld steps of 1 ms: max relative energy error varsym gauss-2 %.1e, MuJoCo "
                "RK4 %.1e, MuJoCo Euler %.1e (rows in %s)\n",
                p.name.c_str(), steps, worst[0], worst[1], worst[2], file.c_str());
    mj_deleteData(rk);
    mj_deleteData(eu);
    mj_deleteModel(euler.mj);
}

void scaling(int rounds) {
    std::printf("\nns per step against the number of links (a generated chain, h = 1 ms, 500 "
                "steps, median of %d interleaved rounds; per link in parentheses)\n%-7s",
                rounds, "links");
    const auto all = methods();
    const auto named = [&](const std::string& label) {
        return *std::find_if(all.begin(), all.end(),
                             [&](const method& x) { return x.label == label; });
    };
    const method chosen[] = {
        named("mujoco-rk4"),
        named("simpson"),
        named("gauss-2"),
        {"simpson-fixed", false, 0, scheme_spec(scheme_kind::simpson), iteration_kind::fixed_point},
        named("simpson-simpl"),
        named("gauss-2-simpl"),
        named("simpson-art"),
        named("gauss-2-art"),
        // The default: Newton or the articulated iteration, step by step, from 10 links.
        {"simpson-auto", false, 0, scheme_spec(scheme_kind::simpson)},
        {"gauss-2-auto", false, 0, scheme_spec(scheme_kind::gauss, 2)}};
    for (const method& m : chosen)
        std::printf(" %24s", m.label.c_str());
    std::printf("\n");
    for (int n : {7, 10, 20, 50, 100}) {
        pair p = load("chain" + std::to_string(n), chain(n));
        std::printf("%-7d", n);
        std::vector<std::vector<double>> t(std::size(chosen));
        for (int r = 0; r < rounds; ++r) // interleaved: every method once per round
            for (std::size_t k = 0; k < std::size(chosen); ++k)
                t[k].push_back(time_steps(p, chosen[k], 1e-3, 500, start_of(p)));
        for (std::size_t k = 0; k < std::size(chosen); ++k) {
            const double ns = median(t[k]) / 500 * 1e9;
            std::printf(" %12.0f (%8.0f)", ns, ns / n);
        }
        std::printf("\n");
        mj_deleteModel(p.mj);
    }
}

} // namespace

int main(int argc, char** argv) {
    const std::string dir = VARSYM_BENCH_DATA "/urdf/";
    std::vector<pair> robots{load("ur5", read(dir + "ur5_robot.urdf")),
                             load("iiwa14", read(dir + "iiwa14_no_collision.urdf")),
                             load("panda9", read(dir + "panda_fingers_free.urdf"))};
    std::vector<std::string> what(argv + 1, argv + argc);
    if (what.empty()) what = {"check", "steps", "precision", "scaling"};
    for (std::size_t a = 0; a < what.size(); ++a) {
        if (what[a] == "check") check(robots);
        if (what[a] == "steps") steps(robots, 5);
        if (what[a] == "precision") precision(robots);
        if (what[a] == "scaling") scaling(3);
        if (what[a] == "energy" && a + 1 < what.size()) energy(robots[0], what[++a], 1000000);
    }
    for (pair& p : robots)
        mj_deleteModel(p.mj);
}
