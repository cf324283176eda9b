// varsym/optimal/dmoc.hpp: discrete mechanics and optimal control (DMOC; Ober-Blöbaum, Junge &
// Marsden 2011) at every member of the variational family. The unknowns are the control values
// Q of every step's polynomial (nodes shared between steps) and the controls u at the steps'
// quadrature points; the equations are the discrete Lagrange–d'Alembert equations of the
// trajectory, one per control value, with the boundary momenta; the running cost (costs.hpp) by the
// action's quadrature. Exact sparse first derivatives from L's second derivatives. Eigen only;
// solved by varsym::optimal's IPOPT adapter (optimal/solve.hpp). See docs/optimal_control.md.
#pragma once

#include <memory>
#include <utility>

#include "varsym/autodiff/second_order.hpp"
#include "varsym/optimal/costs.hpp"
#include "varsym/optimal/problem.hpp"
#include "varsym/optimal/replay.hpp"
#include "varsym/optimal/third_order.hpp"
#include "varsym/schemes/tableau.hpp"
#include "varsym/systems/lagrangian.hpp"

namespace varsym::optimal {

/// A transcription whose system is known at run time only (the models layer's): the NLP, the
/// trajectory of a result and its closure check.
class transcription : public nlp {
  public:
    [[nodiscard]] virtual const control_problem& problem() const = 0;
    [[nodiscard]] virtual trajectory unpack(const nlp_result& result) const = 0;
    /// The general engine's nodes under the trajectory's controls (replay.hpp): 2d × (N + 1).
    [[nodiscard]] virtual Eigen::MatrixXd replay(const trajectory& path) const = 0;
};

/// The transcription of a control_problem for the Lagrangian L and the control force F.
/// Unknowns x = (Q_0 … Q_{Ns}, u_{0,0} … u_{N−1,r−1}): Q_g = q((k + d_i) h) for g = k s + i,
/// u_{k,j} = u((k + c_j) h). Equations E_g = 0, g = 0 … N s, d each:
///   E_g = Σ_{(k,i): ks+i=g} h Σ_j w_j [ℓ_i(c_j) (∂L/∂q + f)(q_kj, v_kj, u_kj) + ℓ_i'(c_j)/h ∂L/∂q̇]
///         + [g = 0] p_start − [g = N s] p_end,
/// with q_kj = Σ_l ℓ_l(c_j) Q_{ks+l}, v_kj = Σ_l ℓ_l'(c_j) Q_{ks+l} / h: the discrete
/// Lagrange–d'Alembert equations (interior values, nodes between steps) and the discrete
/// Legendre transforms at both ends. Cost Σ_k h Σ_j w_j ½ u_kjᵀ R u_kj.
template <lagrangian L, control_force F>
class dmoc final : public transcription {
  public:
    static constexpr int D = L::dim, M = F::controls;
    static_assert(F::dim == L::dim, "the control force must have the Lagrangian's dimension");

    dmoc(L l, F force, const control_problem& problem)
        : l_(std::move(l)), f_(std::move(force)), p_(detail::checked(problem, D, M)),
          tab_(galerkin::tableau::make(family_member(p_.scheme).first,
                                       family_member(p_.scheme).second)) {
        s_ = tab_.degree;
        r_ = static_cast<int>(tab_.quad.size());
        n_ = p_.steps;
        h_ = p_.time / n_;
        points_ = n_ * s_ + 1;
        lagrangian_terms<D> t;
        evaluate_gradient(l_, vec<D>(p_.q_start), vec<D>(p_.v_start), 0.0, t);
        p_start_ = t.lv;
        evaluate_gradient(l_, vec<D>(p_.q_end), vec<D>(p_.v_end), p_.time, t);
        p_end_ = t.lv;
    }

    [[nodiscard]] const control_problem& problem() const override { return p_; }
    [[nodiscard]] const galerkin::tableau& table() const { return tab_; }
    [[nodiscard]] int variables() const override { return points_ * D + n_ * r_ * M; }
    [[nodiscard]] int constraints() const override { return points_ * D; }

    void bounds(vector& lower, vector& upper) const override {
        lower.resize(variables());
        upper.resize(variables());
        for (int g = 0; g < points_; ++g) {
            lower.segment<D>(g * D) = p_.position_lower;
            upper.segment<D>(g * D) = p_.position_upper;
        }
        lower.head<D>() = upper.head<D>() = p_.q_start; // fixed ends
        lower.segment<D>((points_ - 1) * D) = upper.segment<D>((points_ - 1) * D) = p_.q_end;
        for (int c = 0; c < n_ * r_; ++c) {
            lower.segment<M>(control_index(c)) = p_.control_lower;
            upper.segment<M>(control_index(c)) = p_.control_upper;
        }
    }

