// varsym/schemes/galerkin.hpp: the variational family beyond the paper. q(t) on a step is a
// polynomial of degree s through control values Q_0 = q_j, Q_1 … Q_{s−1}, Q_s = q_{j+1} at the
// Gauss–Lobatto nodes d_0 = 0 < … < d_s = 1, and the action is integrated by
//   lobatto: the (s+1)-point Gauss–Lobatto rule (s = 1 trapezoidal/Störmer–Verlet, s = 2 the
//            paper's Simpson scheme), or
//   gauss:   the s-point Gauss–Legendre rule (s = 1 the midpoint rule: the paper's Newmark).
// Both have order 2s. For L = ½ q̇ᵀ M q̇ − V(q), with ℓ_i the Lagrange basis on the d_i,
//   L_d = (1/(2h)) Σ_{i,l} A_il Q_iᵀ M Q_l − h Σ_k w_k V(Σ_i ℓ_i(c_k) Q_i),
//   A_il = Σ_k w_k ℓ_i'(c_k) ℓ_l'(c_k)
// (the paper's eq. LLhh is the case lobatto, s = 2).
#pragma once

#include <array>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <variant>

#include "varsym/quadrature/rules.hpp"
#include "varsym/solvers/compensated.hpp"
#include "varsym/solvers/newton.hpp"
#include "varsym/systems/separable.hpp"

namespace varsym::galerkin {

enum class rule_kind { lobatto, gauss };

/// Largest degree offered (order 16). Each degree is compiled as its own fixed-size stepper, so
/// this bounds build time; double precision already stops measuring orders at s = 5 or 6.
inline constexpr int max_degree = 8;

/// The tables of one member: control nodes d_i, quadrature (c_k, w_k), ℓ_i(c_k), ℓ_i'(c_k), A.
struct tableau {
    int degree = 0;
    rule_kind kind = rule_kind::lobatto;
    std::vector<double> control; ///< d_0 … d_s (Gauss–Lobatto nodes on [0, 1])
    quadrature::rule quad;       ///< c_k, w_k
    Eigen::MatrixXd phi;         ///< (s+1) × r: ℓ_i(c_k)
    Eigen::MatrixXd dphi;        ///< (s+1) × r: ℓ_i'(c_k)
    Eigen::MatrixXd stiffness;   ///< (s+1) × (s+1): A_il

