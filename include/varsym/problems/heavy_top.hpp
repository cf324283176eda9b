// varsym/problems/heavy_top.hpp: the symmetric heavy (Lagrange) top in Euler angles, and the
// closed-form solution of its nutation.
//
// Units and conventions: q = (θ, φ, ψ) [rad]: θ the tilt of the symmetry axis from the upward
// vertical, φ the precession angle, ψ the spin angle. I₁ = I₂ and I₃ are the moments of inertia
// about the fixed point [kg m²], mgl the weight times the distance from the fixed point to the
// centre of mass [J].
//   L = ½I₁(θ̇² + φ̇² sin²θ) + ½I₃(ψ̇ + φ̇ cos θ)² − mgl cos θ
// φ and ψ do not appear in L, so p_φ = ∂L/∂φ̇ and p_ψ = ∂L/∂ψ̇ are conserved, with the energy.
// The Euler angles are singular at θ = 0 and θ = π (the mass matrix is singular there).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

#include <boost/math/special_functions/ellint_1.hpp>
#include <boost/math/special_functions/jacobi_elliptic.hpp>
#include <boost/math/tools/roots.hpp>

#include "varsym/systems/lagrangian.hpp"

namespace varsym::heavy_top {

struct lagrangian {
    static constexpr int dim = 3;
    double i1 = 1.0, i3 = 0.5, mgl = 1.0;

    template <class T>
    T operator()(const tvec<T, 3>& q, const tvec<T, 3>& v) const {
        using std::cos, std::sin;
        const T s = sin(q(0)), c = cos(q(0));
        const T spin = v(2) + v(1) * c;
        return 0.5 * i1 * (v(0) * v(0) + v(1) * v(1) * s * s) + 0.5 * i3 * spin * spin - mgl * c;
    }
};

inline lagrangian_system<lagrangian> make_system(const lagrangian& l) {
    for (auto [what, x] : {std::pair{"I1", l.i1}, std::pair{"I3", l.i3}, std::pair{"mgl", l.mgl}})
        if (!(std::isfinite(x) && x > 0.0))
            throw std::invalid_argument(
                std::string(what) + " must be a finite positive number, got " + std::to_string(x));
    return lagrangian_system<lagrangian>(l);
}

/// θ(t) in closed form. With u = cos θ, the conserved E, p_φ, p_ψ give
///   u̇² = f(u) = (1 − u²)(2E' − 2 mgl u)/I₁ − (p_φ − p_ψ u)²/I₁²,  E' = E − p_ψ²/(2I₃),
/// a cubic with roots u₁ ≤ u₂ in [−1, 1], between which u oscillates, and u₃ > 1:
///   u(t) = u₁ + (u₂ − u₁) sn²(λt + τ₀ | k²),  k² = (u₂ − u₁)/(u₃ − u₁),
///   λ = sqrt(mgl (u₃ − u₁)/(2 I₁)),
/// and the nutation period is 2K(k²)/λ (Goldstein, Classical Mechanics, §5.7).
class nutation {
  public:
    /// From a state (θ, φ, ψ; p_θ, p_φ, p_ψ): θ̇ = p_θ/I₁ and, with φ̇ = (p_φ − p_ψ cos θ)/(I₁
    /// sin²θ),
    ///   E = p_θ²/(2I₁) + (p_φ − p_ψ cos θ)²/(2I₁ sin²θ) + p_ψ²/(2I₃) + mgl cos θ
    /// (by hand: this header then instantiates no automatic derivatives).
    nutation(const lagrangian& l, const phase_state<3>& x0)
        : nutation(l, energy(l, x0), x0.p(1), x0.p(2), x0.q(0), x0.p(0) / l.i1) {}

