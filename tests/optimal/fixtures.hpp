// What the optimal control tests share: inputs that are the generalized forces themselves, a
// fully actuated two-link arm, and the check of a transcription's derivatives against central
// differences.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "varsym/optimal/nlp.hpp"
#include "varsym/optimal/system.hpp"
#include "varsym/systems/lagrangian.hpp"

namespace varsym::optimal_test {

/// f = gain u: every coordinate driven by its own input (a torque on an angle, a force on a
/// length); gain 0 makes inputs that act on nothing.
template <int D>
struct direct_input {
    static constexpr int dim = D, controls = D;
    double gain = 1.0;
    template <class T>
    tvec<T, D> operator()(const tvec<T, D>&, const tvec<T, D>&, double, const tvec<T, D>& u) const {
        tvec<T, D> f;
        for (int i = 0; i < D; ++i)
            f(i) = gain * u(i);
        return f;
    }
};

/// One coordinate, L = ½ q̇² − ½ k q² + g cos q: the free mass (k = g = 0), the harmonic
/// oscillator (k = 1), the pendulum from hanging (g). One type for every one-coordinate test, so
/// that its transcription is compiled once (about 40 s each).
struct one_dof {
    static constexpr int dim = 1;
    double spring = 0.0, gravity = 0.0;
    template <class T>
    T operator()(const tvec<T, 1>& q, const tvec<T, 1>& v) const {
        using std::cos;
        return 0.5 * v(0) * v(0) - 0.5 * spring * q(0) * q(0) + gravity * cos(q(0));
    }
};

/// A two-link arm in a vertical plane, relative angles from hanging (uniform links of 1 kg and
/// 1 m): a mass matrix that depends on q2, so L's third derivatives are all there.
struct two_link {
    static constexpr int dim = 2;
    double g = 9.81;
    template <class T>
    T operator()(const tvec<T, 2>& q, const tvec<T, 2>& v) const {
        using std::cos;
        const double m = 1.0, l = 1.0, lc = 0.5, i = 1.0 / 12.0;
        const T c2 = cos(q(1));
        const T m11 = m * lc * lc + m * (l * l + lc * lc + 2.0 * l * lc * c2) + 2.0 * i;
        const T m12 = m * (lc * lc + l * lc * c2) + i;
        const double m22 = m * lc * lc + i;
        const T kinetic = 0.5 * m11 * v(0) * v(0) + m12 * v(0) * v(1) + 0.5 * m22 * v(1) * v(1);
        return kinetic + (m * lc + m * l) * g * cos(q(0)) + m * lc * g * cos(q(0) + q(1));
    }
};

/// The largest differences between a transcription's derivatives at x and central differences
/// (step 1e-6: truncation O(1e-12) times third derivatives, round-off O(1e-10) on values of
/// size ≤ 1e2): the cost's gradient, the Jacobian of the equations, and, where the transcription
/// has it, the Hessian of σJ + λᵀg against differences of σ∇J + (∂g/∂x)ᵀλ.
struct derivative_errors {
    double gradient = 0.0, jacobian = 0.0;
    double hessian = std::numeric_limits<double>::quiet_NaN();
    double largest_hessian = 0.0, largest_jacobian = 0.0, largest_gradient = 0.0; ///< scales
};

/// Two transcriptions of one problem compared: the largest |a_ij − b_ij| and |a_ij| over their
/// Hessians of σJ + λᵀg at x as matrices (their patterns may differ: one may leave out entries
/// that the other stores as zeros), and whether they have as many unknowns.
struct value_gap {
    double worst = 0.0, largest = 0.0;
    bool same_size = false;
};
inline value_gap hessian_gap(const optimal::nlp& first, const optimal::nlp& second,
                             const Eigen::VectorXd& x, double sigma,
                             const Eigen::VectorXd& lambda) {
    value_gap g;
    const int n = first.variables();
    g.same_size = n == second.variables() && first.constraints() == second.constraints();
    if (!g.same_size) return g;
    std::vector<double> a, b;
    first.hessian(x, sigma, lambda, a);
    second.hessian(x, sigma, lambda, b);
    const Eigen::MatrixXd ha = first.hessian_pattern().dense(a, n, n),
                          hb = second.hessian_pattern().dense(b, n, n);
    g.worst = (ha - hb).cwiseAbs().maxCoeff();
    g.largest = ha.cwiseAbs().maxCoeff();
    return g;
}

/// A controlled system that forwards everything to another but does not declare its input
/// matrix constant (controlled_system::constant_input_matrix): its transcription keeps every
/// control block of the Jacobian and the Hessian dense, the reference for the structural zeros that
/// the other's leaves out.
class dense_inputs final : public optimal::controlled_system {
  public:
    using system = optimal::controlled_system;
    using matrix = optimal::matrix;
    using vector = optimal::vector;
    explicit dense_inputs(std::shared_ptr<const system> s) : s_(std::move(s)) {}
    [[nodiscard]] int dimension() const override { return s_->dimension(); }
    [[nodiscard]] int inputs() const override { return s_->inputs(); }
    [[nodiscard]] int constraint_count() const override { return s_->constraint_count(); }
    [[nodiscard]] bool time_dependent() const override { return s_->time_dependent(); }
    void gradient(const vector& q, const vector& v, double t,
                  lagrangian_terms<dynamic>& out) const override {
        s_->gradient(q, v, t, out);
    }
    void derivatives(const vector& q, const vector& v, double t,
                     lagrangian_terms<dynamic>& out) const override {
        s_->derivatives(q, v, t, out);
    }
    void third(const vector& q, const vector& v, double t, const vector& a, const vector& b,
               matrix& out) const override {
        s_->third(q, v, t, a, b, out);
    }
    [[nodiscard]] bool exact_third() const override { return s_->exact_third(); }
    void force(const vector& q, const vector& v, double t, const vector& u,
               optimal::input_terms& out, bool jacobians) const override {
        s_->force(q, v, t, u, out, jacobians);
    }
    void force_hessian(const vector& q, const vector& v, double t, const vector& u, const vector& a,
                       matrix& out) const override {
        s_->force_hessian(q, v, t, u, a, out);
    }
    void constraint(const vector& q, vector& g, matrix& jac) const override {
        s_->constraint(q, g, jac);
    }
    void constraint_curvature(const vector& q, const vector& lambda, matrix& out) const override {
        s_->constraint_curvature(q, lambda, out);
    }
    void constraint_hessian(const vector& q, const vector& impulse, const vector& a,
                            const vector& nu, matrix& out) const override {
        s_->constraint_hessian(q, impulse, a, nu, out);
    }
    void tangent(const vector& q, vector& p, vector& v, double t) const override {
        s_->tangent(q, p, v, t);
    }
    [[nodiscard]] std::optional<matrix> own_replay(const optimal::trajectory& path) const override {
        return s_->own_replay(path);
    }

