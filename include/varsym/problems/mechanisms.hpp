// varsym/problems/mechanisms.hpp: closed-loop mechanisms and constrained pendulums, each a
// Lagrangian with its holonomic constraints for general::constrained_stepper
// (schemes/constrained.hpp; docs/mechanisms.md).
//
// Units and conventions: SI (m, kg, s, rad); angles counter-clockwise from the +x axis unless
// said otherwise; gravity g [m/s²] along −y (−z in 3-D). Bars are uniform: a bar of mass m and
// length l has the moment of inertia m l²/12 about its centre, m l²/3 about an end.
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>

#include "varsym/systems/constraints.hpp"
#include "varsym/systems/lagrangian.hpp"

namespace varsym::mechanisms {

inline void require_positive(const char* what, double x) {
    if (!(std::isfinite(x) && x > 0.0))
        throw std::invalid_argument(std::string(what) + " must be a finite positive number, got " +
                                    std::to_string(x));
}
inline void require_gravity(double g) {
    if (!(std::isfinite(g) && g >= 0.0))
        throw std::invalid_argument("gravity must be finite and >= 0, got " + std::to_string(g));
}

/// The planar four-bar linkage: ground pivots A = (0, 0) and D = (ground, 0); crank AB (length
/// a, mass m1) at angle θ1, coupler BC (b, m2) at θ2, rocker DC (c, m3) at θ3. q = (θ1, θ2, θ3)
/// with the loop closed by two constraints: one degree of freedom.
struct four_bar {
    double a = 1.0, b = 3.0, c = 2.5, ground = 3.0; ///< link lengths [m]
    double m1 = 1.0, m2 = 3.0, m3 = 2.5, g = 9.81;

    void validate() const {
        for (auto [what, x] : {std::pair{"crank length", a},
                               {"coupler length", b},
                               {"rocker length", c},
                               {"ground length", ground},
                               {"crank mass", m1},
                               {"coupler mass", m2},
                               {"rocker mass", m3}})
            require_positive(what, x);
        require_gravity(g);
    }

    /// The coupler and rocker angles that close the loop for crank angle θ1 (the assembly with
    /// C above the line BD when `elbow_up`); throws if the links cannot close there.
    [[nodiscard]] vec<3> assemble(double theta1, bool elbow_up = true) const {
        const double bx = a * std::cos(theta1), by = a * std::sin(theta1);
        const double dx = ground - bx, dy = -by, e = std::hypot(dx, dy);
        if (!(e <= b + c && e >= std::abs(b - c)))
            throw std::invalid_argument(
                "the four-bar cannot close at this crank angle (|BD| = " + std::to_string(e) + ")");
        // C on circles |C − B| = b and |C − D| = c: along BD by x, off it by ±y.
        const double x = (b * b - c * c + e * e) / (2 * e), y = std::sqrt(b * b - x * x);
        const double ux = dx / e, uy = dy / e, sgn = elbow_up ? 1.0 : -1.0;
        const double cx = bx + x * ux - sgn * y * uy, cy = by + x * uy + sgn * y * ux;
        return {theta1, std::atan2(cy - by, cx - bx), std::atan2(cy, cx - ground)};
    }
};

/// The loop: A + a e(θ1) + b e(θ2) = D + c e(θ3), e(θ) = (cos θ, sin θ).
struct four_bar_loop {
    static constexpr int dim = 3, count = 2;
    four_bar p;
    template <class T>
    tvec<T, 2> operator()(const tvec<T, 3>& q) const {
        using std::cos, std::sin;
        return tvec<T, 2>(p.a * cos(q(0)) + p.b * cos(q(1)) - p.c * cos(q(2)) - p.ground,
                          p.a * sin(q(0)) + p.b * sin(q(1)) - p.c * sin(q(2)));
    }
};

/// L = T − V: crank and rocker turn about fixed ends, the coupler's centre moves with B.
struct four_bar_lagrangian {
    static constexpr int dim = 3;
    four_bar p;
    template <class T>
    T operator()(const tvec<T, 3>& q, const tvec<T, 3>& v) const {
        using std::cos, std::sin;
        const T s1 = sin(q(0)), c1 = cos(q(0)), s2 = sin(q(1)), c2 = cos(q(1));
        // coupler centre velocity: a θ1' e⊥(θ1) + (b/2) θ2' e⊥(θ2), e⊥(θ) = (−sin θ, cos θ)
        const T vx = -p.a * s1 * v(0) - (0.5 * p.b) * s2 * v(1);
        const T vy = p.a * c1 * v(0) + (0.5 * p.b) * c2 * v(1);
        const T kinetic =
            (p.m1 * p.a * p.a / 6.0) * v(0) * v(0) + 0.5 * p.m2 * (vx * vx + vy * vy) +
            (p.m2 * p.b * p.b / 24.0) * v(1) * v(1) + (p.m3 * p.c * p.c / 6.0) * v(2) * v(2);
        const T potential = p.g * (p.m1 * 0.5 * p.a * s1 + p.m2 * (p.a * s1 + 0.5 * p.b * s2) +
                                   p.m3 * 0.5 * p.c * sin(q(2)));
        return kinetic - potential;
    }
};

/// The rates of a one-degree-of-freedom loop of three coordinates and two constraints (the
/// four-bar, the slider-crank): q̇ with q̇_0 = rate and G(q) q̇ = 0 (tangent to the loop).
template <class C>
vec<3> loop_rates(const C& c, const vec<3>& q, double rate) {
    vec<2> g;
    constraint_jacobian<3, 2> jac;
    evaluate_constraint(c, q, g, jac);
    const vec<2> rest = jac.rightCols<2>().partialPivLu().solve(-jac.col(0) * rate);
    return {rate, rest(0), rest(1)};
}

/// The slider-crank: crank OA (length r, moment of inertia j about O) at angle θ, connecting rod
/// AB (length l, mass m_rod) at angle φ, slider B (mass m_slider) at x on the x axis.
/// q = (θ, φ, x), two constraints closing the loop: one degree of freedom.
struct slider_crank {
    double r = 0.5, l = 1.5, j = 0.1, m_rod = 1.0, m_slider = 2.0, g = 9.81;

