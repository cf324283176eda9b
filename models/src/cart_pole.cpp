// models/src/cart_pole.cpp: the cart-pole, an underactuated system: a cart on a horizontal
// rail pushed by a force u, carrying a pole on a frictionless pivot. Run by the general engine
// with the control as a generalized force on the cart's coordinate x (systems/forcing.hpp).
//
// Units and conventions: q = (x, th): the cart's position [m] and the pole's angle from the
// upward vertical [rad], positive in the direction of +x. M the cart's mass, m the pole's, l the
// distance from the pivot to the pole's centre of mass, I the pole's moment of inertia about its
// centre of mass (a uniform rod of length 2l: m l^2/3).
//   L = (M+m) x'^2/2 + m l cos(th) x' th' + (m l^2 + I) th'^2/2 - m g l cos(th),
// with the generalized force (u, 0). These are the equations of Barto, Sutton & Anderson (1983)
// as corrected by Florian (2007) for a uniform pole (docs/models.md).
#include <cmath>

#include "simulation_of.hpp"
#include "varsym/models/parameters.hpp"
#include "varsym/optimal/input_system.hpp"

namespace varsym::models::defs {

namespace {

struct cart_pole_lagrangian {
    static constexpr int dim = 2;
    double cart = 1.0, pole = 0.1, l = 0.5, inertia = 0.1 * 0.5 * 0.5 / 3.0, g = 9.81;

    template <class T>
    T operator()(const tvec<T, 2>& q, const tvec<T, 2>& v) const {
        using std::cos;
        const T c = cos(q(1));
        return 0.5 * (cart + pole) * v(0) * v(0) + pole * l * c * v(0) * v(1) +
               0.5 * (pole * l * l + inertia) * v(1) * v(1) - pole * g * l * c;
    }
};

/// The push u on the cart: the generalized force (u, 0).
struct push_on_cart {
    static constexpr int dim = 2, controls = 1;
    template <class T>
    tvec<T, 2> operator()(const tvec<T, 2>&, const tvec<T, 2>&, double, const tvec<T, 1>& u) const {
        return tvec<T, 2>(u(0), T(0.0));
    }
};

struct cart_pole_parameters {
    double cart_mass, pole_mass, pole_length, pole_inertia, gravity, push;
};

cart_pole_lagrangian lagrangian(const cart_pole_parameters& p) {
    return {p.cart_mass, p.pole_mass, p.pole_length, p.pole_inertia, p.gravity};
}

} // namespace

model cart_pole() {
    model m;
    m.name = "cart-pole";
    m.summary = "cart-pole: a pole on a cart pushed by a force u (underactuated)";
    m.description =
        "  L = (M+m) x'^2/2 + m l cos(th) x' th' + (m l^2 + I) th'^2/2 - m g l cos(th), with the\n"
        "  force u on the cart. q = (x [m], th [rad] from the upward vertical); p = (p_x, p_th).\n"
        "  Default start: the pole 0.1 rad from upright, at rest (it falls). Conserved: energy\n"
        "  with u = 0, else E - W (work column); p_x grows by u t exactly (x is cyclic). No\n"
        "  exact solution, no period.";
    m.dim = 2;
    m.coordinates = "x, th";
    const cart_pole_lagrangian l0;
    const parameter_set<cart_pole_parameters> set{
        {{&cart_pole_parameters::cart_mass,
          {.name = "cart_mass",
           .value = l0.cart,
           .unit = "kg",
           .doc = "mass M of the cart",
           .lower = 0.0,
           .lower_open = true}},
         {&cart_pole_parameters::pole_mass,
          {.name = "pole_mass",
           .value = l0.pole,
           .unit = "kg",
           .doc = "mass m of the pole",
           .lower = 0.0,
           .lower_open = true}},
         {&cart_pole_parameters::pole_length,
          {.name = "pole_length",
           .value = l0.l,
           .unit = "m",
           .doc = "distance l from the pivot to the pole's centre of mass",
           .lower = 0.0,
           .lower_open = true}},
         {&cart_pole_parameters::pole_inertia,
          {.name = "pole_inertia",
           .value = l0.inertia,
           .unit = "kg m^2",
           .doc = "pole's moment of inertia I about its centre of mass",
           .lower = 0.0}},
         {&cart_pole_parameters::gravity,
          {.name = "gravity", .value = l0.g, .unit = "m/s^2", .doc = "gravity g", .lower = 0.0}},
         {&cart_pole_parameters::push,
          {.name = "push",
           .value = 0.0,
           .unit = "N",
           .doc = "constant horizontal push u on the cart"}}}};
    set.declare(m);
    m.time = 5.0;
    m.steps = 5000;
    m.ensemble_time = 5.0;
    m.ensemble_steps = 2500;
    m.ensemble_note = "The pole falls over: --event 'q2^2 - 2.4649' (|th| reaches 1.57).";
    m.make = set.make([](const cart_pole_parameters& p, const start& s) {
        using L = cart_pole_lagrangian;
        const auto sys = lagrangian_system<L>(lagrangian(p));
        return detail::controlled_problem<L, push_on_cart>(
            sys, p.push, detail::general_start(sys, s, vec<2>{0.0, 0.1}, vec<2>(vec<2>::Zero())));
    });
    m.pose = set.pose([](const cart_pole_parameters& p, std::span<const double> q) {
        // The pole drawn uniform: twice the pivot-to-centre length.
        const double l = 2.0 * p.pole_length;
        return std::vector<double>{
            q[0] - 0.25,       0.0, q[0] + 0.25, 0.0, q[0], 0.0, q[0] + l * std::sin(q[1]),
            l * std::cos(q[1])};
    });
    m.controls = {"u [N]: horizontal push on the cart"};
    m.simulation_only = {"push"};
    m.control = set.control([](const cart_pole_parameters& p) { // the push on x: f = (u, 0)
        return std::make_shared<const optimal::input_system<cart_pole_lagrangian>>(
            lagrangian(p), optimal::matrix{{1.0}, {0.0}});
    });
    return m;
}

} // namespace varsym::models::defs