  private:
    std::shared_ptr<const system> s_;
};

inline derivative_errors check_derivatives(const optimal::nlp& t, const Eigen::VectorXd& x,
                                           double sigma, const Eigen::VectorXd& lambda) {
    const int n = t.variables(), m = t.constraints();
    const double step = 1e-6;
    const auto jacobian = [&](const Eigen::VectorXd& y) {
        std::vector<double> v;
        t.jacobian(y, v);
        return Eigen::MatrixXd(t.jacobian_pattern().dense(v, m, n));
    };
    const auto gradient = [&](const Eigen::VectorXd& y) { // σ∇J + Jᵀλ
        Eigen::VectorXd g;
        t.cost_gradient(y, g);
        return Eigen::VectorXd(sigma * g + jacobian(y).transpose() * lambda);
    };
    derivative_errors out;
    Eigen::VectorXd g;
    t.cost_gradient(x, g);
    out.largest_gradient = g.size() > 0 ? g.cwiseAbs().maxCoeff() : 0.0;
    const Eigen::MatrixXd jac = jacobian(x);
    out.largest_jacobian = jac.cwiseAbs().maxCoeff();
    Eigen::MatrixXd hes(n, n);
    if (t.has_hessian()) {
        std::vector<double> values;
        t.hessian(x, sigma, lambda, values);
        hes = t.hessian_pattern().dense(values, n, n);
        hes = hes.selfadjointView<Eigen::Lower>();
        out.largest_hessian = hes.cwiseAbs().maxCoeff();
        out.hessian = 0.0;
    }
    for (int i = 0; i < n; ++i) {
        Eigen::VectorXd up = x, down = x, eu, ed;
        up(i) += step;
        down(i) -= step;
        t.residual(up, eu);
        t.residual(down, ed);
        out.jacobian =
            std::max(out.jacobian, ((eu - ed) / (2 * step) - jac.col(i)).cwiseAbs().maxCoeff());
        out.gradient =
            std::max(out.gradient, std::abs((t.cost(up) - t.cost(down)) / (2 * step) - g(i)));
        if (t.has_hessian())
            out.hessian = std::max(
                out.hessian,
                ((gradient(up) - gradient(down)) / (2 * step) - hes.col(i)).cwiseAbs().maxCoeff());
    }
    return out;
}

} // namespace varsym::optimal_test