    void validate() const {
        for (auto [what, x] : {std::pair{"crank length", r},
                               {"rod length", l},
                               {"crank inertia", j},
                               {"rod mass", m_rod},
                               {"slider mass", m_slider}})
            require_positive(what, x);
        if (!(l > r)) throw std::invalid_argument("the rod must be longer than the crank (l > r)");
        require_gravity(g);
    }

    /// φ and x for crank angle θ (the rod on the +x side of the crank).
    [[nodiscard]] vec<3> assemble(double theta) const {
        const double phi = -std::asin(r * std::sin(theta) / l);
        return {theta, phi, r * std::cos(theta) + l * std::cos(phi)};
    }
};

/// B = A + l e(φ) lies on the x axis at x: r cos θ + l cos φ − x = 0, r sin θ + l sin φ = 0.
struct slider_crank_loop {
    static constexpr int dim = 3, count = 2;
    slider_crank p;
    template <class T>
    tvec<T, 2> operator()(const tvec<T, 3>& q) const {
        using std::cos, std::sin;
        return tvec<T, 2>(p.r * cos(q(0)) + p.l * cos(q(1)) - q(2),
                          p.r * sin(q(0)) + p.l * sin(q(1)));
    }
};

struct slider_crank_lagrangian {
    static constexpr int dim = 3;
    slider_crank p;
    template <class T>
    T operator()(const tvec<T, 3>& q, const tvec<T, 3>& v) const {
        using std::cos, std::sin;
        const T st = sin(q(0)), ct = cos(q(0)), sp = sin(q(1)), cp = cos(q(1));
        const T vx = -p.r * st * v(0) - (0.5 * p.l) * sp * v(1);
        const T vy = p.r * ct * v(0) + (0.5 * p.l) * cp * v(1);
        const T kinetic = (0.5 * p.j) * v(0) * v(0) + 0.5 * p.m_rod * (vx * vx + vy * vy) +
                          (p.m_rod * p.l * p.l / 24.0) * v(1) * v(1) +
                          (0.5 * p.m_slider) * v(2) * v(2);
        const T potential = p.g * p.m_rod * (p.r * st + 0.5 * p.l * sp);
        return kinetic - potential;
    }
};

/// The spherical pendulum in Cartesian coordinates: a point mass m at x ∈ R³ with |x| = ℓ,
/// gravity along −z. Conserved: the energy and the angular momentum about the vertical,
/// x p_y − y p_x.
struct spherical_pendulum {
    double m = 1.0, length = 1.0, g = 9.81;

    void validate() const {
        require_positive("mass", m);
        require_positive("length", length);
        require_gravity(g);
    }

    /// (x, ẋ) at polar angle θ from the downward vertical, azimuth φ, and their rates.
    [[nodiscard]] std::pair<vec<3>, vec<3>> state(double theta, double phi, double theta_dot,
                                                  double phi_dot) const {
        const double st = std::sin(theta), ct = std::cos(theta), sp = std::sin(phi),
                     cp = std::cos(phi);
        const vec<3> x = length * vec<3>{st * cp, st * sp, -ct};
        const vec<3> v = length * vec<3>{ct * cp * theta_dot - st * sp * phi_dot,
                                         ct * sp * theta_dot + st * cp * phi_dot, st * theta_dot};
        return {x, v};
    }
    /// x p_y − y p_x.
    static double spin(const phase_state<3>& x) { return x.q(0) * x.p(1) - x.q(1) * x.p(0); }
};

/// (|x|² − ℓ²)/(2ℓ): zero on the sphere, with a gradient of length 1 there.
struct spherical_rod {
    static constexpr int dim = 3, count = 1;
    spherical_pendulum p;
    template <class T>
    tvec<T, 1> operator()(const tvec<T, 3>& q) const {
        return tvec<T, 1>((q.squaredNorm() - p.length * p.length) / (2.0 * p.length));
    }
};

struct spherical_lagrangian {
    static constexpr int dim = 3;
    spherical_pendulum p;
    template <class T>
    T operator()(const tvec<T, 3>& q, const tvec<T, 3>& v) const {
        return (0.5 * p.m) * v.squaredNorm() - (p.m * p.g) * q(2);
    }
};

} // namespace varsym::mechanisms