    /// Builds the tables in long double (64-bit mantissa) and rounds each entry once to double,
    /// so that their errors stay at half an ulp: the scheme's period is then right to ~1 ulp.
    static tableau make(rule_kind kind, int s) {
        using LD = long double;
        if (s < 1 || s > max_degree)
            throw std::invalid_argument("degree must be between 1 and " +
                                        std::to_string(max_degree) + ", got " + std::to_string(s));
        const auto control = quadrature::gauss_lobatto<LD>(s + 1).nodes;
        const auto quad = kind == rule_kind::lobatto ? quadrature::gauss_lobatto<LD>(s + 1)
                                                     : quadrature::gauss_legendre<LD>(s);
        const auto r = static_cast<Eigen::Index>(quad.size());
        using matrix_ld = Eigen::Matrix<LD, Eigen::Dynamic, Eigen::Dynamic>;
        matrix_ld phi(s + 1, r), dphi(s + 1, r);
        for (int i = 0; i <= s; ++i)
            for (Eigen::Index k = 0; k < r; ++k) {
                const LD x = quad.nodes[k];
                LD value = 1, slope = 0;
                for (int m = 0; m <= s; ++m) {
                    if (m == i) continue;
                    const LD inv = 1 / (control[i] - control[m]);
                    slope = slope * (x - control[m]) * inv + value * inv; // product rule
                    value *= (x - control[m]) * inv;
                }
                phi(i, k) = value;
                dphi(i, k) = slope;
            }
        if (kind == rule_kind::lobatto) phi.setIdentity(); // c_k = d_k: ℓ_i(c_k) = δ_ik exactly
        matrix_ld weights = matrix_ld::Zero(r, r);
        for (Eigen::Index k = 0; k < r; ++k)
            weights(k, k) = quad.weights[k];
        const matrix_ld stiffness = dphi * weights * dphi.transpose();

        tableau t;
        t.degree = s;
        t.kind = kind;
        t.control.assign(control.begin(), control.end());
        t.quad.nodes.assign(quad.nodes.begin(), quad.nodes.end());
        t.quad.weights.assign(quad.weights.begin(), quad.weights.end());
        t.phi = phi.cast<double>();
        t.dphi = dphi.cast<double>();
        t.stiffness = stiffness.cast<double>();
        return t;
    }
    [[nodiscard]] int order() const { return 2 * degree; }
};

/// Number of quadrature points of a member: s + 1 for Lobatto, s for Gauss.
constexpr int points(rule_kind kind, int s) {
    return kind == rule_kind::lobatto ? s + 1 : s;
}

/// One step solves, for the increments X_l = Q_l − q_j (l = 1 … s; X_0 = 0), the s·D equations
///   h p_j + Σ_l A_0l M X_l − h² Σ_k w_k ℓ_0(c_k) ∇V(q_k) = 0     (p_j = −∂L_d/∂Q_0)
///           Σ_l A_il M X_l − h² Σ_k w_k ℓ_i(c_k) ∇V(q_k) = 0     (∂L_d/∂Q_i = 0, 0 < i < s)
/// with q_k = q_j + Σ_l ℓ_l(c_k) X_l, by Newton with the exact Jacobian
///   A_il M − h² Σ_k w_k ℓ_i(c_k) ℓ_l(c_k) ∇²V(q_k).
/// Then q_{j+1} = q_j + X_s and p_{j+1} = ∂L_d/∂Q_s, which (the equations summed over i, with
/// Σ_i A_il = 0 and Σ_i ℓ_i = 1) is p_j − h Σ_k w_k ∇V(q_k).
///
/// The degree S and the rule are compile-time parameters, so every matrix has a fixed size and
/// a step allocates nothing; galerkin::stepper below chooses among them at run time.
template <class System, rule_kind Kind, int S>
class fixed_stepper {
  public:
    static constexpr int dim = System::dim;
    static constexpr int R = points(Kind, S);
    static constexpr int N = blocks(S, dim);
    using system_type = System;

    fixed_stepper(System sys, double h, const tableau& t, const newton_options& opt = {});

    [[nodiscard]] double step_size() const { return h_; }
    [[nodiscard]] const System& system() const { return sys_; }
    /// The compensated summation of the increments, whose carries a checkpoint keeps.
    [[nodiscard]] compensated_update<dim>& summation() { return sum_; }

    /// One step (definition below the class).
    newton_report step(phase_state<dim>& x);