    /// The positions interpolated linearly between the ends, the controls zero (clipped into
    /// their bounds).
    [[nodiscard]] vector start() const override {
        vector x = vector::Zero(variables());
        const double span = static_cast<double>(points_ - 1);
        for (int g = 0; g < points_; ++g) {
            const double a = static_cast<double>(g) / span;
            x.segment<D>(g * D) = (1.0 - a) * p_.q_start + a * p_.q_end;
        }
        for (int c = 0; c < n_ * r_; ++c)
            x.segment<M>(control_index(c)) =
                vec<M>::Zero().cwiseMax(p_.control_lower).cwiseMin(p_.control_upper);
        return x;
    }

    [[nodiscard]] double cost(cvector x) const override {
        double j = 0.0;
        for (int k = 0; k < n_; ++k)
            for (int q = 0; q < r_; ++q)
                j += h_ * weight(q) * integrand(x, k, q, nullptr, nullptr);
        return j;
    }
    void cost_gradient(cvector x, vector& gradient) const override {
        gradient.setZero(variables());
        typename cost_type::zvec g;
        for (int k = 0; k < n_; ++k)
            for (int j = 0; j < r_; ++j) {
                (void)integrand(x, k, j, &g, nullptr);
                const double hw = h_ * weight(j);
                for (int l = 0; l <= s_; ++l)
                    gradient.segment<D>((k * s_ + l) * D) +=
                        hw * (tab_.phi(l, j) * g.template head<D>() +
                              tab_.dphi(l, j) / h_ * g.template segment<D>(D));
                gradient.segment<M>(control_index(k * r_ + j)) += hw * g.template tail<M>();
            }
    }

    void residual(cvector x, vector& e) const override {
        e.setZero(constraints());
        lagrangian_terms<D> lt;
        for (int k = 0; k < n_; ++k)
            for (int j = 0; j < r_; ++j) {
                vec<D> q, v;
                point(x, k, j, q, v);
                const double t = (k + tab_.quad.nodes[static_cast<std::size_t>(j)]) * h_;
                evaluate_gradient(l_, q, v, t, lt);
                const vec<D> force = f_(q, v, t, vec<M>(x.segment<M>(control_index(k * r_ + j))));
                const vec<D> lq = h_ * weight(j) * (lt.lq + force), lv = weight(j) * lt.lv;
                for (int i = 0; i <= s_; ++i) // the discrete forced Euler–Lagrange equations
                    e.segment<D>((k * s_ + i) * D) += tab_.phi(i, j) * lq + tab_.dphi(i, j) * lv;
            }
        e.head<D>() += p_start_;                   // p_0 = −D₁L_d − f⁻
        e.segment<D>((points_ - 1) * D) -= p_end_; // p_N = D₂L_d + f⁺
    }

    [[nodiscard]] sparsity jacobian_pattern() const override {
        sparsity s;
        const int w = (s_ + 1) * D;
        for (int k = 0; k < n_; ++k) {
            for (int row = 0; row < w; ++row)
                for (int col = 0; col < w; ++col)
                    s.add(k * s_ * D + row, k * s_ * D + col);
            for (int row = 0; row < w; ++row)
                for (int col = 0; col < r_ * M; ++col)
                    s.add(k * s_ * D + row, control_index(k * r_) + col);
        }
        return s;
    }

    void jacobian(cvector x, std::vector<double>& values) const override {
        const int w = (s_ + 1) * D;
        values.assign(static_cast<std::size_t>(n_) * static_cast<std::size_t>(w * (w + r_ * M)),
                      0.0);
        Eigen::MatrixXd bq(w, w), bu(w, r_ * M);
        lagrangian_terms<D> lt;
        control_terms<F> ft;
        std::size_t at = 0;
        for (int k = 0; k < n_; ++k) {
            bq.setZero();
            bu.setZero();
            for (int j = 0; j < r_; ++j) {
                vec<D> q, v;
                point(x, k, j, q, v);
                const double t = (k + tab_.quad.nodes[static_cast<std::size_t>(j)]) * h_;
                evaluate(l_, q, v, t, lt);
                ft.evaluate(f_, q, v, t, vec<M>(x.segment<M>(control_index(k * r_ + j))));
                const double hw = h_ * weight(j);
                const mat<D> qq = hw * (lt.lqq + ft.fq), qv = weight(j) * (lt.lqv + ft.fv),
                             vq = weight(j) * lt.lqv.transpose(), vv = weight(j) / h_ * lt.lvv;
                for (int i = 0; i <= s_; ++i) {
                    const double pi = tab_.phi(i, j), di = tab_.dphi(i, j);
                    for (int m = 0; m <= s_; ++m) {
                        const double pm = tab_.phi(m, j), dm = tab_.dphi(m, j);
                        bq.block<D, D>(i * D, m * D) +=
                            pi * pm * qq + pi * dm * qv + di * pm * vq + di * dm * vv;
                    }
                    bu.block<D, M>(i * D, j * M) += hw * pi * ft.fu;
                }
            }
            for (int row = 0; row < w; ++row)
                for (int col = 0; col < w; ++col)
                    values[at++] = bq(row, col);
            for (int row = 0; row < w; ++row)
                for (int col = 0; col < r_ * M; ++col)
                    values[at++] = bu(row, col);
        }
    }

