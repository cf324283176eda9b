// varsym/schemes/constrained.hpp: the general engine with holonomic constraints g(q) = 0
// (systems/constraints.hpp), for every member of the family; with a force too, if given.
//
// The discrete action of a step, L_d(Q_0 … Q_s) (variational.hpp), is augmented by −Σ λᵀg(Q_n)
// at the control points that carry state (Marsden & West 2001, §3.5; docs/mechanisms.md). With
// G_i = ∂g/∂q(Q_i), Q_0 = q_j, the step solves, for X_l = Q_l − q_j (l = 1 … s) and the impulses
// Λ_0 … Λ_{s−1},
//   F_0 − G_0ᵀΛ_0 = 0,   F_i − G_iᵀΛ_i = 0 (0 < i < s),   g(Q_l) = 0 (l = 1 … s),
// with F_i the unconstrained equations (forces included); then
//   p̃ = p_j + h Σ_k w_k (L_q(k) + f_k) − Σ_{i<s} G_iᵀΛ_i      (= ∂L_d/∂Q_s − G_iᵀΛ_i terms)
//   p_{j+1} = p̃ − G_sᵀμ  with  G_s q̇_{j+1} = 0,  ∂L/∂q̇(q_{j+1}, q̇_{j+1}) = p_{j+1},
// the projection onto the hidden constraint that RATTLE makes (its lowest member, s = 1 with the
// midpoint rule, is the RATTLE-type variational integrator). Newton solves the saddle-point
// system
//   [ J − diag(0, H_1 … H_{s−1})   −diag(G_0ᵀ … G_{s−1}ᵀ) ] [δX]   [F − GᵀΛ]
//   [ diag(G_1 … G_s)               0                     ] [δΛ] = [g     ],
// H_i = Σ_a Λ_ia ∇²g_a(Q_i), with its exact Jacobian, and chord updates (the same matrix, first
// derivatives only) once the updates are small, as the unconstrained engine's Newton; the
// iteration is always Newton (the linear iterations of variational_solve.hpp are for
// unconstrained systems).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "varsym/schemes/variational.hpp"
#include "varsym/systems/constraints.hpp"

namespace varsym::general {

template <lagrangian L, holonomic_constraint C, class F = unforced>
class constrained_stepper : public stepper<L, F> {
    using base = stepper<L, F>;

  public:
    static constexpr int dim = L::dim, count = C::count;
    static_assert(C::dim == L::dim, "the constraints must be on the Lagrangian's coordinates");
    using jacobian_type = constraint_jacobian<dim, count>;

    constrained_stepper(lagrangian_system<L> sys, C c, double h, const scheme_spec& spec,
                        const newton_options& opt = {}) requires(!base::forced)
        : constrained_stepper(std::move(sys), std::move(c), F{}, h, spec, opt) {}

    constrained_stepper(lagrangian_system<L> sys, C c, F f, double h, const scheme_spec& spec,
                        const newton_options& opt = {})
        : base(std::move(sys), std::move(f), h, spec, newton_only(opt)), c_(std::move(c)),
          m_(constraint_count(c_)) {
        const int s = this->s_, d = this->d_, n = s * (d + m_);
        lam_.setZero(m_, s);
        g_.assign(static_cast<std::size_t>(s + 1), vec<count>::Zero(m_));
        jc_.assign(static_cast<std::size_t>(s + 1), jacobian_type::Zero(m_, d));
        mu_.setZero(m_);
        hc_.setZero(d, d);
        k_.setZero(n, n);
        rk_.setZero(n);
        dk_.setZero(n);
        klu_.reserve(n);
    }

    [[nodiscard]] const C& constraint() const { return c_; }
    /// m, the number of constraint equations.
    [[nodiscard]] int constraints() const { return m_; }

    /// Impulses of the last step: Λ_0 … Λ_{s−1} (columns) and the projection's μ. Their sum over
    /// a step divided by h is the mean constraint force λ̄ (units of L_q · 1/G).
    [[nodiscard]] const Eigen::Matrix<double, count, Eigen::Dynamic>& impulses() const {
        return lam_;
    }
    [[nodiscard]] vec<count> mean_multiplier() const {
        return (lam_.rowwise().sum() + mu_) / this->h_;
    }

    /// max_a |g_a(q)|.
    [[nodiscard]] double residual(const vec<dim>& q) const {
        return c_(q).template lpNorm<Eigen::Infinity>();
    }
    /// max_a |(G(q) q̇)_a| with q̇ from p: the hidden constraint, zero for a momentum on the
    /// manifold's cotangent space.
    [[nodiscard]] double hidden_residual(const phase_state<dim>& x) const {
        vec<count> g;
        jacobian_type jac(m_, x.q.size());
        evaluate_constraint(c_, x.q, g, jac);
        return (jac * this->sys_.velocity(x.q, x.p, this->t_)).template lpNorm<Eigen::Infinity>();
    }

