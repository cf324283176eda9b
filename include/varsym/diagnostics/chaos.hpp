// varsym/diagnostics/chaos.hpp: chaos indicators along a run, from a deviation vector carried by
// the steps' tangent maps (the discrete variational equations; Ch. Skokos and E. Gerlach,
// "Numerical integration of variational equations", Phys. Rev. E 82, 036704, 2010, the "tangent
// map method"): the maximal Lyapunov exponent and MEGNO.
//
// With δ_k the deviation after k steps (renormalised to |δ| = 1 after every step, its growth
// factors a_k = |J_k δ_{k−1}| kept as logarithms), t_k = k h:
//   λ(t_n) = (1/t_n) Σ_{k≤n} ln a_k                         (Benettin et al., Meccanica 15, 1980)
//   Y(t_n) = (2/n) Σ_{k≤n} k ln a_k,  ⟨Y⟩(t_n) = (1/n) Σ_{k≤n} Y(t_k)
// (MEGNO, the mean exponential growth factor of nearby orbits, in its discrete form: P. M.
// Cincotta and C. Simó, Astron. Astrophys. Suppl. 147, 205–228, 2000; P. M. Cincotta, C. M.
// Giordano and C. Simó, Physica D 182, 151–178, 2003). For a quasi-periodic orbit whose
// deviations grow linearly (the generic shear of a torus), ⟨Y⟩ → 2; for a motion whose deviations
// stay bounded (an isochronous oscillator, a stable periodic orbit), ⟨Y⟩ → 0; for a chaotic one
// ⟨Y⟩ ≈ λ t / 2 grows linearly, and λ → its positive exponent. Units: λ in 1/time; Y, ⟨Y⟩
// dimensionless. The deviation's norm is the Euclidean norm of (δq, δp) in the model's units.
#pragma once

#include <cmath>
#include <stdexcept>

#include <Eigen/Dense>

#include "varsym/stepper.hpp"

namespace varsym {

/// A stepper that gives its step's tangent map ∂(q_{j+1}, p_{j+1})/∂(q_j, p_j) after a step:
/// simpson, newmark, galerkin and general steppers.
template <class S>
concept tangent_stepper = stepper<S> &&
    requires(S& s, const phase_state<S::dim>& x, Eigen::MatrixXd& j) {
    s.step_jacobian(x, j);
};

/// The maximal Lyapunov exponent and MEGNO of one run, fed one tangent map per step.
class chaos_indicators {
  public:
    /// Starts from the deviation `deviation` (2d numbers, (δq, δp) order, not all zero) with
    /// steps of size h > 0.
    chaos_indicators(const Eigen::VectorXd& deviation, double h) : delta_(deviation), h_(h) {
        const double n = delta_.norm();
        if (!(n > 0.0 && std::isfinite(n)))
            throw std::invalid_argument("the initial deviation must be finite and not zero");
        if (!(h > 0.0 && std::isfinite(h)))
            throw std::invalid_argument("the step size must be finite and positive");
        delta_ /= n;
    }
    /// The deviation (1, 1, …, 1)/sqrt(2d): every direction, no preferred one, reproducible.
    chaos_indicators(int d, double h) : chaos_indicators(Eigen::VectorXd::Ones(2 * d), h) {}

    /// One step: δ ← J δ / |J δ|, with J that step's tangent map. False if J δ is zero or not
    /// finite: the indicators then keep their values and ok() turns false for good.
    bool advance(const Eigen::MatrixXd& j) {
        if (failed_) return false;
        next_.noalias() = j * delta_;
        const double a = next_.norm();
        if (!(a > 0.0 && std::isfinite(a))) {
            failed_ = true;
            return false;
        }
        delta_ = next_ / a;
        const double growth = std::log(a);
        ++n_;
        const auto k = static_cast<double>(n_);
        sum_log_ += growth;
        weighted_ += k * growth;
        const double y = 2.0 * weighted_ / k;
        sum_y_ += y;
        megno_ = y;
        return true;
    }

    /// False once a tangent map gave a zero or non-finite deviation (the values stop there).
    [[nodiscard]] bool ok() const { return !failed_; }
    [[nodiscard]] long long steps() const { return n_; }
    [[nodiscard]] double time() const { return static_cast<double>(n_) * h_; }
    /// λ(t) = (1/t) Σ ln a_k; 0 before the first step.
    [[nodiscard]] double lyapunov() const { return n_ == 0 ? 0.0 : sum_log_ / time(); }
    /// Y(t), MEGNO itself (it oscillates; its running mean is the indicator).
    [[nodiscard]] double megno() const { return megno_; }
    /// ⟨Y⟩(t), the running mean of MEGNO.
    [[nodiscard]] double mean_megno() const {
        return n_ == 0 ? 0.0 : sum_y_ / static_cast<double>(n_);
    }
    /// The current deviation, of unit norm.
    [[nodiscard]] const Eigen::VectorXd& deviation() const { return delta_; }

  private:
    Eigen::VectorXd delta_, next_;
    double h_;
    long long n_ = 0;
    bool failed_ = false;
    double sum_log_ = 0.0, weighted_ = 0.0, sum_y_ = 0.0, megno_ = 0.0;
};

/// One step of s from x that also advances the indicators by the step's tangent map (`j` is
/// scratch space, reused across calls). The indicators are left alone if the step fails.
template <tangent_stepper S>
newton_report step_with_tangent(S& s, phase_state<S::dim>& x, chaos_indicators& c,
                                Eigen::MatrixXd& j) {
    const phase_state<S::dim> from = x;
    const newton_report rep = s.step(x);
    if (!rep.converged) return rep;
    s.step_jacobian(from, j);
    c.advance(j);
    return rep;
}

} // namespace varsym