    /// Exact, except with the invariant cost (whose Hessian needs L's fourth derivatives).
    [[nodiscard]] bool has_hessian() const override { return p_.cost.invariant == 0.0; }

    /// Lower triangle of each step's dense block over its control values and its controls.
    [[nodiscard]] sparsity hessian_pattern() const override {
        sparsity s;
        const int w = (s_ + 1) * D + r_ * M;
        for (int k = 0; k < n_; ++k)
            for (int row = 0; row < w; ++row)
                for (int col = 0; col <= row; ++col)
                    s.add(step_index(k, row), step_index(k, col));
        return s;
    }

    /// σ ∇²J + Σ_g λ_gᵀ ∇²E_g: each quadrature point's h w_j ψ with ψ = aᵀ(∂L/∂q + f) +
    /// (b/h)ᵀ ∂L/∂q̇, a = Σ_i ℓ_i(c_j) λ_{ks+i}, b = Σ_i ℓ_i'(c_j) λ_{ks+i}, pulled back to
    /// (Q_{ks} … Q_{ks+s}, u_kj) through z = (q, v, u) = G (Q, u).
    void hessian(cvector x, double sigma, cvector lambda,
                 std::vector<double>& values) const override {
        const int w = (s_ + 1) * D + r_ * M, wq = (s_ + 1) * D;
        values.assign(static_cast<std::size_t>(n_) * static_cast<std::size_t>(w * (w + 1) / 2),
                      0.0);
        Eigen::MatrixXd hk(w, w), g = Eigen::MatrixXd::Zero(2 * D + M, w);
        Eigen::Matrix<double, 2 * D + M, 2 * D + M> hz;
        std::size_t at = 0;
        for (int k = 0; k < n_; ++k) {
            hk.setZero();
            for (int j = 0; j < r_; ++j) {
                vec<D> q, v, a = vec<D>::Zero(), b = vec<D>::Zero();
                point(x, k, j, q, v);
                for (int i = 0; i <= s_; ++i) {
                    a += tab_.phi(i, j) * lambda.segment<D>((k * s_ + i) * D);
                    b += tab_.dphi(i, j) / h_ * lambda.segment<D>((k * s_ + i) * D);
                }
                const double t = (k + tab_.quad.nodes[static_cast<std::size_t>(j)]) * h_;
                const vec<M> u = x.segment<M>(control_index(k * r_ + j));
                typename cost_type::zmat hc;
                (void)cost_type::evaluate(l_, f_, p_.cost, p_.effort, q, v, t, u, nullptr, &hc);
                hz = contracted_force_hessian(f_, q, v, t, u, a) + sigma * hc;
                hz.template topLeftCorner<2 * D, 2 * D>() += contracted_third(l_, q, v, t, a, b);
                g.setZero();
                for (int l = 0; l <= s_; ++l) {
                    g.block<D, D>(0, l * D).diagonal().setConstant(tab_.phi(l, j));
                    g.block<D, D>(D, l * D).diagonal().setConstant(tab_.dphi(l, j) / h_);
                }
                g.block<M, M>(2 * D, wq + j * M).setIdentity();
                hk.noalias() += h_ * weight(j) * (g.transpose() * hz * g);
            }
            for (int row = 0; row < w; ++row)
                for (int col = 0; col <= row; ++col)
                    values[at++] = hk(row, col);
        }
    }

