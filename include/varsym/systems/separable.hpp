// varsym/systems/separable.hpp: separable Lagrangians L = ½ q̇ᵀ M q̇ − V(q) with constant M.
#pragma once

#include <concepts>
#include <stdexcept>

#include "varsym/types.hpp"

namespace varsym {

/// What a potential V: R^D → R must provide: its value, gradient ∇V and Hessian ∇²V.
template <class P, int D>
concept potential = requires(const P& v, const vec<D>& q) {
    { v.value(q) } -> std::convertible_to<double>;
    { v.gradient(q) } -> std::convertible_to<vec<D>>;
    { v.hessian(q) } -> std::convertible_to<mat<D>>;
};

/// L(q, q̇) = ½ q̇ᵀ M q̇ − V(q)  (paper eq. Lagrangien-continu, with m → M), q ∈ R^D.
/// M must be symmetric positive definite; its inverse is computed once.
template <int D, class Potential>
class separable_system {
    static_assert(potential<Potential, D>,
                  "Potential must provide value(q) -> double, gradient(q) -> vec<D> and "
                  "hessian(q) -> mat<D>");

  public:
    static constexpr int dim = D;
    using potential_type = Potential;

    separable_system(const mat<D>& mass, Potential v) : mass_(mass), v_(std::move(v)) {
        if (!mass_.allFinite())
            throw std::invalid_argument("mass matrix has a NaN or infinite entry");
        if (!mass_.isApprox(mass_.transpose(), 1e-14))
            throw std::invalid_argument("mass matrix is not symmetric");
        Eigen::LLT<mat<D>> llt(mass_);
        if (llt.info() != Eigen::Success || mass_.rows() == 0)
            throw std::invalid_argument("mass matrix is not positive definite");
        inv_mass_ = llt.solve(mat<D>::Identity(mass_.rows(), mass_.cols()));
    }

    [[nodiscard]] int dimension() const { return static_cast<int>(mass_.rows()); }
    [[nodiscard]] const mat<D>& mass() const { return mass_; }
    [[nodiscard]] const mat<D>& inverse_mass() const { return inv_mass_; }
    [[nodiscard]] const Potential& potential() const { return v_; }

    /// H(q, p) = ½ pᵀ M⁻¹ p + V(q)  (paper §2, Hamilton function).
    [[nodiscard]] double energy(const phase_state<D>& x) const {
        return 0.5 * x.p.dot(inv_mass_ * x.p) + v_.value(x.q);
    }

  private:
    mat<D> mass_;
    mat<D> inv_mass_;
    Potential v_;
};

} // namespace varsym
