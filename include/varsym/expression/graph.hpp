// varsym/expression/graph.hpp: expressions as a graph of shared nodes (each distinct
// subexpression stored once: hash-consing), simplified as they are built, and differentiated
// symbolically. The nodes are created children first, so their ids are in topological order:
// the tape (expression/tape.hpp) evaluates them in that order.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <unordered_map>
#include <vector>

namespace varsym::expr {

/// The operations. `input` is the k-th input (value = k); `powi` raises to the integer `value`.
enum class op : std::uint8_t {
    constant,
    input,
    add,
    sub,
    mul,
    div,
    neg,
    square,
    powi,
    pow,
    sin,
    cos,
    tan,
    exp,
    log,
    sqrt,
    sinh,
    cosh,
    tanh,
    asin,
    acos,
    atan
};

/// One node: an operation on nodes a (and b), or a constant / an input index / an exponent.
struct node {
    op kind = op::constant;
    int a = -1, b = -1;
    double value = 0.0;
};

/// Evaluates a one-argument function (the ops from sin on, and neg, square).
inline double apply(op f, double x) {
    switch (f) {
    case op::neg:
        return -x;
    case op::square:
        return x * x;
    case op::sin:
        return std::sin(x);
    case op::cos:
        return std::cos(x);
    case op::tan:
        return std::tan(x);
    case op::exp:
        return std::exp(x);
    case op::log:
        return std::log(x);
    case op::sqrt:
        return std::sqrt(x);
    case op::sinh:
        return std::sinh(x);
    case op::cosh:
        return std::cosh(x);
    case op::tanh:
        return std::tanh(x);
    case op::asin:
        return std::asin(x);
    case op::acos:
        return std::acos(x);
    case op::atan:
        return std::atan(x);
    default:
        throw std::logic_error("varsym::expr::apply: not a function");
    }
}

/// x to the integer power n by repeated squaring (n may be negative).
inline double integer_power(double x, int n) {
    const bool invert = n < 0;
    unsigned m = invert ? 0U - static_cast<unsigned>(n) : static_cast<unsigned>(n);
    double r = 1.0;
    while (m != 0U) {
        if ((m & 1U) != 0U) r *= x;
        x *= x;
        m >>= 1U;
    }
    return invert ? 1.0 / r : r;
}

/// The expression graph. Builders return node ids; they fold constants and apply the identities
/// x + 0 = x, x·1 = x, x·0 = 0, x − x = 0, x/1 = x, −(−x) = x, x^1 = x, x^2 = x·x,
/// (c·u)·(c'/v) = u·((c c')/v), and order the operands of + and · so that a + b and b + a are
/// one node.
class graph {
  public:
    [[nodiscard]] const node& operator[](int id) const {
        return nodes_[static_cast<std::size_t>(id)];
    }
    [[nodiscard]] int size() const { return static_cast<int>(nodes_.size()); }
    [[nodiscard]] bool is_constant(int id) const { return (*this)[id].kind == op::constant; }
    [[nodiscard]] bool is(int id, double c) const {
        return is_constant(id) && (*this)[id].value == c;
    }

    int constant(double c) {
        if (c == 0.0) c = 0.0; // −0 and 0 are one node
        return make({op::constant, -1, -1, c});
    }
    int input(int k) { return make({op::input, -1, -1, static_cast<double>(k)}); }

