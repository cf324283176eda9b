// varsym/autodiff/jet.hpp: second-order forward-mode automatic differentiation. A jet<N> carries
// a value, its gradient and its Hessian with respect to N seeded variables, so that one pass of a
// user function templated on the scalar type gives everything Newton needs.
//
// Why our own type and not Eigen's unsupported AutoDiffScalar: second derivatives with Eigen need
// AutoDiffScalar nested in AutoDiffScalar, whose every operation builds N inner derivative
// vectors; bench/bench_autodiff.cpp measures the two on the same Lagrangians (docs/autodiff.md).
// tests/autodiff/test_jet.cpp checks this type against the nested Eigen one.
#pragma once

#include <cmath>
#include <type_traits>

#include <Eigen/Core>

namespace varsym::ad {

template <int N>
struct jet {
    using gradient_type = Eigen::Matrix<double, N, 1>;
    using hessian_type = Eigen::Matrix<double, N, N>;

    double v = 0.0;
    gradient_type g = gradient_type::Zero();
    hessian_type h = hessian_type::Zero();

    jet() = default;
    jet(double value) : v(value) {} // NOLINT: implicit, so constants mix with jets
    template <class T, std::enable_if_t<std::is_arithmetic_v<T>, int> = 0>
    jet(T value) : v(static_cast<double>(value)) {} // NOLINT: implicit (int literals)

    /// The i-th independent variable with value x: gradient e_i, Hessian 0.
    static jet variable(double x, int i) {
        jet r(x);
        r.g(i) = 1.0;
        return r;
    }

    jet& operator+=(const jet& b) { v += b.v; g += b.g; h += b.h; return *this; }
    jet& operator-=(const jet& b) { v -= b.v; g -= b.g; h -= b.h; return *this; }
    jet& operator*=(const jet& b) { return *this = *this * b; }
    jet& operator/=(const jet& b) { return *this = *this / b; }
    jet& operator+=(double b) { v += b; return *this; }
    jet& operator-=(double b) { v -= b; return *this; }
    jet& operator*=(double b) { v *= b; g *= b; h *= b; return *this; }
    jet& operator/=(double b) { return *this *= 1.0 / b; }

    friend jet operator-(jet a) { a.v = -a.v; a.g = -a.g; a.h = -a.h; return a; }
    friend jet operator+(const jet& a) { return a; }
    friend jet operator+(jet a, const jet& b) { return a += b; }
    friend jet operator-(jet a, const jet& b) { return a -= b; }
    friend jet operator+(jet a, double b) { return a += b; }
    friend jet operator+(double a, jet b) { return b += a; }
    friend jet operator-(jet a, double b) { return a -= b; }
    friend jet operator-(double a, const jet& b) { return -b + a; }
    friend jet operator*(jet a, double b) { return a *= b; }
    friend jet operator*(double a, jet b) { return b *= a; }
    friend jet operator/(jet a, double b) { return a /= b; }
    friend jet operator/(double a, const jet& b) { return a * reciprocal(b); }
    // (ab)'' = a b'' + b a'' + a' b'ᵀ + b' a'ᵀ
    friend jet operator*(const jet& a, const jet& b) {
        jet r;
        r.v = a.v * b.v;
        r.g = a.v * b.g + b.v * a.g;
        r.h.noalias() = a.v * b.h + b.v * a.h;
        r.h.noalias() += a.g * b.g.transpose();
        r.h.noalias() += b.g * a.g.transpose();
        return r;
    }
    friend jet operator/(const jet& a, const jet& b) { return a * reciprocal(b); }

    /// f(a) for a scalar function with f(a.v) = f0, f'(a.v) = f1, f''(a.v) = f2 (chain rule):
    /// value f0, gradient f1 a', Hessian f1 a'' + f2 a' a'ᵀ.
    friend jet compose(const jet& a, double f0, double f1, double f2) {
        jet r;
        r.v = f0;
        r.g = f1 * a.g;
        r.h.noalias() = f1 * a.h;
        r.h.noalias() += (f2 * a.g) * a.g.transpose();
        return r;
    }
    friend jet reciprocal(const jet& a) {
        const double i = 1.0 / a.v;
        return compose(a, i, -i * i, 2.0 * i * i * i);
    }

