// varsym/optimal/dmoc.hpp: discrete mechanics and optimal control (DMOC; Ober-Blöbaum, Junge &
// Marsden 2011) at every member of the variational family. The unknowns are the control values
// Q of every step's polynomial (nodes shared between steps) and the controls u at the steps'
// quadrature points; the equations are the discrete Lagrange–d'Alembert equations of the
// trajectory, one per control value, with the boundary momenta; the running cost (costs.hpp) by the
// action's quadrature. Exact sparse first derivatives from L's second derivatives. Eigen only;
// solved by varsym::optimal's IPOPT adapter (optimal/solve.hpp). See docs/optimal_control.md.
#pragma once

#include <concepts>
#include <functional>
#include <memory>
#include <utility>

#include "varsym/autodiff/second_order.hpp"
#include "varsym/optimal/costs.hpp"
#include "varsym/optimal/problem.hpp"
#include "varsym/optimal/replay.hpp"
#include "varsym/optimal/third_order.hpp"
#include "varsym/schemes/tableau.hpp"
#include "varsym/systems/constraints.hpp"
#include "varsym/systems/lagrangian.hpp"

namespace varsym::optimal {

/// The transcription of a control_problem for the Lagrangian L and the control force F.
/// Unknowns x = (Q_0 … Q_{Ns}, u_{0,0} … u_{N−1,r−1}): Q_g = q((k + d_i) h) for g = k s + i,
/// u_{k,j} = u((k + c_j) h). Equations E_g = 0, g = 0 … N s, d each:
///   E_g = Σ_{(k,i): ks+i=g} h Σ_j w_j [ℓ_i(c_j) (∂L/∂q + f)(q_kj, v_kj, u_kj) + ℓ_i'(c_j)/h ∂L/∂q̇]
///         + [g = 0] p_start − [g = N s] p_end,
/// with q_kj = Σ_l ℓ_l(c_j) Q_{ks+l}, v_kj = Σ_l ℓ_l'(c_j) Q_{ks+l} / h: the discrete
/// Lagrange–d'Alembert equations (interior values, nodes between steps) and the discrete
/// Legendre transforms at both ends. Cost Σ_k h Σ_j w_j ½ u_kjᵀ R u_kj. With a free final state
/// the final velocity v_N is d more unknowns (before T), p_end = ∂L/∂q̇(Q_{Ns}, v_N), and the
/// free entries of Q_{Ns} and v_N are unbounded; the terminal cost is added. With holonomic
/// constraints C (g(q) = 0, m of them), the impulses Λ_g (m each, after v_N) enter every E_g as
/// −G(Q_g)ᵀΛ_g, and g(Q_g) = 0 holds at every control value between the (fixed) ends
/// (dmoc_constraints.hpp).
template <lagrangian L, control_force F, class C = unconstrained>
class dmoc final : public transcription {
  public:
    static constexpr int D = L::dim, M = F::controls;
    static constexpr int K = constraint_rows<C>; ///< m, the number of constraints (0: none)
    static_assert(F::dim == L::dim, "the control force must have the Lagrangian's dimension");
    static_assert(constraints_on<C, D>, "C: holonomic constraints on the Lagrangian's coordinates");
    static_assert(K >= 0, "the transcription needs a compile-time number of constraints");

    dmoc(L l, F force, const control_problem& problem) requires std::same_as<C, unconstrained>
        : dmoc(std::move(l), C{}, std::move(force), problem) {}
    dmoc(L l, C constraints, F force, const control_problem& problem)
        : l_(std::move(l)), f_(std::move(force)), c_(std::move(constraints)),
          p_(detail::checked(problem, D, M)),
          tab_(galerkin::tableau::make(family_member(p_.scheme).first,
                                       family_member(p_.scheme).second)) {
        s_ = tab_.degree;
        r_ = static_cast<int>(tab_.quad.size());
        n_ = p_.steps;
        // The unknowns and equations are counted in int (IPOPT's Index).
        if (static_cast<double>(n_) * (s_ * (D + K) + r_ * M + 1) + 4.0 * D + 2.0 > 2.0e9)
            throw std::invalid_argument(std::to_string(n_) +
                                        " steps make more than 2e9 unknowns, beyond what IPOPT "
                                        "can index: take fewer steps");
        h_ = p_.time / n_;
        control_terms<F> ends;
        bool acts = false;
        for (const auto* q : {&p_.q_start, &p_.q_end}) {
            const vector& v = q == &p_.q_start ? p_.v_start : p_.v_end;
            ends.evaluate(f_, vec<D>(*q), vec<D>(v), 0.0, vec<M>::Zero());
            acts = acts || !ends.fu.isZero(0.0);
        }
        if (!acts)
            throw std::invalid_argument("the inputs do not act on the system at either boundary "
                                        "state (df/du = 0 there): nothing to control");
        if (p_.free_time && time_dependent_lagrangian<L>)
            throw std::invalid_argument("a free final time needs an autonomous system: this "
                                        "Lagrangian depends on t");
        points_ = n_ * s_ + 1;
        free_end_ = p_.free_end();
        lagrangian_terms<D> t;
        evaluate_gradient(l_, vec<D>(p_.q_start), vec<D>(p_.v_start), 0.0, t);
        p_start_ = t.lv;
        evaluate_gradient(l_, vec<D>(p_.q_end), vec<D>(p_.v_end), p_.time, t);
        p_end_ = t.lv;
        check_boundary_constraints();
    }