    /// Refuses initial data that the step would not keep: dependent constraints (naming the
    /// rows), a position off g = 0 by more than `tolerance` relative to max(|q|, 1)·|G|, or a
    /// velocity not tangent to it by more than `tolerance` relative to |G|·|q̇|. Throws
    /// std::invalid_argument with the residual.
    void check_initial(const phase_state<dim>& x, double tolerance = 1e-12) const {
        vec<count> g;
        jacobian_type jac(m_, x.q.size());
        evaluate_constraint(c_, x.q, g, jac);
        check_independent<dim, count>(jac, "at the initial state");
        sigma_ref_ = singular_values(jac).minCoeff();
        const double scale = jac.template lpNorm<Eigen::Infinity>();
        const double off = g.template lpNorm<Eigen::Infinity>();
        char buf[200];
        if (!(off <= tolerance * scale * std::max(1.0, x.q.template lpNorm<Eigen::Infinity>()))) {
            std::snprintf(buf, sizeof buf,
                          "the initial position is off the constraints: max |g(q0)| = %.3g; "
                          "give a consistent state, or project it onto the constraints",
                          off);
            throw std::invalid_argument(buf);
        }
        const vec<dim> v = this->sys_.velocity(x.q, x.p, this->t_);
        const double tangent = (jac * v).template lpNorm<Eigen::Infinity>();
        if (!(tangent <= tolerance * scale * v.template lpNorm<Eigen::Infinity>())) {
            std::snprintf(buf, sizeof buf,
                          "the initial velocity is not tangent to the constraints: max |G q0'| "
                          "= %.3g; give a consistent state, or project it onto the constraints",
                          tangent);
            throw std::invalid_argument(buf);
        }
    }

    /// (q, p) moved onto the constraints: q by Gauss–Newton along Gᵀ, p by the hidden
    /// constraint's projection (the nearest tangent momentum in the mass matrix's metric).
    [[nodiscard]] phase_state<dim> project(phase_state<dim> x) const {
        project_position(c_, x.q);
        vec<count> g;
        jacobian_type jac(m_, x.q.size());
        evaluate_constraint(c_, x.q, g, jac);
        check_independent<dim, count>(jac, "at the projected initial state");
        sigma_ref_ = singular_values(jac).minCoeff();
        vec<dim> v = this->sys_.velocity(x.q, x.p, this->t_);
        const vec<count> mu =
            tangent_momentum(at(this->sys_.lagrangian(), this->t_), x.q, x.p, jac, v);
        x.p -= jac.transpose() * mu;
        return x;
    }

    newton_report step(phase_state<dim>& x);

    /// After a step from x that did not converge: its cause where one can be named
    /// (constrained_failure.hpp): NaN or infinity from the constraint, a singular constraint
    /// Jacobian (against its smallest singular value at the state check_initial or project saw),
    /// or the general engine's causes; empty otherwise.
    std::string diagnose(const phase_state<dim>& x);