    int add(int a, int b) {
        if (is_constant(a) && is_constant(b)) return constant(value(a) + value(b));
        if (is(a, 0.0)) return b;
        if (is(b, 0.0)) return a;
        if (kind(b) == op::neg) return sub(a, (*this)[b].a);
        if (kind(a) == op::neg) return sub(b, (*this)[a].a);
        return make({op::add, std::min(a, b), std::max(a, b), 0.0});
    }
    int sub(int a, int b) {
        if (is_constant(a) && is_constant(b)) return constant(value(a) - value(b));
        if (a == b) return constant(0.0);
        if (is(b, 0.0)) return a;
        if (is(a, 0.0)) return neg(b);
        if (kind(b) == op::neg) return add(a, (*this)[b].a);
        return make({op::sub, a, b, 0.0});
    }
    int mul(int a, int b) {
        if (is_constant(b) && !is_constant(a)) std::swap(a, b); // the constant first
        if (is_constant(a)) {
            const double c = value(a);
            if (is_constant(b)) return constant(c * value(b));
            if (c == 0.0) return a;
            if (c == 1.0) return b;
            if (c == -1.0) return neg(b);
            if (kind(b) == op::neg) return mul(constant(-c), (*this)[b].a);
            if (kind(b) == op::mul && is_constant((*this)[b].a)) // c·(c'·x) = (c c')·x
                return mul(constant(c * value((*this)[b].a)), (*this)[b].b);
            return make({op::mul, a, b, 0.0});
        }
        if (a == b) return square(a);
        if (kind(a) == op::neg) return neg(mul((*this)[a].a, b));
        if (kind(b) == op::neg) return neg(mul(a, (*this)[b].a));
        // (c·u)·(c'/v) = u·((c c')/v): the chain rule's constants meet (d√(x² + y²)/dx =
        // 2x · (0.5/√…) = x · (1/√…), one quotient shared by every coordinate).
        const auto scaled = [&](int x) { return kind(x) == op::mul && is_constant((*this)[x].a); };
        const auto reciprocal = [&](int x) {
            return kind(x) == op::div && is_constant((*this)[x].a);
        };
        if (scaled(b) && reciprocal(a)) std::swap(a, b);
        if (scaled(a) && reciprocal(b)) {
            const node u = (*this)[a], v = (*this)[b]; // copies: building may reallocate
            return mul(u.b, div(constant(value(u.a) * value(v.a)), v.b));
        }
        return make({op::mul, std::min(a, b), std::max(a, b), 0.0});
    }
    int div(int a, int b) {
        if (is_constant(a) && is_constant(b)) return constant(value(a) / value(b));
        if (is(a, 0.0) && !is_constant(b)) return a;
        if (is(b, 1.0)) return a;
        if (a == b) return constant(1.0);
        return make({op::div, a, b, 0.0});
    }
    int neg(int a) {
        if (is_constant(a)) return constant(-value(a));
        if (kind(a) == op::neg) return (*this)[a].a;
        if (kind(a) == op::sub) return sub((*this)[a].b, (*this)[a].a);
        return make({op::neg, a, -1, 0.0});
    }
    int square(int a) {
        if (is_constant(a)) return constant(value(a) * value(a));
        if (kind(a) == op::neg) a = (*this)[a].a;
        return make({op::square, a, -1, 0.0});
    }
    /// a^b: an integer constant b becomes powi (b = 2: square), b = 1/2 sqrt.
    int pow(int a, int b) {
        if (is_constant(a) && is_constant(b)) return constant(std::pow(value(a), value(b)));
        if (is_constant(b)) {
            const double e = value(b);
            if (e == 0.0) return constant(1.0);
            if (e == 1.0) return a;
            if (e == 2.0) return square(a);
            if (e == 0.5) return call(op::sqrt, a);
            if (e == std::round(e) && std::abs(e) <= 64.0) return make({op::powi, a, -1, e});
        }
        return make({op::pow, a, b, 0.0});
    }
    /// f(a) for f from sin on (and neg, square).
    int call(op f, int a) {
        if (f == op::neg) return neg(a);
        if (f == op::square) return square(a);
        if (is_constant(a)) return constant(apply(f, value(a)));
        return make({f, a, -1, 0.0});
    }

    /// ∂f/∂(input k), built into the graph (and remembered: asked again, it is not rebuilt).
    int derivative(int f, int k);

  private:
    struct key_hash {
        std::size_t operator()(const node& n) const {
            std::uint64_t bits = 0;
            std::memcpy(&bits, &n.value, sizeof bits);
            std::size_t h = std::hash<std::uint64_t>{}(bits);
            for (std::size_t x : {static_cast<std::size_t>(n.kind), static_cast<std::size_t>(n.a),
                                  static_cast<std::size_t>(n.b)})
                h ^= x + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
            return h;
        }
    };
    struct key_equal {
        bool operator()(const node& x, const node& y) const {
            return x.kind == y.kind && x.a == y.a && x.b == y.b &&
                   std::memcmp(&x.value, &y.value, sizeof x.value) == 0;
        }
    };
    static std::uint64_t key(int f, int k) {
        return (static_cast<std::uint64_t>(f) << 32U) | static_cast<unsigned>(k);
    }
    /// ∂f/∂(input k) by the rule of f's operation, from its children's known derivatives.
    int differentiate(int f, int k);
    [[nodiscard]] op kind(int id) const { return (*this)[id].kind; }
    [[nodiscard]] double value(int id) const { return (*this)[id].value; }
    int make(const node& n) {
        const auto [it, fresh] = index_.try_emplace(n, size());
        if (fresh) nodes_.push_back(n);
        return it->second;
    }