  private:
    using stage_matrix = Eigen::Matrix<double, dim, S>;
    System sys_;
    double h_;
    newton_options opt_;
    Eigen::Matrix<double, S, S> a_;
    Eigen::Matrix<double, S, R> u_, v_;
    std::array<double, R> w_{};
    std::array<double, S> control_{};
    std::array<int, R> active_{};
    int n_active_ = 0;
    std::array<bool, R> at_start_{}, at_end_{};
    stage_matrix xm_;
    Eigen::Matrix<double, dim, R> grads_;
    std::array<mat<dim>, R> hess_;
    vec<dim> grad_j_{}, cached_q_{};
    bool cache_valid_ = false;
    compensated_update<dim> sum_;
};

// The constructor and step are defined outside the class, hence not inline, so that a program
// that uses the family for one system from many translation units can compile it once (see
// VARSYM_EXTERN_GALERKIN_FAMILY below).
template <class System, rule_kind Kind, int S>
fixed_stepper<System, Kind, S>::fixed_stepper(System sys, double h, const tableau& t,
                                              const newton_options& opt)
    : sys_(std::move(sys)), h_(h), opt_(opt) {
    if (t.degree != S || t.kind != Kind) throw std::logic_error("galerkin tableau does not match");
    // In matrix form, with X = [X_1 … X_s] (d × s) and G = [∇V(q_1) … ∇V(q_r)] (d × r):
    //   residual R = M X Aᵀ − h² G Uᵀ + h p_j e_0ᵀ,   points Q = q_j 1ᵀ + X V,
    //   Jacobian J = A ⊗ M − h² Σ_k (U_k V_kᵀ) ⊗ ∇²V(q_k),
    // with A_il = A(i, l), U_ik = w_k ℓ_i(c_k) (i < s), V_lk = ℓ_l(c_k) (l ≥ 1).
    a_ = t.stiffness.block(0, 1, S, S);
    for (int k = 0; k < R; ++k) {
        for (int i = 0; i < S; ++i)
            u_(i, k) = t.quad.weights[k] * t.phi(i, k);
        for (int l = 0; l < S; ++l)
            v_(l, k) = t.phi(l + 1, k);
        w_[k] = t.quad.weights[k];
        // Newton evaluates ∇V and ∇²V only where a point enters the solved equations
        // (U_k ≠ 0) and moves with the unknowns (V_k ≠ 0). For Lobatto, c_0 = 0 is q_j
        // itself (its ∇V is cached) and c_s = 1 enters only p_{j+1}.
        if (u_.col(k).cwiseAbs().maxCoeff() > 0.0 && v_.col(k).cwiseAbs().maxCoeff() > 0.0)
            active_[n_active_++] = k;
        at_start_[k] = t.quad.nodes[k] == 0.0;
        at_end_[k] = t.quad.nodes[k] == 1.0;
    }
    for (int l = 0; l < S; ++l)
        control_[l] = t.control[l + 1];
    const int d = sys_.dimension();
    xm_.resize(d, S);
    grads_.resize(d, R);
    grad_j_ = vec<dim>::Zero(d);
    hess_.fill(mat<dim>::Zero(d, d));
}

template <class System, rule_kind Kind, int S>
newton_report fixed_stepper<System, Kind, S>::step(phase_state<dim>& x) {
    const int d = static_cast<int>(x.q.size());
    const auto& m = sys_.mass();
    const auto& minv = sys_.inverse_mass();
    const auto& v = sys_.potential();
    const double h = h_, h2 = h * h;
    if (!cache_valid_ || cached_q_ != x.q) grad_j_ = v.gradient(x.q);
    // Predictor: Taylor to second order, X_l ≈ d_l h M⁻¹p − (d_l h)²/2 M⁻¹∇V(q_j).
    const vec<dim> vel = minv * x.p, acc = -(minv * grad_j_);
    for (int l = 0; l < S; ++l) {
        const double tl = control_[l] * h;
        xm_.col(l) = tl * vel + 0.5 * tl * tl * acc;
    }
    newton_options opt = opt_;
    opt.typical = xm_.template lpNorm<Eigen::Infinity>();
    opt.reference = x.q.template lpNorm<Eigen::Infinity>();
    newton_monitor monitor(opt);
    newton_report rep;
    vec<N> r(S * d), delta(S * d);
    mat<N> jac(S * d, S * d);
    while (true) {
        // Residual R = M X Aᵀ − h² G Uᵀ + h p_j e_0ᵀ and its Jacobian at X.
        for (int k = 0; k < R; ++k)
            grads_.col(k) = at_start_[k] ? grad_j_ : vec<dim>::Zero(d);
        for (int a = 0; a < n_active_; ++a) {
            const int k = active_[a];
            const vec<dim> q = x.q + xm_ * v_.col(k);
            grads_.col(k) = v.gradient(q);
            hess_[k] = v.hessian(q);
        }
        Eigen::Map<typename stage_matrix::PlainObject> rm(r.data(), d, S);
        rm.noalias() = m * xm_ * a_.transpose();
        rm.noalias() -= h2 * grads_ * u_.transpose();
        rm.col(0) += h * x.p;
        if constexpr (dim == 1) {
            // d = 1: J = m A − h² U diag(∇²V(q_k)) Vᵀ as one fixed-size product.
            Eigen::Matrix<double, R, 1> curvature = Eigen::Matrix<double, R, 1>::Zero();
            for (int a = 0; a < n_active_; ++a)
                curvature(active_[a]) = hess_[active_[a]](0, 0);
            jac.noalias() = m(0, 0) * a_;
            jac.noalias() -= h2 * (u_ * curvature.asDiagonal() * v_.transpose());
        } else {
            for (int i = 0; i < S; ++i)
                for (int l = 0; l < S; ++l) {
                    mat<dim> block = a_(i, l) * m;
                    for (int a = 0; a < n_active_; ++a) {
                        const int k = active_[a];
                        const double c = h2 * u_(i, k) * v_(l, k);
                        if (c != 0.0) block -= c * hess_[k];
                    }
                    block_of<dim>(jac, i, l, d) = block;
                }
        }
        rep.residual = r.template lpNorm<Eigen::Infinity>();
        if (monitor.exhausted()) return rep;
        delta = solve_dense<N>(jac, r);
        const double step = delta.template lpNorm<Eigen::Infinity>();
        rep.iterations = monitor.iterations() + 1;
        if (!std::isfinite(step) || !std::isfinite(rep.residual)) return rep;
        xm_ -= Eigen::Map<const typename stage_matrix::PlainObject>(delta.data(), d, S);
        if (monitor.converged(step, xm_.template lpNorm<Eigen::Infinity>())) break;
    }
    rep.converged = true;
    // p_{j+1} − p_j = −h Σ_k w_k ∇V(q_k) at the converged points. A point at c_k = 1 is the
    // new x.q, whose ∇V is kept as the next step's ∇V(q_j); a point at c_k = 0 is q_j.
    const vec<dim> q_j = x.q, grad_j = grad_j_;
    sum_.add_q(x, xm_.col(S - 1));
    vec<dim> dp = vec<dim>::Zero(d);
    cache_valid_ = false;
    for (int k = 0; k < R; ++k) {
        vec<dim> g;
        if (at_end_[k]) {
            g = grad_j_ = v.gradient(x.q);
            cache_valid_ = true;
        } else if (at_start_[k]) {
            g = grad_j;
        } else {
            g = v.gradient(vec<dim>(q_j + xm_ * v_.col(k)));
        }
        dp -= (h * w_[k]) * g;
    }
    sum_.add_p(x, dp);
    cached_q_ = x.q;
    return rep;
}

namespace detail {
template <class System, class Seq>
struct stepper_variant;
template <class System, int... I>
struct stepper_variant<System, std::integer_sequence<int, I...>> {
    using type = std::variant<fixed_stepper<System, rule_kind::lobatto, I + 1>...,
                              fixed_stepper<System, rule_kind::gauss, I + 1>...>;
    // The alternative for (kind, s): index s − 1 for Lobatto, max_degree + s − 1 for Gauss.
    template <std::size_t J>
    static type make_one(const System& sys, double h, const tableau& t, const newton_options& opt) {
        return type(std::in_place_index<J>, sys, h, t, opt);
    }
    template <std::size_t... J>
    static type make_at(std::size_t index, const System& sys, double h, const tableau& t,
                        const newton_options& opt, std::index_sequence<J...>) {
        using factory = type (*)(const System&, double, const tableau&, const newton_options&);
        static constexpr std::array<factory, sizeof...(J)> table{&make_one<J>...};
        return table[index](sys, h, t, opt);
    }
    static type make(const System& sys, double h, const tableau& t, const newton_options& opt) {
        const std::size_t index = (t.kind == rule_kind::lobatto ? 0 : max_degree) + t.degree - 1;
        return make_at(index, sys, h, t, opt, std::make_index_sequence<2 * max_degree>{});
    }
};
} // namespace detail

/// A member of the family chosen at run time: (rule, degree s ≤ max_degree).
template <class System>
class stepper {
    using variant_t =
        typename detail::stepper_variant<System, std::make_integer_sequence<int, max_degree>>::type;