    /// ∂(q_{j+1}, p_{j+1})/∂(q_j, p_j) (2d × 2d) of the step just taken from `from`, through the
    /// saddle-point system and the projection (constrained_sensitivity.hpp). Symplectic on the
    /// tangent space of the constraint manifold's cotangent bundle.
    void step_jacobian(const phase_state<dim>& from, Eigen::MatrixXd& out);
    /// Its block ∂q_{j+1}/∂p_j (d × d) alone: a factorisation of the same matrix, then one
    /// solve of the saddle-point system with d right-hand sides, without the projection (the
    /// contact step's linearisation).
    void position_sensitivity(const phase_state<dim>& from, Eigen::MatrixXd& out);
    /// The same block from the saddle-point matrix K last assembled, factorised if it is not
    /// yet: one solve, no second derivatives. K is the last step's last Newton iterate's (its
    /// first, from the predictor with Λ = 0, where chord updates followed at once), or an
    /// earlier step's after reuse_next(). An approximation, off by K's change from there to the
    /// converged step (the contact step's warm start, which checks its linearisations against
    /// the steps it takes: contact/stepper_step.hpp). Only after a converged step.
    void kept_position_sensitivity(Eigen::MatrixXd& out);
    /// The next step(), from the same q_j with the momentum changed by dp, starts from the last
    /// step's increments and multipliers moved to first order, Z − K⁻¹ (dp, 0), with the last
    /// K assembled (at an iterate of that step or an earlier one, or by position_sensitivity
    /// or step_jacobian), factorised if it is not yet, and iterates by chord updates on its LU
    /// until one fails to contract (the contact step's retakes, contact/stepper_step.hpp). Once;
    /// call it only after a converged step from that q_j.
    void start_next_near(const vec<dim>& dp);
    /// The next step() starts from the predictor with the last step's multipliers and iterates
    /// by chord updates on the LU of the saddle-point matrix K last assembled, in an earlier
    /// step (Jacobian reuse across steps): its first update where it is below chord_start of
    /// q_j (or of the increments), then while they contract as chord updates must; else
    /// Newton's from there, as in any step. The predictor's increments are moved by what the
    /// last such step's predictor missed (its converged increments less its predictor's): a
    /// contact step's warm take, kicked by the last impulses each step, misses by nearly the
    /// same each step (the A1 standing: 9.5e-5 of increments 1.1e-4, the same to 1e-8). A step
    /// from the predictor that does not reuse clears the miss; one from start_next_near keeps it.
    /// Its momentum is evaluated at the converged increments, not linearised, until second
    /// derivatives are evaluated again (by a Newton iterate, position_sensitivity or
    /// step_jacobian): those kept are an earlier step's. Once; ignored before K was ever
    /// assembled (or restored).
    void reuse_next() { reuse_ = assembled_; }
    /// What such a step depends on beyond (q_j, p_j), appended to out: K, the multipliers Λ
    /// and the last reused step's miss with a flag (the contact step's history,
    /// contact/stepper_history.hpp); kept_size() numbers.
    void save_kept(std::vector<double>& out) const;
    [[nodiscard]] std::size_t kept_size() const {
        return static_cast<std::size_t>(k_.size() + lam_.size() + this->x_.size() + 1);
    }
    /// Puts back kept_size() numbers that save_kept gave.
    void restore_kept(const double* in);

  protected:
    /// The step's start: for a free base (lagrangian_with_bias_after_mass_matrix) from M(q_j) and
    /// the bias forces, no second derivatives (predict_dynamics); else the Taylor predictor's
    /// (predict()). Both leave the constraint's force out (Λ = 0).
    void predict_start(const phase_state<dim>& x) {
        if constexpr (lagrangian_with_bias_after_mass_matrix<L>)
            this->predict_dynamics(x);
        else
            this->predict(x);
    }

  private:
    static newton_options newton_only(newton_options opt) {
        opt.iteration = iteration_kind::newton;
        return opt;
    }
    void assemble_constrained(const phase_state<dim>& x, bool jacobian);
    bool at_round_off(const phase_state<dim>& x);
    std::string constraint_problem(const vec<dim>& q, const char* where, double t) const;

