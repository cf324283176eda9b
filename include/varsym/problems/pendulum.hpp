// varsym/problems/pendulum.hpp: the nonlinear pendulum V(q) = m ω² (1 − cos q) of the paper and
// its exact solution by Jacobi elliptic functions (paper Annex), for any initial (q₀, p₀).
//
// Units and conventions: q is the angle from the downward vertical [rad], t is time [s], ω is
// the small-oscillation angular frequency [rad/s], m is the moment of inertia about the pivot
// (for a point mass M on a massless rod of length ℓ: m = M ℓ² [kg m²], ω² = g/ℓ) and
// p = m dq/dt is the angular momentum [kg m² s⁻¹]. The energy is H = p²/(2m) + V(q) [J].
#pragma once

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include <boost/math/special_functions/ellint_1.hpp>
#include <boost/math/special_functions/jacobi_elliptic.hpp>

#include "varsym/systems/separable.hpp"

namespace varsym::pendulum {

/// V(q) = m ω² (1 − cos q), written 2 m ω² sin²(q/2) to keep its accuracy near q = 0.
struct potential {
    double m;
    double omega;
    [[nodiscard]] double value(const vec<1>& q) const {
        const double s = std::sin(0.5 * q(0));
        return 2.0 * m * omega * omega * s * s;
    }
    [[nodiscard]] vec<1> gradient(const vec<1>& q) const {
        return vec<1>{m * omega * omega * std::sin(q(0))};
    }
    [[nodiscard]] mat<1> hessian(const vec<1>& q) const {
        return mat<1>{m * omega * omega * std::cos(q(0))};
    }
};

using system = separable_system<1, potential>;

inline void require_positive(const char* what, double x) {
    if (!(std::isfinite(x) && x > 0.0))
        throw std::invalid_argument(std::string(what) + " must be a finite positive number, got " +
                                    std::to_string(x));
}

/// The pendulum of moment of inertia m and small-oscillation frequency ω (both > 0).
inline system make_system(double m, double omega) {
    require_positive("mass", m);
    require_positive("omega", omega);
    return system(mat<1>{m}, potential{m, omega});
}

/// The three kinds of motion the exact solution covers. The separatrix E = 2mω² between
/// libration and rotation is refused: it has no period (the top is reached in infinite time).
enum class regime { rest, libration, rotation };

/// Exact solution q(t), p(t) from q(0) = q₀, p(0) = p₀. With k² = E/(2mω²):
///  - libration (k < 1): sin(q/2) = k sn(ωt + u₀ | k²), p = 2mωk cn(ωt + u₀ | k²),
///    u₀ = F(φ₀ | k²), sin φ₀ = sin(q₀/2)/k, cos φ₀ = p₀/(2mωk); period T = 4K(k²)/ω
///    (paper eqs. temps and periode);
///  - rotation (k > 1), κ = 1/k, s = sign p₀: q = 2s am(kωt + u₀ | κ²), p = 2smωk dn(kωt + u₀ |
///  κ²),
///    u₀ = F(s q₀/2 | κ²); period (one revolution) T = 2K(κ²)/(kω);
///  - rest (k = 0): q ≡ q₀, p ≡ 0; the period reported is the linear one, 2π/ω.
/// Boost.Math takes the modulus k (not the parameter m = k² of the paper's K(m), F(φ, m)).
/// dn is computed as sqrt(1 − k² sn²) (k < 1 in both regimes), not taken from Boost: Boost
/// 1.74's jacobi_elliptic returns dn(K | 1/2) = 0.70772 instead of 1/√2 = 0.70711 exactly at
/// the turning points u = K, 3K (tests/problems/test_pendulum_exact.cpp holds this).
/// The scalar type Real is double for the library; long double gives a reference with ~3 more
/// digits for measuring high orders (tests/numeric/test_family_orders.cpp).
template <class Real>
class basic_exact_solution {
  public:
    struct point {
        Real q, p;
    };