  public:
    static constexpr int dim = System::dim;
    using system_type = System;

    stepper(const System& sys, double h, rule_kind kind, int degree, const newton_options& opt = {})
        : tab_(tableau::make(kind, degree)),
          impl_(detail::stepper_variant<System, std::make_integer_sequence<int, max_degree>>::make(
              sys, h, tab_, opt)) {}

    [[nodiscard]] double step_size() const {
        return std::visit([](const auto& s) { return s.step_size(); }, impl_);
    }
    [[nodiscard]] const System& system() const {
        return std::visit([](const auto& s) -> const System& { return s.system(); }, impl_);
    }
    [[nodiscard]] const tableau& table() const { return tab_; }
    [[nodiscard]] compensated_update<dim>& summation() {
        return std::visit([](auto& s) -> compensated_update<dim>& { return s.summation(); }, impl_);
    }
    newton_report step(phase_state<dim>& x) {
        return std::visit([&](auto& s) { return s.step(x); }, impl_);
    }

  private:
    tableau tab_;
    variant_t impl_;
};

} // namespace varsym::galerkin

/// Compiles the whole family (16 fixed_steppers) for one System once per program instead of once
/// per translation unit: `VARSYM_EXTERN_GALERKIN_FAMILY(System);` in a header the users include
/// before they use the family, and `VARSYM_INSTANTIATE_GALERKIN_FAMILY(System);` in one source
/// file. Optional: without them each translation unit that steps the family compiles it again,
/// which gives the same program but builds slowly (about 2 minutes per system at -O3).
#define VARSYM_GALERKIN_MEMBER_(PREFIX, KIND, S, ...)                                              \
    PREFIX template class ::varsym::galerkin::fixed_stepper<                                       \
        __VA_ARGS__, ::varsym::galerkin::rule_kind::KIND, S>
