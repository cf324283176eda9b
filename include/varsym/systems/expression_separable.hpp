// varsym/systems/expression_separable.hpp: an expression Lagrangian that is separable,
// L = ½ q̇ᵀ M q̇ − V(q) with M constant (expression_lagrangian::separable()), as the separable
// system the paper's Simpson and Newmark steppers and the family stepper take
// (systems/separable.hpp): V, ∇V and ∇²V from its own compiled code, M from the graph.
#pragma once

#include <stdexcept>
#include <utility>

#include "varsym/systems/expression_lagrangian.hpp"
#include "varsym/systems/separable.hpp"

namespace varsym {

/// V(q) = −L(q, 0) of a separable expression Lagrangian. Holds a copy of L (its registers are
/// its own: one object is not for concurrent use).
class expression_potential {
  public:
    explicit expression_potential(expression_lagrangian l) : l_(std::move(l)) {
        if (!l_.separable())
            throw std::invalid_argument("L is not ½ q̇ᵀ M q̇ − V(q) with a constant M");
    }
    [[nodiscard]] double value(const vec<dynamic>& q) const { return l_.potential(q); }
    [[nodiscard]] vec<dynamic> gradient(const vec<dynamic>& q) const {
        return l_.potential_gradient(q);
    }
    [[nodiscard]] mat<dynamic> hessian(const vec<dynamic>& q) const {
        return l_.potential_hessian(q);
    }

  private:
    expression_lagrangian l_;
};

using expression_separable_system = separable_system<dynamic, expression_potential>;

/// The separable system of L; throws std::invalid_argument where L is not separable.
inline expression_separable_system separable_system_of(const expression_lagrangian& l) {
    return {l.separable_mass(), expression_potential(l)};
}

} // namespace varsym
