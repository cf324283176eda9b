// varsym/optimal/nlp.hpp: a nonlinear program min f(x) subject to g(x) = c, bounds on x, with
// sparse first derivatives, as the optimal control transcription (optimize/transcription.hpp)
// states it and a solver (the IPOPT adapter of varsym::optimal, optimal/solve.hpp) consumes it.
// Eigen only.
// See docs/optimal_control.md.
#pragma once

#include <limits>
#include <vector>

#include <Eigen/Core>

namespace varsym::optimal {

inline constexpr double unbounded = std::numeric_limits<double>::infinity();

using vector = Eigen::VectorXd;
using cvector = Eigen::Ref<const Eigen::VectorXd>;

/// A sparse matrix's pattern as triplets (row, column): the values come in the same order.
/// An entry may appear more than once; its values add up (IPOPT's convention).
struct sparsity {
    std::vector<int> rows, cols;
    [[nodiscard]] int size() const { return static_cast<int>(rows.size()); }
    void add(int r, int c) {
        rows.push_back(r);
        cols.push_back(c);
    }
    /// The matrix of `values` (in this pattern's order) as a dense n_rows × n_cols matrix,
    /// repeated entries summed: for checking a transcription's derivatives, and small problems.
    [[nodiscard]] Eigen::MatrixXd dense(const std::vector<double>& values, int n_rows,
                                        int n_cols) const {
        Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n_rows, n_cols);
        for (std::size_t i = 0; i < rows.size(); ++i)
            a(rows[i], cols[i]) += values[i];
        return a;
    }
};

/// min f(x) over x ∈ Rⁿ subject to g_lower ≤ g(x) ≤ g_upper (m rows: equations g(x) = 0 by
/// default, constraint_bounds()) and x_lower ≤ x ≤ x_upper (± unbounded where there is no
/// bound; equal bounds fix x_i).
class nlp {
  public:
    nlp() = default;
    nlp(const nlp&) = default;
    nlp& operator=(const nlp&) = default;
    nlp(nlp&&) = default;
    nlp& operator=(nlp&&) = default;
    virtual ~nlp() = default;

    [[nodiscard]] virtual int variables() const = 0;
    [[nodiscard]] virtual int constraints() const = 0;
    virtual void bounds(vector& lower, vector& upper) const = 0;
    /// The bounds of g's rows: 0 and 0 (equations) unless overridden for inequality rows.
    virtual void constraint_bounds(vector& lower, vector& upper) const {
        lower = upper = vector::Zero(constraints());
    }
    /// How far g(x) lies outside its bounds, row by row (g itself for equations).
    [[nodiscard]] vector constraint_violation(cvector x) const {
        vector g, lower, upper;
        residual(x, g);
        constraint_bounds(lower, upper);
        return (g - g.cwiseMax(lower).cwiseMin(upper)).eval();
    }
    [[nodiscard]] virtual vector start() const = 0;
    [[nodiscard]] virtual double cost(cvector x) const = 0;
    virtual void cost_gradient(cvector x, vector& gradient) const = 0;
    virtual void residual(cvector x, vector& g) const = 0;
    [[nodiscard]] virtual sparsity jacobian_pattern() const = 0;
    /// The Jacobian ∂g/∂x at x, its values in jacobian_pattern()'s order.
    virtual void jacobian(cvector x, std::vector<double>& values) const = 0;
    /// Whether hessian() gives the exact Hessian of the Lagrangian σ f + Σ λ_i g_i (its lower
    /// triangle); otherwise the solver approximates it (limited-memory BFGS).
    [[nodiscard]] virtual bool has_hessian() const { return false; }
    [[nodiscard]] virtual sparsity hessian_pattern() const { return {}; }
    virtual void hessian(cvector /*x*/, double /*sigma*/, cvector /*lambda*/,
                         std::vector<double>& /*values*/) const {}
};

} // namespace varsym::optimal