    /// The trajectory of a solver's result (its last iterate if it did not converge).
    [[nodiscard]] trajectory unpack(const nlp_result& result) const override {
        const vector& x = result.x;
        trajectory out;
        out.scheme = p_.scheme;
        out.h = h_;
        out.degree = s_;
        out.control_nodes = tab_.control;
        out.cost = cost(x);
        out.points.resize(D, points_);
        for (int g = 0; g < points_; ++g)
            out.points.col(g) = x.segment<D>(g * D);
        out.node_times.resize(n_ + 1);
        out.q.resize(D, n_ + 1);
        out.p.resize(D, n_ + 1);
        out.v.resize(D, n_ + 1);
        out.costate.resize(D, n_ + 1);
        // p_{k+1} = D₂L_d + f⁺: step k's contribution to its end node's equation.
        vector e_end = vector::Zero(constraints());
        step_contributions(x, e_end);
        const lagrangian_system<L> sys(l_);
        for (int n = 0; n <= n_; ++n) {
            out.node_times(n) = n * h_;
            out.q.col(n) = x.segment<D>(n * s_ * D);
            out.p.col(n) = n == 0 ? vec<D>(p_start_) : vec<D>(e_end.segment<D>(n * s_ * D));
            out.v.col(n) = sys.velocity(vec<D>(out.q.col(n)), vec<D>(out.p.col(n)), n * h_);
            if (result.lambda.size() == constraints())
                out.costate.col(n) = -result.lambda.segment<D>(n * s_ * D);
            else
                out.costate.col(n).setConstant(std::nan(""));
        }
        out.control_times.resize(n_ * r_);
        out.u.resize(M, n_ * r_);
        for (int k = 0; k < n_; ++k)
            for (int j = 0; j < r_; ++j) {
                out.control_times(k * r_ + j) =
                    (k + tab_.quad.nodes[static_cast<std::size_t>(j)]) * h_;
                out.u.col(k * r_ + j) = x.segment<M>(control_index(k * r_ + j));
            }
        return out;
    }

    [[nodiscard]] Eigen::MatrixXd replay(const trajectory& path) const override {
        return optimal::replay(l_, f_, path);
    }

  private:
    using cost_type = running_cost<L, F>;
    L l_;
    F f_;
    control_problem p_;
    galerkin::tableau tab_;
    int s_ = 1, r_ = 1, n_ = 1, points_ = 2;
    double h_ = 1.0;
    vec<D> p_start_, p_end_;

    [[nodiscard]] int control_index(int c) const { return points_ * D + c * M; }
    /// The unknown of step k's local index: its control values, then its controls.
    [[nodiscard]] int step_index(int k, int local) const {
        const int wq = (s_ + 1) * D;
        return local < wq ? k * s_ * D + local : control_index(k * r_) + (local - wq);
    }
    [[nodiscard]] double weight(int j) const {
        return tab_.quad.weights[static_cast<std::size_t>(j)];
    }
    /// The running cost at step k's quadrature point j, with its gradient and Hessian in z.
    double integrand(cvector x, int k, int j, typename cost_type::zvec* g,
                     typename cost_type::zmat* hz) const {
        vec<D> q, v;
        point(x, k, j, q, v);
        const double t = (k + tab_.quad.nodes[static_cast<std::size_t>(j)]) * h_;
        return cost_type::evaluate(l_, f_, p_.cost, p_.effort, q, v, t,
                                   vec<M>(x.segment<M>(control_index(k * r_ + j))), g, hz);
    }
    /// q and q̇ at step k's quadrature point j.
    void point(cvector x, int k, int j, vec<D>& q, vec<D>& v) const {
        q.setZero();
        v.setZero();
        for (int i = 0; i <= s_; ++i) {
            const auto qi = x.segment<D>((k * s_ + i) * D);
            q += tab_.phi(i, j) * qi;
            v += tab_.dphi(i, j) / h_ * qi;
        }
    }
    /// Each step's contribution to the equation of its last control value only (the end node).
    void step_contributions(cvector x, vector& e) const {
        lagrangian_terms<D> lt;
        for (int k = 0; k < n_; ++k)
            for (int j = 0; j < r_; ++j) {
                vec<D> q, v;
                point(x, k, j, q, v);
                const double t = (k + tab_.quad.nodes[static_cast<std::size_t>(j)]) * h_;
                evaluate_gradient(l_, q, v, t, lt);
                const vec<D> force = f_(q, v, t, vec<M>(x.segment<M>(control_index(k * r_ + j))));
                e.segment<D>(((k + 1) * s_) * D) +=
                    h_ * weight(j) * tab_.phi(s_, j) * (lt.lq + force) +
                    weight(j) * tab_.dphi(s_, j) * lt.lv;
            }
    }
};

/// A transcription for L and F (the type deduced).
template <lagrangian L, control_force F>
std::unique_ptr<dmoc<L, F>> transcribe(L l, F force, const control_problem& problem) {
    return std::make_unique<dmoc<L, F>>(std::move(l), std::move(force), problem);
}

} // namespace varsym::optimal