    std::vector<node> nodes_;
    std::unordered_map<node, int, key_hash, key_equal> index_;
    std::unordered_map<std::uint64_t, int> derivatives_; ///< (f, k) → ∂f/∂x_k
};

inline int graph::derivative(int f, int k) {
    if (const auto it = derivatives_.find(key(f, k)); it != derivatives_.end()) return it->second;
    // The nodes f depends on whose derivative is not known yet, found going down the ids (a
    // node's children have smaller ids; a known derivative's children are known), then
    // differentiated going up: no recursion, however deep the expression.
    std::vector<char> needed(static_cast<std::size_t>(f) + 1, 0);
    needed[static_cast<std::size_t>(f)] = 1;
    for (int id = f; id >= 0; --id) {
        if (needed[static_cast<std::size_t>(id)] == 0) continue;
        if (derivatives_.contains(key(id, k))) {
            needed[static_cast<std::size_t>(id)] = 0;
            continue;
        }
        const node& x = (*this)[id];
        if (x.a >= 0) needed[static_cast<std::size_t>(x.a)] = 1;
        if (x.b >= 0 && x.kind != op::powi) needed[static_cast<std::size_t>(x.b)] = 1;
    }
    for (int id = 0; id <= f; ++id)
        if (needed[static_cast<std::size_t>(id)] != 0)
            derivatives_.emplace(key(id, k), differentiate(id, k));
    return derivatives_.at(key(f, k));
}

inline int graph::differentiate(int f, int k) {
    const node n = (*this)[f]; // a copy: building nodes may reallocate
    auto d = [&](int x) { return derivatives_.at(key(x, k)); };
    int r = 0;
    switch (n.kind) {
    case op::constant:
        r = constant(0.0);
        break;
    case op::input:
        r = constant(static_cast<int>(n.value) == k ? 1.0 : 0.0);
        break;
    case op::add:
        r = add(d(n.a), d(n.b));
        break;
    case op::sub:
        r = sub(d(n.a), d(n.b));
        break;
    case op::mul:
        r = add(mul(d(n.a), n.b), mul(n.a, d(n.b)));
        break;
    case op::div: // (a' − (a/b) b')/b; with a' = 0, −((a/b)/b) b': one quotient for every k
        r = is(d(n.a), 0.0) ? neg(mul(div(f, n.b), d(n.b)))
                            : div(sub(d(n.a), mul(f, d(n.b))), n.b);
        break;
    case op::neg:
        r = neg(d(n.a));
        break;
    case op::square:
        r = mul(mul(constant(2.0), n.a), d(n.a));
        break;
    case op::powi:
        r = mul(mul(constant(n.value), pow(n.a, constant(n.value - 1.0))), d(n.a));
        break;
    case op::pow: // a^b (ln a · b' + b a'/a)
        r = mul(f, add(mul(call(op::log, n.a), d(n.b)), div(mul(n.b, d(n.a)), n.a)));
        break;
    case op::sin:
        r = mul(call(op::cos, n.a), d(n.a));
        break;
    case op::cos:
        r = neg(mul(call(op::sin, n.a), d(n.a)));
        break;
    case op::tan:
        r = mul(add(constant(1.0), square(f)), d(n.a));
        break;
    case op::exp:
        r = mul(f, d(n.a));
        break;
    case op::log:
        r = div(d(n.a), n.a);
        break;
    case op::sqrt: // a' (0.5/√a): one quotient for every k
        r = mul(d(n.a), div(constant(0.5), f));
        break;
    case op::sinh:
        r = mul(call(op::cosh, n.a), d(n.a));
        break;
    case op::cosh:
        r = mul(call(op::sinh, n.a), d(n.a));
        break;
    case op::tanh:
        r = mul(sub(constant(1.0), square(f)), d(n.a));
        break;
    case op::asin:
        r = div(d(n.a), call(op::sqrt, sub(constant(1.0), square(n.a))));
        break;
    case op::acos:
        r = neg(div(d(n.a), call(op::sqrt, sub(constant(1.0), square(n.a)))));
        break;
    case op::atan:
        r = div(d(n.a), add(constant(1.0), square(n.a)));
        break;
    }
    return r;
}

} // namespace varsym::expr
