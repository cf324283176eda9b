// varsym/quadrature/rules.hpp: Gauss–Legendre and Gauss–Lobatto quadrature on [0, 1], nodes
// computed to full double precision by Newton's method on the Legendre polynomials.
#pragma once

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace varsym::quadrature {

/// ∫₀¹ f ≈ Σ_k weights[k] f(nodes[k]); nodes increasing. Real is double, or long double for
/// tables computed with extra digits before rounding them to double.
template <class Real = double>
struct basic_rule {
    std::vector<Real> nodes;
    std::vector<Real> weights;
    [[nodiscard]] std::size_t size() const { return nodes.size(); }
};
using rule = basic_rule<double>;

/// P_n(x) and P_n'(x) on [−1, 1] by the three-term recurrence
/// (k+1) P_{k+1} = (2k+1) x P_k − k P_{k−1}, and P_n' = n (x P_n − P_{n−1}) / (x² − 1).
template <class Real>
struct legendre_value {
    Real p, dp, p_prev;
};
template <class Real>
legendre_value<Real> legendre(int n, Real x) {
    Real p0 = 1, p1 = x;
    if (n == 0) return {1, 0, 0};
    for (int k = 1; k < n; ++k) {
        const Real p2 = ((2 * k + 1) * x * p1 - k * p0) / (k + 1);
        p0 = p1;
        p1 = p2;
    }
    using std::abs, std::pow;
    const Real dp = abs(x * x - 1) > 0 ? n * (x * p1 - p0) / (x * x - 1)
                                       : Real(0.5) * n * (n + 1) * pow(x, n + 1);
    return {p1, dp, p0};
}

namespace detail {
// Maps a rule on [−1, 1] with decreasing nodes (cosine initial guesses) to [0, 1]
// (x ↦ (1 − x)/2, w ↦ w/2), made exactly symmetric: c_{n−1−i} = 1 − c_i, equal weights.
template <class Real>
basic_rule<Real> to_unit_interval(const std::vector<Real>& x, const std::vector<Real>& w) {
    const std::size_t n = x.size();
    basic_rule<Real> r{std::vector<Real>(n), std::vector<Real>(n)};
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t j = n - 1 - i;
        r.nodes[i] = (1 - (x[i] - x[j]) / 2) / 2; // x_i averaged with −x_j
        r.weights[i] = (w[i] + w[j]) / 4;
    }
    if (n % 2 == 1) r.nodes[n / 2] = Real(0.5);
    return r;
}
} // namespace detail

/// n-point Gauss–Legendre rule (exact for polynomials of degree ≤ 2n − 1): nodes are the roots
/// of P_n, weights 2 / ((1 − x²) P_n'(x)²) on [−1, 1].
template <class Real = double>
basic_rule<Real> gauss_legendre(int n) {
    if (n < 1) throw std::invalid_argument("Gauss–Legendre rule needs n >= 1 points");
    std::vector<Real> x(n), w(n);
    for (int i = 0; i < n; ++i) {
        Real z = std::cos(std::numbers::pi_v<Real> * (i + Real(0.75)) / (n + Real(0.5))); // Tricomi
        for (int it = 0; it < 100; ++it) {
            const auto v = legendre(n, z);
            const Real dz = v.p / v.dp;
            z -= dz;
            if (std::abs(dz) <= 2 * std::numeric_limits<Real>::epsilon()) break;
        }
        const auto v = legendre(n, z);
        x[i] = z;
        w[i] = 2 / ((1 - z * z) * v.dp * v.dp);
    }
    return detail::to_unit_interval(x, w);
}

/// n-point Gauss–Lobatto rule, n ≥ 2 (exact for degree ≤ 2n − 3): nodes ±1 and the roots of
/// P_{n−1}', weights 2 / (n (n − 1) P_{n−1}(x)²) on [−1, 1].
template <class Real = double>
basic_rule<Real> gauss_lobatto(int n) {
    if (n < 2) throw std::invalid_argument("Gauss–Lobatto rule needs n >= 2 points");
    const int m = n - 1; // interior nodes are the roots of P_m'
    std::vector<Real> x(n), w(n);
    x[0] = 1;
    x[n - 1] = -1;
    for (int i = 1; i < n - 1; ++i) {
        Real z = std::cos(std::numbers::pi_v<Real> * i / m); // Chebyshev–Gauss–Lobatto guess
        for (int it = 0; it < 100; ++it) {
            // Newton on P_m': P_m'' = (2x P_m' − m(m+1) P_m) / (1 − x²)
            const auto v = legendre(m, z);
            const Real d2 = (2 * z * v.dp - m * (m + 1) * v.p) / (1 - z * z);
            const Real dz = v.dp / d2;
            z -= dz;
            if (std::abs(dz) <= 2 * std::numeric_limits<Real>::epsilon()) break;
        }
        x[i] = z;
    }
    for (int i = 0; i < n; ++i) {
        const Real p = legendre(m, x[i]).p;
        w[i] = 2 / (n * (n - 1) * p * p);
    }
    return detail::to_unit_interval(x, w);
}

} // namespace varsym::quadrature
