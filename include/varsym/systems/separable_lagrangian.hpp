// varsym/systems/separable_lagrangian.hpp: a separable system L = ½ q̇ᵀMq̇ − V(q) as a general
// Lagrangian with its derivatives by hand (included by lagrangian.hpp).
#pragma once

#include "varsym/systems/lagrangian.hpp"
#include "varsym/systems/separable.hpp"

namespace varsym {

/// A separable system L = ½ q̇ᵀMq̇ − V(q) seen as a general Lagrangian, with its derivatives by
/// hand: lets the general engine run any separable system (and tests compare the two paths).
template <separable Separable>
struct separable_lagrangian {
    static constexpr int dim = Separable::dim;
    Separable sys;
    bool diagonal = is_diagonal(sys); ///< the mass matrix is (then M q̇ is a product of vectors)

    static bool is_diagonal(const Separable& s) {
        if constexpr (scalar_mass<Separable>)
            return true;
        else
            return s.mass().isDiagonal(0.0);
    }

    [[nodiscard]] int dimension() const { return sys.dimension(); }
    double operator()(const vec<dim>& q, const vec<dim>& v) const {
        if constexpr (scalar_mass<Separable>)
            return 0.5 * sys.mass() * v.squaredNorm() - sys.potential().value(q);
        else
            return 0.5 * v.dot(sys.mass() * v) - sys.potential().value(q);
    }
    void gradient(const vec<dim>& q, const vec<dim>& v, lagrangian_terms<dim>& t) const {
        t.lq = -sys.potential().gradient(q);
        if constexpr (scalar_mass<Separable>)
            t.lv = sys.mass() * v;
        else if (diagonal)
            t.lv = sys.mass().diagonal().cwiseProduct(v);
        else
            t.lv.noalias() = sys.mass() * v;
    }
    void derivatives(const vec<dim>& q, const vec<dim>& v, lagrangian_terms<dim>& t) const {
        t.value = (*this)(q, v);
        t.lq = -sys.potential().gradient(q);
        t.lqq = -sys.potential().hessian(q);
        t.lqv.setZero(q.size(), q.size());
        if constexpr (scalar_mass<Separable>) {
            t.lv = sys.mass() * v;
            t.lvv.setZero(q.size(), q.size());
            t.lvv.diagonal().setConstant(sys.mass());
        } else {
            t.lv.noalias() = sys.mass() * v;
            t.lvv = sys.mass();
        }
    }
};

} // namespace varsym