    [[nodiscard]] const control_problem& problem() const override { return p_; }
    [[nodiscard]] const galerkin::tableau& table() const { return tab_; }
    [[nodiscard]] int variables() const override {
        return multiplier_index(points_) + (p_.free_time ? 1 : 0);
    }
    [[nodiscard]] int constraints() const override {
        return points_ * D + (points_ - 2) * K; // g(Q_g) = 0 between the ends
    }

    void bounds(vector& lower, vector& upper) const override {
        lower = vector::Constant(variables(), -unbounded); // the impulses Λ are free
        upper = vector::Constant(variables(), unbounded);
        for (int g = 0; g < points_; ++g) {
            lower.segment<D>(g * D) = p_.position_lower;
            upper.segment<D>(g * D) = p_.position_upper;
        }
        lower.head<D>() = upper.head<D>() = p_.q_start; // fixed ends
        for (int i = 0; i < D; ++i) {                   // the end: fixed, or free within the bounds
            if (p_.free_end_position[static_cast<std::size_t>(i)]) continue;
            lower((points_ - 1) * D + i) = upper((points_ - 1) * D + i) = p_.q_end(i);
        }
        for (int c = 0; c < n_ * r_; ++c) {
            lower.segment<M>(control_index(c)) = p_.control_lower;
            upper.segment<M>(control_index(c)) = p_.control_upper;
        }
        for (int i = 0; free_end_ && i < D; ++i) {
            const bool free = p_.free_end_velocity[static_cast<std::size_t>(i)];
            lower(end_velocity_index() + i) = free ? -unbounded : p_.v_end(i);
            upper(end_velocity_index() + i) = free ? unbounded : p_.v_end(i);
        }
        if (p_.free_time) {
            lower(time_index()) = p_.time_lower;
            upper(time_index()) = p_.time_upper;
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
        if (free_end_) x.segment<D>(end_velocity_index()) = p_.v_end;
        if (p_.free_time) x(time_index()) = p_.time;
        if constexpr (K > 0) // the interpolated positions put on the constraints, where possible
            for (int g = 1; g + 1 < points_; ++g) {
                vec<D> q = x.segment<D>(g * D);
                try {
                    project_position(c_, q);
                    x.segment<D>(g * D) = q;
                } catch (const std::domain_error&) { // G singular there: left as it is
                }
            }
        return x;
    }

    /// The unknowns along a given path q(t), t ∈ [0, T] (a guess of the motion: its positions at
    /// the control values, the ends kept), the controls zero (clipped into their bounds).
    [[nodiscard]] vector start_along(const std::function<vector(double)>& q) const override {
        vector x = start();
        for (int g = 1; g + 1 < points_; ++g) {
            const vector at = q((g / s_ + tab_.control[static_cast<std::size_t>(g % s_)]) * h_);
            detail::require(at.size() == D && at.allFinite(),
                            "the guessed path must give " + std::to_string(D) +
                                " finite coordinates at every time");
            x.segment<D>(g * D) = at;
        }
        return x;
    }

    /// The unknowns of `guess` (another N or scheme: a coarser solution) at this transcription's
    /// points, at the same fractions of the horizon: its dense output for the positions, its
    /// controls interpolated linearly (clipped into the bounds), its horizon if T is free.
    [[nodiscard]] vector start_from(const trajectory& guess) const override {
        vector x = start();
        const double horizon = guess.node_times(guess.node_times.size() - 1);
        for (int k = 0; k < n_; ++k)
            for (int i = (k == 0 ? 1 : 0); i <= s_; ++i) {
                const double frac = (k + tab_.control[static_cast<std::size_t>(i)]) / n_;
                const vec<D> q = guess.position(frac * horizon);
                for (int a = 0; a < D; ++a) // the fixed ends stay
                    if (k < n_ - 1 || i < s_ || p_.free_end_position[static_cast<std::size_t>(a)])
                        x((k * s_ + i) * D + a) = q(a);
            }
        for (int a = 0; free_end_ && a < D; ++a)
            if (p_.free_end_velocity[static_cast<std::size_t>(a)])
                x(end_velocity_index() + a) = guess.v(a, guess.v.cols() - 1);
        const auto& ct = guess.control_times;
        for (int k = 0; k < n_; ++k)
            for (int j = 0; j < r_; ++j) {
                const double t = (k + tab_.quad.nodes[static_cast<std::size_t>(j)]) / n_ * horizon;
                const auto at = std::lower_bound(ct.data(), ct.data() + ct.size(), t) - ct.data();
                const Eigen::Index hi = std::clamp<Eigen::Index>(at, 1, ct.size() - 1), lo = hi - 1;
                const double span = ct(hi) - ct(lo),
                             a = span > 0 ? std::clamp((t - ct(lo)) / span, 0.0, 1.0) : 0.0;
                const vec<M> u = (1.0 - a) * guess.u.col(lo) + a * guess.u.col(hi);
                x.segment<M>(control_index(k * r_ + j)) =
                    u.cwiseMax(p_.control_lower).cwiseMin(p_.control_upper);
            }
        if (p_.free_time) x(time_index()) = std::clamp(horizon, p_.time_lower, p_.time_upper);
        return x;
    }

    [[nodiscard]] double cost(cvector x) const override {
        const double h = h_of(x);
        double j = p_.cost.time * h * n_ + terminal_cost(x, nullptr);
        for (int k = 0; k < n_; ++k)
            for (int q = 0; q < r_; ++q)
                j += h * weight(q) * integrand(x, k, q, nullptr, nullptr);
        return j;
    }
    void cost_gradient(cvector x, vector& gradient) const override {
        gradient.setZero(variables());
        const double h = h_of(x);
        if (p_.free_time) gradient(time_index()) = p_.cost.time;
        (void)terminal_cost(x, &gradient);
        typename cost_type::zvec g;
        for (int k = 0; k < n_; ++k)
            for (int j = 0; j < r_; ++j) {
                const double c = integrand(x, k, j, &g, nullptr);
                const double hw = h * weight(j);
                for (int l = 0; l <= s_; ++l)
                    gradient.segment<D>((k * s_ + l) * D) +=
                        hw * (tab_.phi(l, j) * g.template head<D>() +
                              tab_.dphi(l, j) / h * g.template segment<D>(D));
                if (p_.free_time) { // d(h w c(q, V/h, u))/dT = w (c − ∇_v c · v) / N
                    vec<D> q, v;
                    point(x, k, j, q, v);
                    gradient(time_index()) +=
                        weight(j) * (c - g.template segment<D>(D).dot(v)) / n_;
                }
                gradient.segment<M>(control_index(k * r_ + j)) += hw * g.template tail<M>();
            }
    }

    void residual(cvector x, vector& e) const override;
    [[nodiscard]] sparsity jacobian_pattern() const override;
    void jacobian(cvector x, std::vector<double>& values) const override;
    /// Exact, except with the invariant cost (whose Hessian needs L's fourth derivatives) and
    /// with a free final time.
    [[nodiscard]] bool has_hessian() const override {
        return p_.cost.invariant == 0.0 && !p_.free_time;
    }

    /// Lower triangle of each step's dense block over its control values and its controls;
    /// with a free final state, of the block over (Q_{Ns}, v_N).
    [[nodiscard]] sparsity hessian_pattern() const override {
        sparsity s;
        const int w = (s_ + 1) * D + r_ * M;
        for (int k = 0; k < n_; ++k)
            for (int row = 0; row < w; ++row)
                for (int col = 0; col <= row; ++col)
                    s.add(step_index(k, row), step_index(k, col));
        for (int row = 0; free_end_ && row < 2 * D; ++row)
            for (int col = 0; col <= row; ++col)
                s.add(end_index(row), end_index(col));
        add_constraint_hessian(vector(), vector(), &s, nullptr);
        return s;
    }

    /// σ ∇²J + Σ_g λ_gᵀ ∇²E_g (fixed time; see dmoc_derivatives.hpp).
    void hessian(cvector x, double sigma, cvector lambda,
                 std::vector<double>& values) const override;
    /// The trajectory of a solver's result (its last iterate if it did not converge).
    [[nodiscard]] trajectory unpack(const nlp_result& result) const override;
    [[nodiscard]] Eigen::MatrixXd replay(const trajectory& path) const override {
        if constexpr (K > 0)
            return optimal::replay(l_, c_, f_, path);
        else
            return optimal::replay(l_, f_, path);
    }

  private:
    using cost_type = running_cost<L, F>;
    L l_;
    F f_;
    C c_;
    control_problem p_;
    galerkin::tableau tab_;
    int s_ = 1, r_ = 1, n_ = 1, points_ = 2;
    bool free_end_ = false;
    double h_ = 1.0;
    vec<D> p_start_, p_end_;

    [[nodiscard]] int control_index(int c) const { return points_ * D + c * M; }
    /// The unknown final velocity v_N of a free final state, after the controls.
    [[nodiscard]] int end_velocity_index() const { return points_ * D + n_ * r_ * M; }
    /// (Q_{Ns}, v_N)'s local index i < 2d as an unknown's.
    [[nodiscard]] int end_index(int i) const {
        return i < D ? (points_ - 1) * D + i : end_velocity_index() + i - D;
    }
    /// The impulses Λ_g of the constraints at control value g (m each), after v_N.
    [[nodiscard]] int multiplier_index(int g) const {
        return end_velocity_index() + (free_end_ ? D : 0) + g * K;
    }
    /// The unknown T of a free final time: the last.
    [[nodiscard]] int time_index() const { return multiplier_index(points_); }
    /// The terminal cost (control_problem's cost_weights::terminal_*); its gradient added to
    /// `gradient` if given.
    double terminal_cost(cvector x, vector* gradient) const {
        if (!free_end_) return 0.0;
        const vec<D> dq = x.segment<D>((points_ - 1) * D) - p_.q_end,
                     dv = x.segment<D>(end_velocity_index()) - p_.v_end;
        const vec<D>&a = p_.cost.terminal_position, &b = p_.cost.terminal_velocity;
        if (gradient) {
            gradient->segment<D>((points_ - 1) * D) += a.cwiseProduct(dq);
            gradient->segment<D>(end_velocity_index()) += b.cwiseProduct(dv);
        }
        return 0.5 * (dq.dot(a.cwiseProduct(dq)) + dv.dot(b.cwiseProduct(dv)));
    }
    /// The final momentum: fixed, or ∂L/∂q̇(Q_{Ns}, v_N) with a free final state.
    [[nodiscard]] vec<D> end_momentum(cvector x) const {
        if (!free_end_) return p_end_;
        lagrangian_terms<D> t;
        evaluate_gradient(l_, vec<D>(x.segment<D>((points_ - 1) * D)),
                          vec<D>(x.segment<D>(end_velocity_index())), n_ * h_of(x), t);
        return t.lv;
    }
    /// The step h = T/N: fixed, or from the unknown T.
    [[nodiscard]] double h_of(cvector x) const { return p_.free_time ? x(time_index()) / n_ : h_; }
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
        const double t = (k + tab_.quad.nodes[static_cast<std::size_t>(j)]) * h_of(x);
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
            v += tab_.dphi(i, j) / h_of(x) * qi;
        }
    }
    /// Each step's terms of the equations (dmoc_derivatives.hpp), all or the end node's only.
    void add_step_equations(cvector x, vector& e, bool end_only) const;
    // The constraints' parts (dmoc_constraints.hpp; nothing without constraints).
    void check_boundary_constraints() const;
    void add_constraint_residual(cvector x, vector& e) const;
    void add_constraint_jacobian(cvector x, sparsity* pattern, std::vector<double>* values) const;
    void add_constraint_hessian(cvector x, cvector lambda, sparsity* pattern,
                                std::vector<double>* values) const;
    /// The momentum at node n made tangent to the constraints (p − Gᵀμ, G q̇ = 0), with q̇.
    void tangent_node(const vec<D>& q, vec<D>& p, vec<D>& v, double t) const;
};

/// A transcription for L and F (the type deduced).
template <lagrangian L, control_force F>
std::unique_ptr<dmoc<L, F>> transcribe_fixed(L l, F force, const control_problem& problem) {
    return std::make_unique<dmoc<L, F>>(std::move(l), std::move(force), problem);
}

/// A transcription for L under the holonomic constraints C, with F.
template <lagrangian L, holonomic_constraint C, control_force F>
std::unique_ptr<dmoc<L, F, C>> transcribe_fixed(L l, C constraints, F force,
                                          const control_problem& problem) {
    return std::make_unique<dmoc<L, F, C>>(std::move(l), std::move(constraints), std::move(force),
                                           problem);
}

} // namespace varsym::optimal

#include "varsym/optimal/dmoc_constraints.hpp"
#include "varsym/optimal/dmoc_derivatives.hpp"
