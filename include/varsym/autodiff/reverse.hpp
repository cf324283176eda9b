// varsym/autodiff/reverse.hpp: the gradient of a scalar function by reverse-mode automatic
// differentiation, at a cost that does not grow with the number of variables (forward mode's
// grows in proportion): about 14 evaluations of the function for the N-body Lagrangian, against
// 21 for forward mode at 36 variables (docs/autodiff.md).
//
// Each arithmetic operation on a `reverse` scalar appends one node to a tape: the indices of its
// (at most two) operands and the partial derivatives with respect to them. The gradient is one
// sweep of the tape backwards, accumulating adjoints (Griewank & Walther, "Evaluating
// Derivatives", 2nd ed., SIAM 2008, ch. 3). The tape is per thread and reused, so after the first
// evaluation nothing is allocated.
//
// Written here rather than taken from a library (docs/autodiff.md): Trilinos Sacado's reverse
// mode (Sacado::Rad, Debian's libtrilinos-sacado-dev) keeps its tape in one static context, so
// two threads cannot differentiate at once, and measured no faster on the same Lagrangian.
#pragma once

#include <algorithm>
#include <cmath>

#include <Eigen/Core>

namespace varsym::ad {

/// One operation: result = f(x_a, x_b), with ∂f/∂x_a = da and ∂f/∂x_b = db. An operand that is
/// a constant, or absent (a unary operation or an independent variable), has index 0.
struct tape_node {
    int a, b;
    double da, db;
};

/// The thread's tape: a plain (trivially constructed) thread-local, so that each operation
/// reaches it without a guard; its storage grows by doubling and is kept for the next recording.
struct tape {
    tape_node* nodes;
    double* adjoints;
    int size, capacity;

    static tape& local() { return instance; }
    /// Starts a recording. Node 0 stands for the constants and is never swept.
    void clear() {
        if (capacity == 0) grow();
        nodes[0] = {0, 0, 0.0, 0.0};
        size = 1;
    }
    int push(int a, double da, int b, double db) {
        if (size == capacity) grow();
        const int k = size++;
        nodes[k] = {a, b, da, db};
        adjoints[k] = 0.0;
        return k;
    }
    /// The adjoint of every node for the output node `out` (∂out/∂node, in adjoints[i]).
    ///
    /// The sweep is bound by latency: each update is a load, a multiply-add and a store that the
    /// next node's load waits for. The operand most often updated is the node just before
    /// (k − 1), so that one is carried in a register instead; updates of the constants' slot
    /// (0) and of k − 1 go to the node's own slot with a zero instead, which nothing waits for.
    void sweep(int out) {
        adjoints[out] = 1.0;
        double carry = 0.0; // the adjoint node k + 1 passed to node k
        for (int k = out; k > 0; --k) {
            const tape_node& n = nodes[k];
            const double w = adjoints[k] + carry;
            adjoints[k] = w;
            const double ga = n.da * w, gb = n.db * w;
            const bool pa = n.a == k - 1, pb = n.b == k - 1;
            carry = (pa ? ga : 0.0) + (pb ? gb : 0.0);
            const bool sa = pa || n.a == 0, sb = pb || n.b == 0;
            adjoints[sa ? k : n.a] += sa ? 0.0 : ga;
            adjoints[sb ? k : n.b] += sb ? 0.0 : gb;
        }
    }
    [[nodiscard]] double adjoint(int i) const { return adjoints[i]; }

  private:
    void grow() {
        const int n = capacity == 0 ? 4096 : 2 * capacity;
        auto* bigger = new tape_node[static_cast<std::size_t>(n)];
        auto* more = new double[static_cast<std::size_t>(n)];
        std::copy(nodes, nodes + size, bigger);
        std::copy(adjoints, adjoints + size, more);
        delete[] nodes;
        delete[] adjoints;
        nodes = bigger;
        adjoints = more;
        capacity = n;
        if (!registered) { // frees the storage when the thread ends
            registered = true;
            static thread_local struct release {
                ~release() {
                    delete[] instance.nodes;
                    delete[] instance.adjoints;
                }
            } r;
        }
    }
    static inline thread_local bool registered = false;
    static thread_local tape instance;
};
inline thread_local tape tape::instance{nullptr, nullptr, 0, 0};

/// A scalar recorded on the thread's tape. Index 0 (the default) is a constant.
class reverse {
  public:
    reverse() = default;
    reverse(double v) : v_(v) {} // NOLINT(google-explicit-constructor): constants mix freely
    reverse(double v, int index) : v_(v), i_(index) {}

    /// A new independent variable on the thread's tape.
    static reverse variable(double v) { return {v, tape::local().push(0, 0.0, 0, 0.0)}; }

    [[nodiscard]] double value() const { return v_; }
    [[nodiscard]] int index() const { return i_; }

    reverse& operator+=(const reverse& o) { return *this = *this + o; }
    reverse& operator-=(const reverse& o) { return *this = *this - o; }
    reverse& operator*=(const reverse& o) { return *this = *this * o; }
    reverse& operator/=(const reverse& o) { return *this = *this / o; }

