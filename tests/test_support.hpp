// tests/test_support.hpp: small systems and helpers shared by the tests.
#pragma once

#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "varsym/schemes/scheme_kind.hpp"
#include "varsym/systems/separable.hpp"

namespace varsym::test {

/// Whether this build runs under AddressSanitizer (make test-sanitize), where a step costs 30 to
/// 60 times more: long-run tests then run fewer steps, enough to exercise the same code.
#if defined(__SANITIZE_ADDRESS__) // GCC
inline constexpr bool sanitized = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) // clang
inline constexpr bool sanitized = true;
#else
inline constexpr bool sanitized = false;
#endif
#else
inline constexpr bool sanitized = false;
#endif

/// Two pendulums coupled by a spring, V = a(1 − cos q₁) + b(1 − cos q₂) + (c/2)(q₁ − q₂)²,
/// with a non-diagonal mass matrix: a d = 2 system for the generic-dimension code paths.
struct coupled_pendulums {
    double a = 4.0, b = 9.0, c = 1.5;
    [[nodiscard]] double value(const vec<2>& q) const {
        const double d = q(0) - q(1);
        return a * (1 - std::cos(q(0))) + b * (1 - std::cos(q(1))) + 0.5 * c * d * d;
    }
    [[nodiscard]] vec<2> gradient(const vec<2>& q) const {
        const double d = q(0) - q(1);
        return {a * std::sin(q(0)) + c * d, b * std::sin(q(1)) - c * d};
    }
    [[nodiscard]] mat<2> hessian(const vec<2>& q) const {
        mat<2> h;
        h << a * std::cos(q(0)) + c, -c, -c, b * std::cos(q(1)) + c;
        return h;
    }
};

inline separable_system<2, coupled_pendulums> coupled_system() {
    mat<2> m;
    m << 2.0, 0.5, 0.5, 1.0;
    return {m, coupled_pendulums{}};
}

/// V = (k/2) q²: the linear oscillator, for which Newmark conserves the energy exactly.
struct harmonic {
    double k = 3.0;
    [[nodiscard]] double value(const vec<1>& q) const { return 0.5 * k * q(0) * q(0); }
    [[nodiscard]] vec<1> gradient(const vec<1>& q) const { return vec<1>{k * q(0)}; }
    [[nodiscard]] mat<1> hessian(const vec<1>&) const { return mat<1>{k}; }
};

/// A member of the family and the order of convergence it must show.
struct member {
    scheme_spec spec;
    double order;
};

/// Newmark, Simpson, gauss-2, gauss-3 and lobatto-3, of orders 2, 4, 4, 6 and 6.
inline const std::array<member, 5> five_members{{{scheme_kind::newmark, 2},
                                                 {scheme_kind::simpson, 4},
                                                 {{scheme_kind::gauss, 2}, 4},
                                                 {{scheme_kind::gauss, 3}, 6},
                                                 {{scheme_kind::lobatto, 3}, 6}}};

/// x in scientific notation with 4 significant digits, for RecordProperty.
inline std::string sci(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3e", x);
    return buf;
}

} // namespace varsym::test