    // Comparisons look at values only (branches in a Lagrangian, e.g. piecewise potentials).
    friend bool operator<(const jet& a, const jet& b) { return a.v < b.v; }
    friend bool operator>(const jet& a, const jet& b) { return a.v > b.v; }
    friend bool operator<=(const jet& a, const jet& b) { return a.v <= b.v; }
    friend bool operator>=(const jet& a, const jet& b) { return a.v >= b.v; }
    friend bool operator==(const jet& a, const jet& b) { return a.v == b.v; }
};

template <int N>
jet<N> sin(const jet<N>& a) {
    const double s = std::sin(a.v), c = std::cos(a.v);
    return compose(a, s, c, -s);
}
template <int N>
jet<N> cos(const jet<N>& a) {
    const double s = std::sin(a.v), c = std::cos(a.v);
    return compose(a, c, -s, -c);
}
template <int N>
jet<N> tan(const jet<N>& a) {
    const double t = std::tan(a.v), s = 1.0 + t * t;
    return compose(a, t, s, 2.0 * t * s);
}
template <int N>
jet<N> exp(const jet<N>& a) {
    const double e = std::exp(a.v);
    return compose(a, e, e, e);
}
template <int N>
jet<N> log(const jet<N>& a) {
    const double i = 1.0 / a.v;
    return compose(a, std::log(a.v), i, -i * i);
}
template <int N>
jet<N> sqrt(const jet<N>& a) {
    const double s = std::sqrt(a.v);
    return compose(a, s, 0.5 / s, -0.25 / (s * a.v));
}
template <int N>
jet<N> pow(const jet<N>& a, double e) {
    const double p = std::pow(a.v, e - 2.0);
    return compose(a, p * a.v * a.v, e * p * a.v, e * (e - 1.0) * p);
}
template <int N>
jet<N> abs(const jet<N>& a) {
    return a.v < 0.0 ? -a : a;
}
template <int N>
jet<N> atan(const jet<N>& a) {
    const double s = 1.0 / (1.0 + a.v * a.v);
    return compose(a, std::atan(a.v), s, -2.0 * a.v * s * s);
}
template <int N>
jet<N> sinh(const jet<N>& a) {
    const double s = std::sinh(a.v), c = std::cosh(a.v);
    return compose(a, s, c, s);
}
template <int N>
jet<N> cosh(const jet<N>& a) {
    const double s = std::sinh(a.v), c = std::cosh(a.v);
    return compose(a, c, s, c);
}
template <int N>
bool isfinite(const jet<N>& a) {
    return std::isfinite(a.v) && a.g.allFinite() && a.h.allFinite();
}

} // namespace varsym::ad

namespace Eigen {
/// Lets Eigen matrices hold jets (q.dot(v), squaredNorm(), matrix products in a Lagrangian).
template <int N>
struct NumTraits<varsym::ad::jet<N>> : NumTraits<double> {
    using Real = varsym::ad::jet<N>;
    using NonInteger = varsym::ad::jet<N>;
    using Nested = varsym::ad::jet<N>;
    using Literal = double;
    enum { IsComplex = 0, IsInteger = 0, IsSigned = 1, RequireInitialization = 1,
           ReadCost = 1 + N + N * N, AddCost = 1 + N + N * N, MulCost = 3 + 4 * N * N };
};
template <int N, typename BinaryOp>
struct ScalarBinaryOpTraits<varsym::ad::jet<N>, double, BinaryOp> {
    using ReturnType = varsym::ad::jet<N>;
};
template <int N, typename BinaryOp>
struct ScalarBinaryOpTraits<double, varsym::ad::jet<N>, BinaryOp> {
    using ReturnType = varsym::ad::jet<N>;
};
} // namespace Eigen
