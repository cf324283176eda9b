// varsym/systems/expression_constraint.hpp: holonomic constraints g(q) = 0 given at run time as
// expressions over an expression Lagrangian's coordinates and parameters, one per equation,
// e.g. a pendulum as a point mass on a circle: {"x**2 + y**2 - l**2"}. The Jacobian G = ∂g/∂q
// and the Hessians ∇²g_a are differentiated symbolically once and compiled into straight-line
// code (expression/tape.hpp), which the constrained stepper evaluates
// (schemes/constrained.hpp; docs/mechanisms.md).
//
// A holonomic constraint depends on the configuration alone: an expression that names a
// velocity NAME_dot or the time t (after simplification) is refused.
#pragma once

#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "varsym/expression/tape.hpp"
#include "varsym/expression/variables.hpp"
#include "varsym/systems/constraints.hpp"

namespace varsym {

class expression_constraint {
  public:
    static constexpr int dim = dynamic, count = dynamic;

    /// g_a = equations[a] (zero on the constraint manifold). Throws expr::parse_error (naming
    /// the equation and the column) for an expression that does not parse or names something
    /// unknown, std::invalid_argument for no equation, bad names, or an expression that depends
    /// on a velocity or on t.
    expression_constraint(std::vector<std::string> equations, std::vector<std::string> coordinates,
                          std::vector<expression_parameter> parameters = {})
        : texts_(std::move(equations)), vars_(std::move(coordinates), std::move(parameters)) {
        if (texts_.empty()) throw std::invalid_argument("give at least one constraint g(q) = 0");
        const int d = dimension(), m = size();
        expr::graph g;
        std::vector<int> eq;
        for (int a = 0; a < m; ++a) {
            const std::string& text = texts_[static_cast<std::size_t>(a)];
            try {
                eq.push_back(vars_.parse(text, g));
            } catch (const expr::parse_error& e) {
                throw expr::parse_error("constraint " + std::to_string(a + 1) + ": " + e.what(),
                                        e.position());
            }
            for (int k = d; k <= 2 * d; ++k)
                if (!g.is(g.derivative(eq.back(), k), 0.0))
                    throw std::invalid_argument(
                        "constraint " + std::to_string(a + 1) + " (" + text + ") depends on " +
                        (k == 2 * d
                             ? std::string("the time t")
                             : "the velocity " +
                                   vars_.coordinates()[static_cast<std::size_t>(k - d)] + "_dot") +
                        ": a holonomic constraint g(q) = 0 is on the coordinates alone");
        }
        // first_: g_a, then G(a, i) row by row; second_: ∂²g_a/∂q_i∂q_j (i ≤ j) for each a.
        std::vector<int> first = eq, second;
        std::vector<int> grad(static_cast<std::size_t>(d));
        for (int a = 0; a < m; ++a) {
            for (int i = 0; i < d; ++i) {
                grad[static_cast<std::size_t>(i)] =
                    g.derivative(eq[static_cast<std::size_t>(a)], i);
                first.push_back(grad[static_cast<std::size_t>(i)]);
            }
            for (int i = 0; i < d; ++i)
                for (int j = i; j < d; ++j)
                    second.push_back(g.derivative(grad[static_cast<std::size_t>(i)], j));
        }
        value_ = expr::tape(g, eq, vars_.inputs());
        first_ = expr::tape(g, first, vars_.inputs());
        second_ = expr::tape(g, second, vars_.inputs());
        input_.assign(static_cast<std::size_t>(vars_.inputs()), 0.0);
    }

    [[nodiscard]] int dimension() const { return vars_.dimension(); }
    /// m, the number of equations.
    [[nodiscard]] int size() const { return static_cast<int>(texts_.size()); }
    [[nodiscard]] const std::vector<std::string>& equations() const { return texts_; }
    [[nodiscard]] const std::vector<std::string>& coordinates() const {
        return vars_.coordinates();
    }

    /// g(q).
    [[nodiscard]] vec<dynamic> operator()(const vec<dynamic>& q) const {
        value_.run(load(q));
        vec<dynamic> r(size());
        for (int a = 0; a < size(); ++a)
            r(a) = value_.output(static_cast<std::size_t>(a));
        return r;
    }
    /// G = ∂g/∂q (m × d).
    void jacobian(const vec<dynamic>& q, Eigen::MatrixXd& jac) const {
        const int d = dimension(), m = size();
        first_.run(load(q));
        jac.resize(m, d);
        std::size_t k = static_cast<std::size_t>(m);
        for (int a = 0; a < m; ++a)
            for (int i = 0; i < d; ++i)
                jac(a, i) = first_.output(k++);
    }
    /// H = Σ_a λ_a ∇²g_a(q) (d × d).
    void curvature(const vec<dynamic>& q, const vec<dynamic>& lambda, mat<dynamic>& h) const {
        second_.run(load(q));
        sum_hessians(
            lambda, [this](std::size_t k) { return second_.output(k); }, h);
    }

    /// Σ_a λ_a times the rate of ∇²g_a(q) along dq (d × d): g's third derivatives contracted
    /// with dq and λ, exact (the code of ∇²g run forward along dq, expr::tape::run_tangent). An
    /// optimal control transcription's exact Hessian needs them for the impulses −G(q)ᵀΛ.
    void curvature_rate(const vec<dynamic>& q, const vec<dynamic>& dq, const vec<dynamic>& lambda,
                        mat<dynamic>& h) const {
        const int d = dimension();
        const std::span<const double> in = load(q);
        direction_.assign(in.size(), 0.0);
        for (int i = 0; i < d; ++i)
            direction_[static_cast<std::size_t>(i)] = dq(i);
        second_.run_tangent(in.data(), direction_.data(), static_cast<int>(in.size()));
        sum_hessians(
            lambda, [this](std::size_t k) { return second_.tangent(k); }, h);
    }

  private:
    /// Σ_a λ_a H_a into h (d × d), H_a's upper triangle (i ≤ j, row by row) from read(k), the
    /// k-th output of the code of ∇²g (its values or its rates).
    template <class Read>
    void sum_hessians(const vec<dynamic>& lambda, Read read, mat<dynamic>& h) const {
        const int d = dimension(), m = size();
        h.setZero(d, d);
        std::size_t k = 0;
        for (int a = 0; a < m; ++a)
            for (int i = 0; i < d; ++i)
                for (int j = i; j < d; ++j) {
                    const double v = lambda(a) * read(k++);
                    h(i, j) += v;
                    if (j != i) h(j, i) += v;
                }
    }

    // q into the inputs; the velocities and t stay 0 (nothing here depends on them).
    std::span<const double> load(const vec<dynamic>& q) const {
        if (q.size() != dimension())
            throw std::invalid_argument("q must have " + std::to_string(dimension()) +
                                        " entries, one per coordinate");
        for (int i = 0; i < dimension(); ++i)
            input_[static_cast<std::size_t>(i)] = q(i);
        return input_;
    }

    std::vector<std::string> texts_;
    expr::variables vars_;
    expr::tape value_, first_, second_;
    mutable std::vector<double> input_, direction_;
};

} // namespace varsym