    C c_;
    int m_;                                            // constraint_count(c_)
    Eigen::Matrix<double, count, Eigen::Dynamic> lam_; // Λ_0 … Λ_{s−1}
    vec<count> mu_;                                    // the projection's impulse
    std::vector<vec<count>> g_;                        // g(Q_0 … Q_s)
    std::vector<jacobian_type> jc_;                    // G(Q_0 … Q_s)
    mat<dim> hc_;
    mutable double sigma_ref_ = 0.0; // G's smallest singular value at the checked initial state
    Eigen::MatrixXd k_;
    Eigen::VectorXd rk_, dk_;
    small_lu klu_;
    // start_next_near's start for the next step: increments, multipliers, the start's move.
    Eigen::Matrix<double, dim, Eigen::Dynamic> near_x_;
    Eigen::Matrix<double, count, Eigen::Dynamic> near_lam_;
    double near_move_ = 0.0;
    bool near_ = false;
    bool reuse_ = false;
    // The predictor's increments of this step where it reuses the kept matrix, and the last
    // reused step's converged increments less its predictor's (reuse_next: the next reused step
    // starts from its predictor plus it).
    Eigen::Matrix<double, dim, Eigen::Dynamic> reuse_taylor_, reuse_miss_;
    bool reuse_miss_valid_ = false;
    bool assembled_ = false; // k_ was assembled (or restored) since construction
    // The second derivatives at the quadrature points are of this step's iterates (or of the
    // last one's converged point, by position_sensitivity or step_jacobian): the momentum may be
    // linearised with them. Not after reuse_next() until they are evaluated again.
    bool second_current_ = false;
    bool factorised_ = false; // klu_ holds the LU of k_ as last assembled
    void factorise() {
        klu_.compute(k_);
        factorised_ = true;
    }
};

template <lagrangian L, holonomic_constraint C, class F>
newton_report constrained_stepper<L, C, F>::step(phase_state<dim>& x) {
    const int s = this->s_, d = this->d_;
    auto& X = this->x_;
    const bool near = std::exchange(near_, false);
    const bool reuse = std::exchange(reuse_, false) && !near;
    if (near) { // start_next_near's start (the predictor would evaluate M, or more)
        X = near_x_;
        lam_ = near_lam_;
    } else {
        predict_start(x);
        if (!reuse) lam_.setZero();
        if (reuse) {
            reuse_taylor_ = X;
            if (reuse_miss_valid_) X += reuse_miss_; // the last reused step's miss (reuse_next)
        }
    }
    evaluate_constraint(c_, x.q, g_[0], jc_[0]);
    newton_options opt = this->opt_;
    opt.typical = X.template lpNorm<Eigen::Infinity>();
    opt.reference = x.q.template lpNorm<Eigen::Infinity>();
    newton_monitor monitor(opt);
    newton_report rep;
    // Chord updates as the unconstrained engine's (variational_solve.hpp, chord_policy): a chord
    // iterate keeps the saddle-point matrix and its LU and evaluates first derivatives alone.
    chord_policy chords(opt);
    if (near) chords.keep(near_move_, X.template lpNorm<Eigen::Infinity>());
    if (reuse && opt.chord_start > 0.0) {
        second_current_ = false;
        if (!factorised_) factorise();
        // Its first update below chord_start of q_j (or of the increments): a first-order
        // move, which K's change since it was assembled leaves accurate to their product; the
        // next update must then contract as chord updates do, or Newton's iteration takes over.
        chords.keep_stale(std::max(opt.reference, opt.typical));
    }
    bool linearised = false;
    while (true) {
        const bool chord = chords.chord();
        this->evaluate_points(x.q, !chord);
        if (!chord) second_current_ = true;
        this->assemble(x.p, !chord);
        assemble_constrained(x, !chord);
        rep.residual = rk_.template lpNorm<Eigen::Infinity>();
        if (at_round_off(x)) { // as the unconstrained engine's stop (variational_solve.hpp)
            rep.iterations = monitor.iterations();
            this->delta_.setZero(); // the momentum from this iterate's L_q, no update to correct
            linearised = true;
            break;
        }
        if (monitor.exhausted()) return rep;
        if (!chord) factorise();
        klu_.solve(rk_, dk_);
        const double update = dk_.head(s * d).template lpNorm<Eigen::Infinity>();
        rep.iterations = monitor.iterations() + 1;
        if (!std::isfinite(rep.residual)) return base::failed(rep);
        if (!dk_.allFinite()) {
            if (!chord) return base::failed(rep);
            chords.drop(); // the kept LU: try Newton's own from this iterate
            continue;
        }
        if (chord && !chords.contracts(update)) {
            if (chords.at_noise(update)) {
                // The chord has reached the noise of the equations: the last iterate stands
                // (what the last chord update left is ρ times its size). Near a singular
                // constraint Jacobian (a four-bar near its change point) that noise is 1e-13 of
                // increments of 5e-3, above 64 ulp of q, and Newton from there cycled between
                // two iterates 5e-14 apart until it ran out of iterations.
                rep.iterations = monitor.iterations();
                break;
            }
            chords.drop(); // this iterate is Newton's after all
            continue;
        }
        for (int l = 0; l < s; ++l)
            X.col(l) -= dk_.segment(l * d, d);
        for (int i = 0; i < s; ++i)
            lam_.col(i) -= dk_.segment(s * d + i * m_, m_);
        const double size = X.template lpNorm<Eigen::Infinity>();
        if (monitor.converged(update, size, chord)) {
            // The momentum from this iterate, corrected to first order for the update, where
            // what that leaves is below ε (chord_policy::linearisable).
            linearised = second_current_ && chords.linearisable(update, size);
            if (linearised) this->delta_ = dk_.head(s * d);
            break;
        }
        chords.taken(update, size);
    }
    // p̃ − p_j, then the projection onto the hidden constraint at q_{j+1}.
    if (!(linearised ? this->momentum_change_linearised(x) : this->momentum_change(x)))
        return base::failed(rep);
    for (int i = 1; i <= s; ++i) {
        this->qk_ = x.q + X.col(i - 1);
        evaluate_constraint(c_, this->qk_, g_[static_cast<std::size_t>(i)],
                            jc_[static_cast<std::size_t>(i)]);
    }
    for (int i = 0; i < s; ++i)
        this->dp_.noalias() -= jc_[static_cast<std::size_t>(i)].transpose() * lam_.col(i);
    this->qk_ = x.q + X.col(s - 1);
    this->acc_ = x.p + this->dp_;        // p̃
    this->vk_ = X.col(s - 1) / this->h_; // a start for q̇_{j+1}
    try {
        mu_ = tangent_momentum(at(this->sys_.lagrangian(), this->t_ + this->h_), this->qk_,
                               this->acc_, jc_[static_cast<std::size_t>(s)], this->vk_);
    } catch (const std::domain_error&) {
        return base::failed(rep);
    }
    this->dp_.noalias() -= jc_[static_cast<std::size_t>(s)].transpose() * mu_;
    if (!this->dp_.allFinite()) return base::failed(rep);
    // What the predictor missed, for the next reused step's start. A step from the predictor that
    // did not reuse (the contact step's cold path: its free step) leaves none, as a checkpoint
    // there would: the contact step's history keeps the miss only with its warm contacts.
    if (!near) {
        reuse_miss_valid_ = reuse;
        if (reuse) reuse_miss_ = X - reuse_taylor_;
    }
    this->commit(x);
    rep.converged = true;
    return rep;
}

/// The saddle-point residual, and where `jacobian` its Jacobian (the header comment), from the
/// unconstrained ones that assemble() left in res_ and jac_.
template <lagrangian L, holonomic_constraint C, class F>
void constrained_stepper<L, C, F>::assemble_constrained(const phase_state<dim>& x, bool jacobian) {
    const int s = this->s_, d = this->d_, sd = s * d;
    const auto& X = this->x_;
    if (jacobian) {
        k_.setZero();
        k_.topLeftCorner(sd, sd) = this->jac_;
        factorised_ = false;
        assembled_ = true;
    }
    rk_.head(sd) = this->res_;
    for (int l = 1; l <= s; ++l) { // g(Q_l) = 0, rows sd + (l−1)m, columns of X_l
        const auto n = static_cast<std::size_t>(l);
        this->qk_ = x.q + X.col(l - 1);
        evaluate_constraint(c_, this->qk_, g_[n], jc_[n]);
        rk_.segment(sd + (l - 1) * m_, m_) = g_[n];
        if (jacobian) k_.block(sd + (l - 1) * m_, (l - 1) * d, m_, d) = jc_[n];
    }
    for (int i = 0; i < s; ++i) { // − G_iᵀΛ_i in equation i
        const auto& jac = jc_[static_cast<std::size_t>(i)];
        rk_.segment(i * d, d).noalias() -= jac.transpose() * lam_.col(i);
        if (!jacobian) continue;
        k_.block(i * d, sd + i * m_, d, m_) = -jac.transpose();
        if (i == 0) continue; // G_0 is at q_j, which the step does not move
        this->qk_ = x.q + X.col(i - 1);
        constraint_curvature(c_, this->qk_, vec<count>(lam_.col(i)), hc_);
        k_.block(i * d, (i - 1) * d, d, d) -= hc_;
    }
}

/// Whether the saddle-point residual (after assemble_constrained) is round-off of its own terms:
/// the momentum rows as the unconstrained residual's (stepper::at_round_off), their round-off
/// with 2ε |G_iᵀ||Λ_i| added, and each constraint row below 2ε |G(Q_l)| |Q_l| (the round-off of
/// evaluating g at Q_l). Then no update could be told from noise, and the solve stops (a
/// free-base robot at rest: its motion is round-off of the forces on it).
template <lagrangian L, holonomic_constraint C, class F>
bool constrained_stepper<L, C, F>::at_round_off(const phase_state<dim>& x) {
    constexpr double eps2 = 2.0 * std::numeric_limits<double>::epsilon();
    const int s = this->s_, d = this->d_, sd = s * d;
    if (!rk_.allFinite()) return false;
    this->residual_resolution(x.p);
    for (int i = 0; i < s; ++i)
        this->delta_.segment(i * d, d).noalias() +=
            eps2 *
            (jc_[static_cast<std::size_t>(i)].cwiseAbs().transpose() * lam_.col(i).cwiseAbs());
    if (!base::at_round_off(rk_.head(sd), x.p, true, this->terms_[0].lvv.diagonal())) return false;
    for (int l = 1; l <= s; ++l) {
        const auto& g = jc_[static_cast<std::size_t>(l)];
        this->qk_ = x.q + this->x_.col(l - 1);
        if (!(rk_.segment(sd + (l - 1) * m_, m_).array().abs() <=
              eps2 * (g.cwiseAbs() * this->qk_.cwiseAbs()).array())
                 .all())
            return false;
    }
    return true;
}

} // namespace varsym::general

#include "varsym/schemes/constrained_failure.hpp"
#include "varsym/schemes/constrained_sensitivity.hpp"