    basic_exact_solution(Real m, Real omega, Real q0, Real p0) : m_(m), omega_(omega) {
        using std::abs, std::sqrt, std::sin, std::atan2, std::round, std::isfinite;
        require_positive("mass", static_cast<double>(m));
        require_positive("omega", static_cast<double>(omega));
        if (!isfinite(q0) || !isfinite(p0))
            throw std::invalid_argument("initial q0 and p0 must be finite");
        const Real pi = std::numbers::pi_v<Real>;
        shift_ = 2 * pi * round(q0 / (2 * pi)); // V is 2π-periodic: solve from q₀ ∈ [−π, π]
        const Real half = (q0 - shift_) / 2;
        const Real s = sin(half);
        const Real c = p0 / (2 * m * omega);
        k2_ = s * s + c * c; // E/(2mω²) = sin²(q/2) + (p/(2mω))²
        k_ = sqrt(k2_);
        if (abs(k2_ - 1) <= Real(1e-12))
            throw std::invalid_argument(
                "initial state is on the separatrix (energy 2 m omega^2): the pendulum takes "
                "infinite time to reach the top, so there is no period; change q0 or p0");
        if (k2_ == 0) {
            kind_ = regime::rest;
            period_ = 2 * pi / omega;
            q_rest_ = q0;
        } else if (k2_ < 1) {
            kind_ = regime::libration;
            quarter_ = boost::math::ellint_1(k_); // K(k²), modulus k
            u0_ = boost::math::ellint_1(k_, atan2(s, c));
            period_ = 4 * quarter_ / omega; // eq. periode
        } else {
            kind_ = regime::rotation;
            sign_ = p0 >= 0 ? 1 : -1;
            kappa_ = 1 / k_;
            quarter_ = boost::math::ellint_1(kappa_); // K(κ²), modulus κ
            u0_ = boost::math::ellint_1(kappa_, sign_ * half);
            period_ = 2 * quarter_ / (k_ * omega);
        }
    }

    [[nodiscard]] regime kind() const { return kind_; }
    /// Period of the motion [s]: libration 4K(k²)/ω, rotation 2K(1/k²)/(kω), rest 2π/ω.
    [[nodiscard]] Real period() const { return period_; }
    /// Energy H = p²/(2m) + m ω² (1 − cos q) = 2 m ω² k² [J].
    [[nodiscard]] Real energy() const { return 2 * m_ * omega_ * omega_ * k2_; }
    /// k = sqrt(E/(2mω²)): the elliptic modulus in libration (k < 1).
    [[nodiscard]] Real modulus() const { return k_; }

    [[nodiscard]] point state(Real t) const {
        using std::asin, std::atan2, std::floor, std::fmod, std::sqrt;
        const Real pi = std::numbers::pi_v<Real>;
        Real cn = 0;
        switch (kind_) {
        case regime::rest:
            return {q_rest_, 0};
        case regime::libration: {
            // Reduce the argument modulo the period 4K of sn, cn to keep long times accurate.
            const Real u = fmod(omega_ * t + u0_, 4 * quarter_);
            const Real sn = boost::math::jacobi_elliptic(k_, u, &cn, static_cast<Real*>(nullptr));
            // sin(q/2) = k sn (paper Annex), p = m dq/dt = 2 m ω k cn
            return {shift_ + 2 * asin(k_ * sn), 2 * m_ * omega_ * k_ * cn};
        }
        case regime::rotation: {
            // am(u) = atan2(sn, cn) on [−K, K), plus π for each half-period 2K.
            const Real u = k_ * omega_ * t + u0_;
            const Real n = floor((u + quarter_) / (2 * quarter_));
            const Real ur = u - 2 * quarter_ * n;
            const Real sn =
                boost::math::jacobi_elliptic(kappa_, ur, &cn, static_cast<Real*>(nullptr));
            const Real dn = sqrt(1 - kappa_ * kappa_ * sn * sn);
            const Real am = atan2(sn, cn) + n * pi;
            return {shift_ + sign_ * 2 * am, sign_ * 2 * m_ * omega_ * k_ * dn};
        }
        }
        return {}; // unreachable
    }

    /// state(t) as a phase-space state in double precision.
    [[nodiscard]] phase_state<1> at(Real t) const {
        const point x = state(t);
        return {vec<1>{static_cast<double>(x.q)}, vec<1>{static_cast<double>(x.p)}};
    }

  private:
    Real m_, omega_;
    Real k2_ = 0, k_ = 0, kappa_ = 0;
    Real quarter_ = 0, u0_ = 0, period_ = 0;
    Real shift_ = 0, sign_ = 1, q_rest_ = 0;
    regime kind_ = regime::rest;
};

/// The exact solution in double precision (at(t) gives phase-space states).
using exact_solution = basic_exact_solution<double>;

} // namespace varsym::pendulum
