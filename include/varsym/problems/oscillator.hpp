// varsym/problems/oscillator.hpp: the d-dimensional harmonic oscillator L = ½ q̇ᵀMq̇ − ½ qᵀKq
// with symmetric positive definite M and K, and its exact solution by normal modes.
//
// Units: whatever the user's M and K are in; q in the unit of length, p = M q̇. Frequencies ω_i
// solve K φ = ω² M φ; the period reported is the slowest mode's, 2π/ω_min.
#pragma once

#include <cmath>
#include <numbers>
#include <stdexcept>

#include <Eigen/Eigenvalues>

#include "varsym/systems/separable.hpp"

namespace varsym::oscillator {

/// V(q) = ½ qᵀ K q (dimension chosen at run time).
struct potential {
    Eigen::MatrixXd k;
    [[nodiscard]] double value(const vec<dynamic>& q) const { return 0.5 * q.dot(k * q); }
    [[nodiscard]] vec<dynamic> gradient(const vec<dynamic>& q) const { return k * q; }
    [[nodiscard]] mat<dynamic> hessian(const vec<dynamic>&) const { return k; }
    /// The same into g (and h), keeping their storage: a step then allocates nothing.
    void gradient(const vec<dynamic>& q, vec<dynamic>& g) const { g.noalias() = k * q; }
    void gradient_and_hessian(const vec<dynamic>& q, vec<dynamic>& g, mat<dynamic>& h) const {
        g.noalias() = k * q;
        h = k;
    }
};

using system = separable_system<dynamic, potential>;

/// The system, refusing a K that is not symmetric positive definite (a non-positive frequency)
/// or whose size differs from M's. (This and basic_exact_solution are templates only so that a
/// file including this header without using them compiles none of their Eigen solvers.)
template <int Unused = 0>
system make_system(const Eigen::MatrixXd& m, const Eigen::MatrixXd& k) {
    if (k.rows() != m.rows() || k.cols() != m.cols())
        throw std::invalid_argument("mass and stiffness matrices must have the same size");
    if (!k.allFinite() || !k.isApprox(k.transpose(), 1e-14))
        throw std::invalid_argument("stiffness matrix must be finite and symmetric");
    const Eigen::LLT<Eigen::MatrixXd> llt(k);
    if (llt.info() != Eigen::Success)
        throw std::invalid_argument("stiffness matrix is not positive definite (some frequency "
                                    "would be zero or imaginary)");
    return system(m, potential{k});
}

/// q(t), p(t) from (q₀, p₀) by the modes Φ (ΦᵀMΦ = I, ΦᵀKΦ = diag ω²): η = Φᵀ M q,
/// η(t) = η₀ cos ωt + (η̇₀/ω) sin ωt with η̇₀ = Φᵀ p₀, and q = Φ η, p = M Φ η̇.
template <int Unused = 0>
class basic_exact_solution {
  public:
    basic_exact_solution(const Eigen::MatrixXd& m, const Eigen::MatrixXd& k,
                         const phase_state<dynamic>& x0)
        : m_(m) {
        const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(k, m);
        if (eig.info() != Eigen::Success || eig.eigenvalues().minCoeff() <= 0.0)
            throw std::invalid_argument("K phi = omega^2 M phi has a non-positive eigenvalue");
        omega_ = eig.eigenvalues().cwiseSqrt();
        modes_ = eig.eigenvectors();
        eta0_ = modes_.transpose() * (m * x0.q);
        rate0_ = modes_.transpose() * x0.p;
    }
    [[nodiscard]] const Eigen::VectorXd& frequencies() const { return omega_; }
    [[nodiscard]] double period() const { return 2.0 * std::numbers::pi / omega_.minCoeff(); }
    [[nodiscard]] phase_state<dynamic> at(double t) const {
        const Eigen::ArrayXd wt = omega_.array() * t;
        const Eigen::VectorXd eta =
            (eta0_.array() * wt.cos() + rate0_.array() / omega_.array() * wt.sin()).matrix();
        const Eigen::VectorXd rate =
            (rate0_.array() * wt.cos() - eta0_.array() * omega_.array() * wt.sin()).matrix();
        return {modes_ * eta, m_ * (modes_ * rate)};
    }

  private:
    Eigen::MatrixXd m_, modes_;
    Eigen::VectorXd omega_, eta0_, rate0_;
};

using exact_solution = basic_exact_solution<>;

} // namespace varsym::oscillator