    friend reverse operator+(const reverse& x, const reverse& y) {
        return {x.v_ + y.v_, tape::local().push(x.i_, 1.0, y.i_, 1.0)};
    }
    friend reverse operator-(const reverse& x, const reverse& y) {
        return {x.v_ - y.v_, tape::local().push(x.i_, 1.0, y.i_, -1.0)};
    }
    friend reverse operator*(const reverse& x, const reverse& y) {
        return {x.v_ * y.v_, tape::local().push(x.i_, y.v_, y.i_, x.v_)};
    }
    friend reverse operator/(const reverse& x, const reverse& y) {
        const double r = 1.0 / y.v_, q = x.v_ * r;
        return {q, tape::local().push(x.i_, r, y.i_, -q * r)};
    }
    friend reverse operator-(const reverse& x) { return unary(x, -x.v_, -1.0); }
    friend reverse operator+(const reverse& x) { return x; }

    // Comparisons look at values only (as the function would with doubles).
    friend bool operator==(const reverse& x, const reverse& y) { return x.v_ == y.v_; }
    friend bool operator!=(const reverse& x, const reverse& y) { return x.v_ != y.v_; }
    friend bool operator<(const reverse& x, const reverse& y) { return x.v_ < y.v_; }
    friend bool operator<=(const reverse& x, const reverse& y) { return x.v_ <= y.v_; }
    friend bool operator>(const reverse& x, const reverse& y) { return x.v_ > y.v_; }
    friend bool operator>=(const reverse& x, const reverse& y) { return x.v_ >= y.v_; }

    // Elementary functions, found by argument-dependent lookup after `using std::sin;`.
    friend reverse sin(const reverse& x) { return unary(x, std::sin(x.v_), std::cos(x.v_)); }
    friend reverse cos(const reverse& x) { return unary(x, std::cos(x.v_), -std::sin(x.v_)); }
    friend reverse tan(const reverse& x) {
        const double t = std::tan(x.v_);
        return unary(x, t, 1.0 + t * t);
    }
    friend reverse exp(const reverse& x) {
        const double e = std::exp(x.v_);
        return unary(x, e, e);
    }
    friend reverse log(const reverse& x) { return unary(x, std::log(x.v_), 1.0 / x.v_); }
    friend reverse sqrt(const reverse& x) {
        const double r = std::sqrt(x.v_);
        return unary(x, r, 0.5 / r);
    }
    friend reverse abs(const reverse& x) {
        return unary(x, std::abs(x.v_), x.v_ < 0.0 ? -1.0 : 1.0);
    }
    friend reverse sinh(const reverse& x) { return unary(x, std::sinh(x.v_), std::cosh(x.v_)); }
    friend reverse cosh(const reverse& x) { return unary(x, std::cosh(x.v_), std::sinh(x.v_)); }
    friend reverse tanh(const reverse& x) {
        const double t = std::tanh(x.v_);
        return unary(x, t, 1.0 - t * t);
    }
    friend reverse asin(const reverse& x) {
        return unary(x, std::asin(x.v_), 1.0 / std::sqrt(1.0 - x.v_ * x.v_));
    }
    friend reverse acos(const reverse& x) {
        return unary(x, std::acos(x.v_), -1.0 / std::sqrt(1.0 - x.v_ * x.v_));
    }
    friend reverse atan(const reverse& x) {
        return unary(x, std::atan(x.v_), 1.0 / (1.0 + x.v_ * x.v_));
    }
    friend reverse atan2(const reverse& y, const reverse& x) {
        const double r = 1.0 / (x.v_ * x.v_ + y.v_ * y.v_);
        return {std::atan2(y.v_, x.v_), tape::local().push(y.i_, x.v_ * r, x.i_, -y.v_ * r)};
    }
    friend reverse pow(const reverse& x, double n) {
        const double p = std::pow(x.v_, n);
        return unary(x, p, n == 0.0 ? 0.0 : n * std::pow(x.v_, n - 1.0));
    }
    friend reverse pow(const reverse& x, const reverse& y) {
        const double p = std::pow(x.v_, y.v_);
        const double dx = y.v_ == 0.0 ? 0.0 : y.v_ * std::pow(x.v_, y.v_ - 1.0);
        const double dy = x.v_ > 0.0 ? p * std::log(x.v_) : 0.0;
        return {p, tape::local().push(x.i_, dx, y.i_, dy)};
    }
    friend reverse square(const reverse& x) { return x * x; }

  private:
    static reverse unary(const reverse& x, double value, double derivative) {
        return {value, tape::local().push(x.i_, derivative, 0, 0.0)};
    }

    double v_ = 0.0;
    int i_ = 0;
};

} // namespace varsym::ad

namespace Eigen {
/// Lets Eigen's vectors and reductions (dot, squaredNorm, norm) hold reverse scalars.
template <>
struct NumTraits<varsym::ad::reverse> : NumTraits<double> {
    using Real = varsym::ad::reverse;
    using NonInteger = varsym::ad::reverse;
    using Nested = varsym::ad::reverse;
    using Literal = double;
    enum { IsComplex = 0, RequireInitialization = 1, ReadCost = 1, AddCost = 3, MulCost = 3 };
};
template <typename BinaryOp>
struct ScalarBinaryOpTraits<varsym::ad::reverse, double, BinaryOp> {
    using ReturnType = varsym::ad::reverse;
};
template <typename BinaryOp>
struct ScalarBinaryOpTraits<double, varsym::ad::reverse, BinaryOp> {
    using ReturnType = varsym::ad::reverse;
};
} // namespace Eigen