    /// From the conserved E, p_φ, p_ψ and the tilt θ₀ and its rate θ̇₀ at t = 0.
    nutation(const lagrangian& l, double e, double p_phi, double p_psi, double theta0,
             double theta_dot0) {
        pphi_ = p_phi;
        ppsi_ = p_psi;
        e1_ = e - ppsi_ * ppsi_ / (2.0 * l.i3);
        const double u0 = std::cos(theta0);
        const double du0 = -std::sin(theta0) * theta_dot0;
        // f(u) = c₃u³ + c₂u² + c₁u + c₀; f(1) = −(p_φ − p_ψ)²/I₁² < 0 < f(+∞) brackets u₃ > 1.
        const double i1 = l.i1;
        c3_ = 2.0 * l.mgl / i1;
        c2_ = -2.0 * e1_ / i1 - ppsi_ * ppsi_ / (i1 * i1);
        c1_ = -2.0 * l.mgl / i1 + 2.0 * pphi_ * ppsi_ / (i1 * i1);
        c0_ = 2.0 * e1_ / i1 - pphi_ * pphi_ / (i1 * i1);
        if (!(f(1.0) < 0.0) || !(f(-1.0) < 0.0))
            throw std::invalid_argument(
                "the top's axis reaches the vertical (p_phi = +-p_psi): the "
                "Euler angles are singular there");
        double hi = 2.0;
        while (f(hi) <= 0.0)
            hi *= 2.0;
        std::uintmax_t iterations = 200;
        const auto r = boost::math::tools::toms748_solve(
            [this](double u) { return f(u); }, 1.0, hi, boost::math::tools::eps_tolerance<double>(),
            iterations);
        u3_ = 0.5 * (r.first + r.second);
        // Deflate: f(u) = (u − u₃)(c₃u² + b u + c), then polish the two roots on f itself.
        const double b = c2_ + c3_ * u3_, c = c1_ + b * u3_;
        const double disc = std::max(b * b - 4.0 * c3_ * c, 0.0);
        const double qd = -0.5 * (b + std::copysign(std::sqrt(disc), b));
        double ra = qd / c3_, rb = qd != 0.0 ? c / qd : ra;
        for (double* root : {&ra, &rb})
            for (int it = 0; it < 3; ++it) {
                const double u = *root;
                const double df = (3.0 * c3_ * u + 2.0 * c2_) * u + c1_;
                if (df != 0.0) *root = u - f(u) / df;
            }
        u1_ = std::min(ra, rb);
        u2_ = std::max(ra, rb);
        u0_ = std::clamp(u0, u1_, u2_);
        if (u2_ - u1_ <= 1e-12) {
            steady_ = true; // steady precession: θ stays at θ₀
            u1_ = u2_ = u0;
            return;
        }
        k_ = std::sqrt((u2_ - u1_) / (u3_ - u1_));
        lambda_ = std::sqrt(l.mgl * (u3_ - u1_) / (2.0 * l.i1));
        half_ = boost::math::ellint_1(k_);
        const double s2 = std::clamp((u0_ - u1_) / (u2_ - u1_), 0.0, 1.0);
        tau0_ = boost::math::ellint_1(k_, std::asin(std::sqrt(s2)));
        if (du0 < 0.0) tau0_ = -tau0_; // u̇ = 2(u₂−u₁)λ sn cn dn has the sign of sn on (−K, K)
    }

    [[nodiscard]] double period() const { return steady_ ? 0.0 : 2.0 * half_ / lambda_; }
    [[nodiscard]] double theta_min() const { return std::acos(u2_); }
    [[nodiscard]] double theta_max() const { return std::acos(u1_); }
    [[nodiscard]] double theta(double t) const {
        if (steady_) return std::acos(u1_);
        const double arg = std::fmod(lambda_ * t + tau0_, 2.0 * half_);
        const double sn = boost::math::jacobi_sn(k_, arg);
        return std::acos(std::clamp(u1_ + (u2_ - u1_) * sn * sn, -1.0, 1.0));
    }

  private:
    [[nodiscard]] double f(double u) const { return ((c3_ * u + c2_) * u + c1_) * u + c0_; }
    static double energy(const lagrangian& l, const phase_state<3>& x) {
        const double s = std::sin(x.q(0)), c = std::cos(x.q(0));
        const double a = x.p(1) - x.p(2) * c;
        return x.p(0) * x.p(0) / (2.0 * l.i1) + a * a / (2.0 * l.i1 * s * s) +
               x.p(2) * x.p(2) / (2.0 * l.i3) + l.mgl * c;
    }

    double pphi_ = 0, ppsi_ = 0, e1_ = 0;
    double c0_ = 0, c1_ = 0, c2_ = 0, c3_ = 0;
    double u0_ = 0, u1_ = 0, u2_ = 0, u3_ = 0;
    double k_ = 0, lambda_ = 0, half_ = 0, tau0_ = 0;
    bool steady_ = false;
};

} // namespace varsym::heavy_top
