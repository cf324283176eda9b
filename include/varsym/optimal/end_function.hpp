// varsym/optimal/end_function.hpp: a function φ(q) of the final position that an optimal control
// problem drives to zero at T (control_problem::end_target), as a constraint or as a terminal
// cost: a robot frame's distance to a target pose (models::frame_target), where a roboticist
// says "reach this point" rather than giving joint angles. Eigen only.
// See docs/optimal_control.md.
#pragma once

#include <algorithm>
#include <cmath>

#include <Eigen/Core>

namespace varsym::optimal {

/// φ: R^d → R^k with its Jacobian and the curvature Σ_a w_a ∇²φ_a. Implementations are
/// immutable after construction and may be called from several threads.
class end_function {
  public:
    end_function() = default;
    end_function(const end_function&) = default;
    end_function& operator=(const end_function&) = default;
    end_function(end_function&&) = default;
    end_function& operator=(end_function&&) = default;
    virtual ~end_function() = default;

    [[nodiscard]] virtual int dimension() const = 0; ///< d, the coordinates it takes
    [[nodiscard]] virtual int rows() const = 0;      ///< k ≥ 1, its values
    /// φ(q) into `value` (k) and, if `jacobian`, ∂φ/∂q into it (k × d).
    virtual void evaluate(const Eigen::VectorXd& q, Eigen::VectorXd& value,
                          Eigen::MatrixXd* jacobian) const = 0;
    /// Σ_a w_a ∇²φ_a(q) (d × d, symmetric). By default a central difference of wᵀ ∂φ/∂q (step
    /// 6e-6 max(1, |q|): relative error about 1e-10 on a smooth φ), symmetrised.
    virtual void curvature(const Eigen::VectorXd& q, const Eigen::VectorXd& w,
                           Eigen::MatrixXd& out) const {
        const auto d = q.size();
        out.setZero(d, d);
        const double eps = 6e-6 * std::max(1.0, q.lpNorm<Eigen::Infinity>());
        Eigen::VectorXd qs = q, value;
        Eigen::MatrixXd jac;
        for (Eigen::Index i = 0; i < d; ++i)
            for (const double sign : {1.0, -1.0}) {
                qs(i) = q(i) + sign * eps;
                evaluate(qs, value, &jac);
                out.col(i) += sign / (2.0 * eps) * (jac.transpose() * w);
                qs(i) = q(i);
            }
        out = 0.5 * (out + out.transpose()).eval();
    }
};

} // namespace varsym::optimal
