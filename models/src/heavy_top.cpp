// models/src/heavy_top.cpp: the symmetric heavy (Lagrange) top in Euler angles, with its
// closed-form nutation (varsym/problems/heavy_top.hpp), run by the general engine.
#include <optional>

#include "simulation_of.hpp"
#include "varsym/models/parameters.hpp"
#include "varsym/problems/heavy_top.hpp"

namespace varsym::models::defs {

namespace {

struct heavy_top_parameters {
    double i1, i3, mgl;
};

} // namespace

model heavy_top() {
    model m;
    m.name = "heavy-top";
    m.summary = "symmetric heavy (Lagrange) top in Euler angles, closed-form nutation";
    m.description =
        "  L = I1 (th'^2 + phi'^2 sin^2 th)/2 + I3 (psi' + phi' cos th)^2/2 - mgl cos th\n"
        "  q = (th, phi, psi) [rad]: tilt from the upward vertical, precession, spin. Default\n"
        "  start q0 (1, 0, 0), v0 (0, 0.5, 8) [rad/s]. The Euler angles are singular at th = 0\n"
        "  and pi. Conserved: energy, p_phi, p_psi (exactly: phi and psi are cyclic).\n"
        "  Exact: th(t) in closed form (q_1_exact). Period: the nutation period.";
    m.dim = 3;
    m.coordinates = "th, phi, psi";
    const parameter_set<heavy_top_parameters> set{
        {{&heavy_top_parameters::i1,
          {.name = "I1",
           .value = 1.0,
           .unit = "kg m^2",
           .doc = "moment of inertia about a transverse axis",
           .lower = 0.0,
           .lower_open = true}},
         {&heavy_top_parameters::i3,
          {.name = "I3",
           .value = 0.5,
           .unit = "kg m^2",
           .doc = "moment of inertia about the symmetry axis",
           .lower = 0.0,
           .lower_open = true}},
         {&heavy_top_parameters::mgl,
          {.name = "mgl",
           .value = 1.0,
           .unit = "J",
           .doc = "weight times distance to the centre of mass",
           .lower = 0.0,
           .lower_open = true}}}};
    set.declare(m);
    m.steps_per_period = 100;
    m.time = 10.0;
    m.steps = 1000;
    m.ensemble_time = 20.0;
    m.ensemble_steps = 2000;
    m.make = set.make([](const heavy_top_parameters& par, const start& s) {
        using L = heavy_top::lagrangian;
        const L l{par.i1, par.i3, par.mgl};
        const auto sys = heavy_top::make_system(l);
        const phase_state<3> x0 =
            detail::general_start(sys, s, vec<3>{1.0, 0.0, 0.0}, vec<3>{0.0, 0.5, 8.0});
        std::optional<heavy_top::nutation> nutation;
        std::string no_period;
        try {
            nutation.emplace(l, x0);
        } catch (const std::invalid_argument& e) {
            no_period = e.what();
        }
        problem pr = detail::make_problem(
            x0, nutation ? nutation->period() : 0.0, [=](const step_options& o) {
                detail::check_general(o);
                return detail::simulate_general(
                    general::stepper<L>(sys, o.h, o.spec, o.newton), x0,
                    detail::column_set{
                        {"energy", "p_phi", "p_psi", "q_1_exact"},
                        [sys, nutation](double t, const auto& x, const auto&, double* out) {
                            out[0] = sys.energy(x);
                            out[1] = x.p(1);
                            out[2] = x.p(2);
                            out[3] = nutation ? nutation->theta(t)
                                              : std::numeric_limits<double>::quiet_NaN();
                        }});
            });
        pr.no_period = no_period;
        return pr;
    });
    m.drawing = set.drawing([](const heavy_top_parameters& par) {
        // Only mgl is given, not l: the centre of mass is drawn 1 m up the symmetry axis.
        figure f = rigid_figure(Eigen::Vector3d(par.i1, par.i1, par.i3).asDiagonal(),
                                Eigen::Vector3d(0.0, 0.0, 1.0));
        f.scale = "drawn with its centre of mass 1 m from the pivot (mgl sets only the product)";
        return f;
    });
    return m;
}

} // namespace varsym::models::defs
