// varsym/systems/separable.hpp: separable Lagrangians L = ½ q̇ᵀ M q̇ − V(q) with constant M.
#pragma once

#include <concepts>
#include <stdexcept>
#include <type_traits>

#include "varsym/types.hpp"

namespace varsym {

/// What a potential V: R^D → R must provide: its value, gradient ∇V and Hessian ∇²V.
template <class P, int D>
concept potential = requires(const P& v, const vec<D>& q) {
    { v.value(q) } -> std::convertible_to<double>;
    { v.gradient(q) } -> std::convertible_to<vec<D>>;
    { v.hessian(q) } -> std::convertible_to<mat<D>>;
};

/// Optional on a potential: `gradients(q, count, g)`, ∇V at `count` points at once (q and g
/// d × count, column-major), for a potential whose cost per call is mostly overhead (an
/// interpreted expression, expression_separable.hpp). The family stepper then evaluates a
/// sweep's points in one call. It must give gradient()'s values.
template <class P>
concept batch_potential = requires(const P& v, const double* q, int count, double* g) {
    v.gradients(q, count, g);
};

/// Optional on a potential: `gradient_and_hessian(q, g, h)`, ∇V and ∇²V at one point in one
/// evaluation (their common subexpressions once), for the Newton iterations of Simpson's and
/// Newmark's stage equation, which need both. It must give gradient()'s and hessian()'s values.
template <class P, int D>
concept joint_potential = requires(const P& v, const vec<D>& q, vec<D>& g, mat<D>& h) {
    v.gradient_and_hessian(q, g, h);
};

/// Optional on a potential: `gradient(q, g)`, ∇V at q written into g (sized by the caller or
/// by the member), for potentials at a run-time dimension: the steppers then keep g across
/// steps instead of receiving a newly allocated vector at every call. It must give
/// gradient(q)'s values.
template <class P, int D>
concept in_place_gradient = requires(const P& v, const vec<D>& q, vec<D>& g) {
    v.gradient(q, g);
};

/// g = ∇V(q), in place when the potential can (in_place_gradient).
template <int D, class P>
void gradient_into(const P& v, const vec<D>& q, vec<D>& g) {
    if constexpr (in_place_gradient<P, D>)
        v.gradient(q, g);
    else
        g = v.gradient(q);
}

/// The protocol of a separable system L = ½ q̇ᵀ M q̇ − V(q), which the Simpson, Newmark and family
/// steppers take: `dim` (a size ≥ 1, or `dynamic` when d is known only at run time),
/// `dimension()`, a constant mass M and its inverse (a matrix, or one number for M = m I), the
/// potential's gradient and Hessian, and the energy. Optional: a member
/// `solve_stage(c, q, r, delta, opt, workspace)` with its type `stage_workspace`, replacing the
/// dense Newton on M δ + c ∇V(q + δ) = r (solvers/stage_equation.hpp), e.g. by a banded solve.
template <class S>
concept separable = requires {
    S::dim;
}
&&(S::dim >= 1 || S::dim == dynamic) && requires(const S& s, const phase_state<S::dim>& x) {
    { s.dimension() } -> std::convertible_to<int>;
    s.mass();
    s.inverse_mass();
    { s.potential().value(x.q) } -> std::convertible_to<double>;
    { s.potential().gradient(x.q) } -> std::convertible_to<vec<S::dim>>;
    s.potential().hessian(x.q);
    { s.energy(x) } -> std::convertible_to<double>;
};

/// True when the system's mass is one number m (M = m I) rather than a matrix.
template <class S>
inline constexpr bool scalar_mass =
    std::is_arithmetic_v<std::remove_cvref_t<decltype(std::declval<const S&>().mass())>>;

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
        // At dynamic size: one instantiation serves every dimension (about 1.2 s of compile
        // time each), for a factorisation done once.
        const Eigen::LLT<Eigen::MatrixXd> llt(mass_);
        if (llt.info() != Eigen::Success || mass_.rows() == 0)
            throw std::invalid_argument("mass matrix is not positive definite");
        inv_mass_ = llt.solve(Eigen::MatrixXd::Identity(mass_.rows(), mass_.cols()));
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