#define VARSYM_GALERKIN_FAMILY_(PREFIX, ...)                                                       \
    static_assert(::varsym::galerkin::max_degree == 8, "list every degree below");                 \
    VARSYM_GALERKIN_MEMBER_(PREFIX, lobatto, 1, __VA_ARGS__);                                      \
    VARSYM_GALERKIN_MEMBER_(PREFIX, lobatto, 2, __VA_ARGS__);                                      \
    VARSYM_GALERKIN_MEMBER_(PREFIX, lobatto, 3, __VA_ARGS__);                                      \
    VARSYM_GALERKIN_MEMBER_(PREFIX, lobatto, 4, __VA_ARGS__);                                      \
    VARSYM_GALERKIN_MEMBER_(PREFIX, lobatto, 5, __VA_ARGS__);                                      \
    VARSYM_GALERKIN_MEMBER_(PREFIX, lobatto, 6, __VA_ARGS__);                                      \
    VARSYM_GALERKIN_MEMBER_(PREFIX, lobatto, 7, __VA_ARGS__);                                      \
    VARSYM_GALERKIN_MEMBER_(PREFIX, lobatto, 8, __VA_ARGS__);                                      \
    VARSYM_GALERKIN_MEMBER_(PREFIX, gauss, 1, __VA_ARGS__);                                        \
    VARSYM_GALERKIN_MEMBER_(PREFIX, gauss, 2, __VA_ARGS__);                                        \
    VARSYM_GALERKIN_MEMBER_(PREFIX, gauss, 3, __VA_ARGS__);                                        \
    VARSYM_GALERKIN_MEMBER_(PREFIX, gauss, 4, __VA_ARGS__);                                        \
    VARSYM_GALERKIN_MEMBER_(PREFIX, gauss, 5, __VA_ARGS__);                                        \
    VARSYM_GALERKIN_MEMBER_(PREFIX, gauss, 6, __VA_ARGS__);                                        \
    VARSYM_GALERKIN_MEMBER_(PREFIX, gauss, 7, __VA_ARGS__);                                        \
    VARSYM_GALERKIN_MEMBER_(PREFIX, gauss, 8, __VA_ARGS__)
#define VARSYM_EXTERN_GALERKIN_FAMILY(...) VARSYM_GALERKIN_FAMILY_(extern, __VA_ARGS__)
#define VARSYM_INSTANTIATE_GALERKIN_FAMILY(...) VARSYM_GALERKIN_FAMILY_(, __VA_ARGS__)
