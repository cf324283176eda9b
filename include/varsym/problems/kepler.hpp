// varsym/problems/kepler.hpp: the planar two-body (Kepler) problem in relative coordinates and
// its exact solution through Kepler's equation.
//
// Units and conventions: q = (x, y) is the position of one body relative to the other, t the
// time, μ = G (m₁ + m₂) the gravitational parameter; the Lagrangian is per unit reduced mass,
// L = ½|q̇|² + μ/|q|, so p = q̇, the energy is E = ½|p|² − μ/|q| = −μ/(2a) and the angular
// momentum is ℓ = x p_y − y p_x. The orbit starts at pericentre (a(1 − e), 0) moving
// counter-clockwise; its period is T = 2π sqrt(a³/μ).
#pragma once

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "varsym/systems/lagrangian.hpp"
#include "varsym/systems/separable.hpp"

namespace varsym::kepler {

/// V(q) = −μ/|q|.
struct potential {
    double mu = 1.0;
    [[nodiscard]] double value(const vec<2>& q) const { return -mu / q.norm(); }
    [[nodiscard]] vec<2> gradient(const vec<2>& q) const {
        const double r = q.norm();
        return (mu / (r * r * r)) * q;
    }
    /// ∇²V = μ (I/r³ − 3 q qᵀ/r⁵)
    [[nodiscard]] mat<2> hessian(const vec<2>& q) const {
        const double r = q.norm(), r3 = r * r * r;
        return (mu / r3) * (mat<2>::Identity() - (3.0 / (r * r)) * q * q.transpose());
    }
};

using system = separable_system<2, potential>;

inline system make_system(double mu = 1.0) {
    if (!(std::isfinite(mu) && mu > 0.0))
        throw std::invalid_argument("mu must be a finite positive number, got " +
                                    std::to_string(mu));
    return system(mat<2>::Identity(), potential{mu});
}

/// The same system written as a Lagrangian for the general engine (tests compare the two).
struct lagrangian {
    static constexpr int dim = 2;
    double mu = 1.0;
    template <class T>
    T operator()(const tvec<T, 2>& q, const tvec<T, 2>& v) const {
        using std::sqrt;
        return 0.5 * v.squaredNorm() + mu / sqrt(q.squaredNorm());
    }
};

/// ℓ = x p_y − y p_x: conserved (rotations are a symmetry of L; discrete Noether).
inline double angular_momentum(const phase_state<2>& x) {
    return x.q(0) * x.p(1) - x.q(1) * x.p(0);
}

/// The Keplerian ellipse of eccentricity 0 ≤ e < 1 and semi-major axis a > 0, from pericentre.
class orbit {
  public:
    orbit(double eccentricity, double semi_major_axis, double mu = 1.0)
        : e_(eccentricity), a_(semi_major_axis), mu_(mu) {
        if (!(std::isfinite(e_) && e_ >= 0.0 && e_ < 1.0))
            throw std::invalid_argument("eccentricity must be in [0, 1) (a bound orbit), got " +
                                        std::to_string(e_));
        if (!(std::isfinite(a_) && a_ > 0.0))
            throw std::invalid_argument("semi-major axis must be a finite positive number, got " +
                                        std::to_string(a_));
        if (!(std::isfinite(mu_) && mu_ > 0.0))
            throw std::invalid_argument("mu must be a finite positive number, got " +
                                        std::to_string(mu_));
        b_ = a_ * std::sqrt((1.0 - e_) * (1.0 + e_));
        n_ = std::sqrt(mu_ / (a_ * a_ * a_));
    }

    [[nodiscard]] double period() const { return 2.0 * std::numbers::pi / n_; }
    [[nodiscard]] double energy() const { return -mu_ / (2.0 * a_); }
    [[nodiscard]] double angular_momentum() const { return std::sqrt(mu_ * a_) * b_ / a_; }
    [[nodiscard]] double eccentricity() const { return e_; }

    /// Position and momentum at time t: mean anomaly M = n t, eccentric anomaly E from Kepler's
    /// equation E − e sin E = M, then x = a (cos E − e), y = b sin E and their time derivatives
    /// (dE/dt = n / (1 − e cos E)). M is reduced modulo 2π in long double, so a time given in
    /// long double (e.g. n h of a long run, which double would round) is kept to ~1e-19.
    [[nodiscard]] phase_state<2> at(long double t) const {
        using LD = long double;
        const double mean =
            static_cast<double>(std::fmod(static_cast<LD>(n_) * t, 2 * std::numbers::pi_v<LD>));
        const double ecc = eccentric_anomaly(mean);
        const double c = std::cos(ecc), s = std::sin(ecc);
        const double rate = n_ / (1.0 - e_ * c);
        return {vec<2>{a_ * (c - e_), b_ * s}, vec<2>{0.0 - a_ * s * rate, b_ * c * rate}}; // no −0
    }

  private:
    /// Newton on f(E) = E − e sin E − M from E = M + e sin M (or π for e > 0.8), which converges
    /// monotonically for all e < 1; stops when the update is at round-off.
    [[nodiscard]] double eccentric_anomaly(double mean) const {
        double ecc = e_ > 0.8 ? std::numbers::pi : mean + e_ * std::sin(mean);
        for (int i = 0; i < 60; ++i) {
            const double f = ecc - e_ * std::sin(ecc) - mean;
            const double step = f / (1.0 - e_ * std::cos(ecc));
            ecc -= step;
            if (std::abs(step) <= 1e-16 * std::max(1.0, std::abs(ecc))) break;
        }
        return ecc;
    }

    double e_, a_, mu_, b_ = 0.0, n_ = 0.0;
};

} // namespace varsym::kepler
