// varsym/systems/expression_separable.hpp: an expression Lagrangian that is separable,
// L = ½ q̇ᵀ M q̇ − V(q) with M constant (expression_lagrangian::separable()), as the separable
// system the paper's Simpson and Newmark steppers and the family stepper take
// (systems/separable.hpp): V, ∇V and ∇²V from its own compiled code, M from the graph. At a
// fixed dimension D (separable_system_of<D>) the steppers run on fixed-size vectors, as for a
// built-in model; at D = dynamic, on vectors sized at run time.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>

#include "varsym/systems/expression_lagrangian.hpp"
#include "varsym/systems/separable.hpp"

namespace varsym {

/// V(q) = −L(q, 0) of a separable expression Lagrangian, for q ∈ R^D. Holds a copy of L (its
/// registers are its own: one object is not for concurrent use).
template <int D>
class expression_potential_of {
  public:
    explicit expression_potential_of(expression_lagrangian l) : l_(std::move(l)) {
        if (!l_.separable())
            throw std::invalid_argument("L is not ½ q̇ᵀ M q̇ − V(q) with a constant M");
        if constexpr (D != dynamic)
            if (l_.dimension() != D)
                throw std::invalid_argument("L has " + std::to_string(l_.dimension()) +
                                            " coordinates, not " + std::to_string(D));
    }
    [[nodiscard]] double value(const vec<D>& q) const { return l_.potential(q); }
    [[nodiscard]] vec<D> gradient(const vec<D>& q) const {
        vec<D> g(q.size());
        l_.potential_gradient(q.data(), g.data());
        return g;
    }
    /// The same into g, which keeps its storage across calls (separable.hpp, in_place_gradient).
    void gradient(const vec<D>& q, vec<D>& g) const {
        g.resize(q.size());
        l_.potential_gradient(q.data(), g.data());
    }
    /// ∇V at `count` points (d × count, column-major) into g (the same layout), in one pass
    /// over the compiled code: the family stepper's points of a sweep (separable.hpp).
    void gradients(const double* q, int count, double* g) const {
        l_.potential_gradients(q, count, g);
    }
    /// ∇V and ∇²V at q by one code (Simpson's and Newmark's Newton iterations, separable.hpp).
    void gradient_and_hessian(const vec<D>& q, vec<D>& g, mat<D>& h) const {
        g.resize(q.size());
        h.resize(q.size(), q.size());
        l_.potential_gradient_and_hessian(q.data(), g.data(), h.data());
    }
    [[nodiscard]] mat<D> hessian(const vec<D>& q) const {
        mat<D> h(q.size(), q.size());
        l_.potential_hessian(q.data(), h.data());
        return h;
    }

  private:
    expression_lagrangian l_;
};

using expression_potential = expression_potential_of<dynamic>;
template <int D>
using expression_separable_system_of = separable_system<D, expression_potential_of<D>>;
using expression_separable_system = expression_separable_system_of<dynamic>;

/// The separable system of L at dimension D (L's own, or dynamic); throws std::invalid_argument
/// where L is not separable or has another dimension.
template <int D = dynamic>
expression_separable_system_of<D> separable_system_of(const expression_lagrangian& l) {
    expression_potential_of<D> v(l); // checks L first: M must fit mat<D>
    return {l.separable_mass(), std::move(v)};
}

} // namespace varsym
