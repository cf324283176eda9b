// varsym/schemes/variational.hpp: the general engine. Any Lagrangian L(q, q̇), any member of the
// family (Lobatto or Gauss quadrature, degree s; Simpson = Lobatto 2, Newmark = Gauss 1), one
// Newton solve per step with the exact Jacobian from second derivatives of L.
//
// On a step, q(t_j + τh) = Σ_i ℓ_i(τ) Q_i with Q_0 = q_j, Q_s = q_{j+1} (docs/design.md, "The one
// idea"), and
//   L_d(Q_0 … Q_s) = h Σ_k w_k L(q_k, v_k),  q_k = Σ_i ℓ_i(c_k) Q_i,  v_k = (1/h) Σ_i ℓ_i'(c_k) Q_i
// (for s = 2 and Lobatto this is the paper's eq. LLhh applied to a general L). With φ_ik = ℓ_i(c_k)
// and ψ_ik = ℓ_i'(c_k), the position–momentum form of the discrete Euler–Lagrange equations is
//   F_0 = p_j + Σ_k w_k (h φ_0k L_q(k) + ψ_0k L_v(k)) = 0          (p_j = −∂L_d/∂Q_0)
//   F_i =       Σ_k w_k (h φ_ik L_q(k) + ψ_ik L_v(k)) = 0, 0<i<s   (∂L_d/∂Q_i = 0)
//   p_{j+1} = ∂L_d/∂Q_s = p_j + h Σ_k w_k L_q(k)     (the F_i summed: Σ_i φ_ik = 1, Σ_i ψ_ik = 0)
// solved for the increments X_l = Q_l − q_j (l = 1 … s) by Newton with the Jacobian blocks
//   ∂F_i/∂X_l = Σ_k w_k (h φ_ik φ_lk L_qq + φ_ik ψ_lk L_qv + ψ_ik φ_lk L_vq + ψ_ik ψ_lk L_vv / h).
// The coefficients w_k φ_ik, w_k ψ_ik, w_k are tableau::wphi, wdphi, weights (+ weights_lo), with
// φ_0k and ψ_0k derived from the other rows and applied as double + low part, and the velocities
// use ψ as dphi + dphi_lo: then the identities above hold far below an ulp, the step is exactly
// the map of one L_d, and rounding does not tilt the energy (galerkin.hpp; docs/design.md,
// "Round-off that tilts the map"). For L = ½ q̇ᵀMq̇ − V(q) these are the separable path's
// equations divided by h.
//
// Newton evaluates second derivatives at every point of each iterate whose Jacobian it builds;
// once its updates are small it keeps that Jacobian for chord updates within the step
// (newton_options::chord_start; variational_solve.hpp), and p_{j+1} comes from its last
// iterate's derivatives, corrected to first order for the last update (no evaluation). For a
// robot (lagrangian_with_bias_forces; a free base's in the constrained stepper,
// lagrangian_with_bias_after_mass_matrix) its predictor takes M(q_j) and the bias forces in place
// of second derivatives at q_j. The linear iterations (simplified, fixed_point;
// variational_solve.hpp) evaluate only first derivatives in their sweeps, against one Jacobian
// kept across steps (with automatic derivatives O(2d) per operation of L, not O((2d)²):
// docs/autodiff.md); the articulated one, against M alone, in O(d) (variational_articulated.hpp).
//
// Forces (the discrete Lagrange–d'Alembert principle; Marsden & West 2001, §3.2): a generalized
// force f(q, q̇, t) adds h Σ_k w_k φ_ik f(q_k, v_k, t_j + c_k h) to equation i, i.e. f joins L_q
// at every quadrature point, and ∂f/∂q, ∂f/∂q̇ join the Jacobian beside L_qq and L_qv (not
// beside L_vq: f is not differentiated in q̇ by the principle). Then
//   p_{j+1} = p_j + h Σ_k w_k (L_q(k) + f_k),
// and the step's work h Σ_k w_k f_k·v_k is kept (last_work) for the energy balance.
//
// A Lagrangian that depends on time changes the energy by dE/dt = −∂L/∂t (+ f·q̇): where L gives
// ∂L/∂t (systems/lagrangian_time.hpp: by hand, as the expression Lagrangian does, or by
// differentiating a call templated on the time), the step's work also holds
// −h Σ_k w_k ∂L/∂t(q_k, v_k, t_j + c_k h), so that E − E0 − total_work() measures the scheme's
// error for a time-dependent L as for a forced one.
#pragma once

#include <cmath>
#include <span>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "varsym/schemes/galerkin.hpp"
#include "varsym/schemes/scheme_kind.hpp"
#include "varsym/solvers/compensated.hpp"
#include "varsym/solvers/iteration_choice.hpp"
#include "varsym/solvers/newton.hpp"
#include "varsym/solvers/small_ldlt.hpp"
#include "varsym/solvers/small_lu.hpp"
#include "varsym/systems/forcing.hpp"
#include "varsym/systems/lagrangian.hpp"
#include "varsym/systems/lagrangian_time.hpp"

namespace varsym::general {

/// One step of the scheme for the system's Lagrangian. The state is (q, p); the iteration starts
/// from a Taylor predictor from (q_j, p_j) (predictor `previous` is the family stepper's
/// only). The default iteration (`automatic`) is Newton for a Lagrangian with derivatives by
/// hand and the simplified iteration for automatic derivatives (docs/autodiff.md). With Newton,
/// steps depend on nothing else, except a robot's (bias forces by hand; unforced, or with a force
/// continuous in time), whose predictor takes a jerk from the last step it continues; with a
/// linear iteration they also depend on the kept Jacobian. save_history / restore_history hand
/// both to a checkpoint, so a run restarted from a saved state continues exactly as it would have.
/// All work arrays are sized in the constructor: for a compile-time d a step allocates nothing;
/// d may also be `dynamic` (known at run time), with the derivatives given by hand.
/// With a force F (systems/forcing.hpp) the step is the forced one, and a time-dependent
/// L(q, q̇, t) is evaluated at each quadrature point's time; the step's time t_j is set by
/// set_time (the drivers of integrate.hpp do) and advances by h per step otherwise.
template <lagrangian L, class F = unforced>
class stepper {
  public:
    static constexpr int dim = L::dim;
    static constexpr bool forced = !std::is_same_v<F, unforced>;
    /// Whether a step depends on its time t_j: a force, or a time-dependent L(q, q̇, t).
    static constexpr bool timed = forced || time_dependent_lagrangian<L>;
    static_assert(force_for<F, L::dim>(), "the force must be a generalized_force "
                                          "(systems/forcing.hpp) of the Lagrangian's dimension");
    using system_type = lagrangian_system<L>;
    using force_type = F;

    stepper(system_type sys, double h, const scheme_spec& spec,
            const newton_options& opt = {}) requires(!forced)
        : stepper(std::move(sys), F{}, h, spec, opt) {}

    stepper(system_type sys, F force, double h, const scheme_spec& spec,
            const newton_options& opt = {})
        : sys_(std::move(sys)), force_(std::move(force)), h_(h), opt_(opt), spec_(spec),
          tab_(galerkin::tableau::make(family_member(spec).first, family_member(spec).second)) {
        const bool automatic = opt_.iteration == iteration_kind::automatic;
        if (automatic)
            opt_.iteration = lagrangian_with_derivatives<at_time_t<L>> ? iteration_kind::newton
                                                                       : iteration_kind::simplified;
        s_ = tab_.degree;
        r_ = static_cast<int>(tab_.quad.size());
        d_ = sys_.dimension();
        x_.setZero(d_, s_);
        terms_.resize(static_cast<std::size_t>(r_));
        for (auto& t : terms_) {
            t.lq.setZero(d_);
            t.lv.setZero(d_);
            t.lqq.setZero(d_, d_);
            t.lqv.setZero(d_, d_);
            t.lvv.setZero(d_, d_);
        }
        if constexpr (forced) {
            fterms_.resize(static_cast<std::size_t>(r_));
            for (auto& t : fterms_) {
                t.f.setZero(d_);
                t.fq.setZero(d_, d_);
                t.fv.setZero(d_, d_);
            }
        }
        for (auto* v : {&qk_, &vk_, &dp_, &dq_, &acc_, &lq0_, &lv0_, &q_bar_, &v_bar_, &rhs_, &a0_,
                        &a_next_, &q_end_, &p_end_})
            v->setZero(d_);
        res_.setZero(s_ * d_);
        delta_.setZero(s_ * d_);
        if constexpr (jerk_history) {
            x_taylor_.setZero(d_, s_);
            x_miss_.setZero(d_, s_);
        }
        jac_.setZero(s_ * d_, s_ * d_);
        lqvt_.setZero(d_, d_);
        lu_.reserve(s_ * d_);
        if (linear()) jinv_.setZero(s_ * d_, s_ * d_);
        if (automatic) choose_iteration(); // a robot's: Newton or articulated, step by step
        if (opt_.iteration == iteration_kind::articulated) articulated_setup();
    }

    [[nodiscard]] double step_size() const { return h_; }
    [[nodiscard]] const system_type& system() const { return sys_; }
    /// The compensated summation of the increments, whose carries a checkpoint keeps.
    [[nodiscard]] auto& summation() { return sum_; }
    [[nodiscard]] const galerkin::tableau& table() const { return tab_; }
    [[nodiscard]] const F& force() const { return force_; }
    /// The force, to change between steps (a controlled<…> force's input u). A change to a force
    /// that says it is continuous in time (a PD controller's gains) reads as a jerk at the next
    /// step's start, which costs that start an iteration or two, never the answer.
    [[nodiscard]] F& force() { return force_; }
    /// The time t_j of the next step's start (used by forces and a time-dependent L; an
    /// autonomous step ignores it).
    [[nodiscard]] double time() const { return t_; }
    void set_time(double t) { t_ = t; }
    /// The energy put in over the last step: the forces' work h Σ_k w_k f_k·q̇_k, less
    /// h Σ_k w_k ∂L/∂t for an L that gives its time derivative (0 for neither): the energy
    /// balance E_{j+1} − E_j ≈ W_j holds to the scheme's order.
    [[nodiscard]] double last_work() const { return work_; }
    /// The energy put in since the start (or the restored history): Σ_j W_j (last_work), summed
    /// with compensation. E(t_j) − E(t_0) − total_work() is the energy balance's error.
    [[nodiscard]] double total_work() const { return total_work_ + work_carry_; }

    /// With a linear iteration: whether a Jacobian is kept and the point (q̄, v̄) it was taken
    /// at (1 + 2d numbers); with a force, then that point's time and the total work with its
    /// carry (3 numbers; also for a time-dependent L, its −∫∂L/∂t); for an L with bias forces by
    /// hand (a robot), unforced or with a force continuous in time, then the predictor's jerk:
    /// a flag, and if it is set a₀, q and p where the last step ended, and a flag and if it is
    /// set the last step's miss (1, 2 + 3d or 2 + 3d + sd numbers);
    /// empty for an autonomous, unforced Newton stepper otherwise. run_state::history keeps it
    /// for a checkpoint.
    void save_history(std::vector<double>& out) const;
    /// Puts back what save_history gave (an empty history starts afresh): the next step is then
    /// the one the saved run would have taken. Throws std::invalid_argument on a wrong length.
    void restore_history(const phase_state<dim>& x, const std::vector<double>& in);

    /// The Jacobian ∂(q_{j+1}, p_{j+1})/∂(q_j, p_j) (2d × 2d, (q, p) order) of the step just
    /// taken from `from` = (q_j, p_j), by the implicit function theorem on its equations
    /// (variational_sensitivity.hpp). Call it after a converged step(), with the state that step
    /// started from. Symplectic without forces: Jᵀ Ω J = Ω.
    /// With a controlled<…> force, `controls` also receives ∂(q_{j+1}, p_{j+1})/∂u_j
    /// (2d × M) for the input u_j held over that step.
    void step_jacobian(const phase_state<dim>& from, Eigen::MatrixXd& out,
                       Eigen::MatrixXd* controls = nullptr);
    /// Its block ∂q_{j+1}/∂p_j (d × d) alone: a factorisation of the same matrix, then one
    /// solve with d right-hand sides, no q_j columns nor p_{j+1} rows (the contact step's
    /// linearisation, contact/stepper_step.hpp).
    void position_sensitivity(const phase_state<dim>& from, Eigen::MatrixXd& out);

    /// After a step from x that did not converge: its cause where one can be named (NaN or
    /// infinity from L or the force, a singular or indefinite ∂²L/∂q̇², at the step's start, on
    /// the predicted motion or at Newton's last iterate), empty otherwise
    /// (variational_failure.hpp). integrate.hpp's drivers call it.
    std::string diagnose(const phase_state<dim>& x);

    /// The step's own polynomial through its control values q_j + X_l, on the step just taken
    /// from `from`, at τ ∈ [0, 1] (t = t_j + τh): q(τ) and dq/dτ (run/section.hpp).
    void dense_output(const phase_state<dim>& from, double tau, vec<dim>& q, vec<dim>& dq) const {
        tab_.polynomial(from.q, x_, tau, q, dq);
    }
    /// The same stepper with another step size, starting afresh (for a step to a section).
    [[nodiscard]] stepper with_step_size(double h) const {
        newton_options o = opt_;
        if (choice_.on()) o.iteration = iteration_kind::automatic; // chosen again at h
        return stepper(sys_, force_, h, spec_, o);
    }

    /// The automatic choice between Newton and the articulated iteration (off where the
    /// iteration was named, or for a robot whose break-even, the articulated updates a step
    /// that cost as much as Newton's step, is below choice_threshold;
    /// variational_articulated.hpp).
    [[nodiscard]] const iteration_choice& choice() const { return choice_; }
    /// Settles an automatic choice on Newton (the contact step takes a step several times over).
    void keep_newton() {
        if (!choice_.on()) return;
        choice_.off();
        opt_.iteration = iteration_kind::newton;
    }

    newton_report step(phase_state<dim>& x) {
        if constexpr (jerk_history) a0_taken_ = false; // not a failed step's
        newton_report rep;
        int spent = 0; // the linear or articulated updates of a step handed to Newton
        bool handed = false;
        if (opt_.iteration == iteration_kind::newton || (choice_.on() && !choice_.articulated())) {
            rep = solve_newton(x);
        } else { // a step that diverged or was too slow goes to Newton
            rep = linear() ? solve_linear(x) : solve_articulated(x);
            spent = rep.iterations;
            handed = !rep.converged;
            if (handed) {
                rep = solve_newton(x);
                rep.iterations += spent;
            }
        }
        if constexpr (jerk_history) {
            // In a violent motion the jerk's start can be out of Newton's reach where the
            // second-order start is not (a 50-link chain whipping at 130 rad/s): Newton again
            // from there. The history is only read here; a step that still fails leaves it.
            if (!rep.converged && jerk_taken_) {
                const int tried = rep.iterations;
                struct second_order_start {
                    bool& on;
                    explicit second_order_start(bool& b) : on(b) { on = true; }
                    ~second_order_start() { on = false; }
                    second_order_start(const second_order_start&) = delete;
                    second_order_start& operator=(const second_order_start&) = delete;
                } start(second_order_);
                rep = solve_newton(x);
                rep.iterations += tried;
            }
        }
        if (!rep.converged) return rep;
        if (!(linearised_ ? momentum_change_linearised(x) : momentum_change(x))) return failed(rep);
        commit(x);
        choice_.record(spent, handed); // a step that fails leaves the choice as it was
        return rep;
    }

  protected:
    // What the constrained stepper (constrained.hpp) builds on.

    /// dp_ = p_{j+1} − p_j = h Σ_k w_k (L_q(k) + f_k) at the converged increments; false if not
    /// finite. A coordinate that L does not depend on has L_q = 0 exactly, so its momentum is
    /// conserved to the last bit.
    bool momentum_change(const phase_state<dim>& x) {
        evaluate_points(x.q, false);
        dp_.setZero();
        for (int k = 0; k < r_; ++k) {
            dp_ += tab_.quad.weights[k] * terms_[k].lq;
            dp_ += tab_.weights_lo[static_cast<std::size_t>(k)] * terms_[k].lq;
        }
        dp_ *= h_;
        add_time_work(x);
        return dp_.allFinite();
    }
    bool momentum_change_linearised(const phase_state<dim>& x); // variational_solve.hpp
    void residual_resolution(const vec<dim>& p);                // variational_solve.hpp
    template <class Diagonal> // m_j: ∂²L/∂q̇_j² (or M's diagonal) at the step
    bool at_round_off(Eigen::Ref<const Eigen::VectorXd> res, const vec<dim>& p, bool resolved,
                      const Diagonal& m);
    /// work_ −= Σ_k w_k ∂L/∂t(q_k, v_k, t_k) at the increments, for an L that gives ∂L/∂t.
    void add_time_work(const phase_state<dim>& x) {
        if constexpr (time_dependent_lagrangian<L> && lagrangian_time_known<L>) {
            if (depends_on_time(sys_.lagrangian()))
                for (int k = 0; k < r_; ++k) {
                    set_point(x.q, k);
                    work_ -= tab_.quad.weights[static_cast<std::size_t>(k)] *
                             time_derivative(sys_.lagrangian(), qk_, vk_, point_time(k));
                }
        }
    }
    /// q_{j+1} = q_j + X_s and p_{j+1} = p_j + dp_ (compensated); the clock and work advance
    /// (variational_history.hpp).
    void commit(phase_state<dim>& x);
    void add_state_derivative(Eigen::MatrixXd& b) const;
    void add_momentum_derivative(const Eigen::MatrixXd& dx, Eigen::MatrixXd& out, bool state) const;
    void control_jacobian(const phase_state<dim>& from, Eigen::MatrixXd& out);
    static newton_report failed(newton_report rep) {
        rep.converged = false;
        rep.residual = std::numeric_limits<double>::quiet_NaN();
        return rep;
    }

    [[nodiscard]] bool linear() const {
        return opt_.iteration == iteration_kind::simplified ||
               opt_.iteration == iteration_kind::fixed_point;
    }

    std::string diagnose_points(const phase_state<dim>& x, const char* where);

    newton_report solve_newton(const phase_state<dim>& x) {
        if constexpr (lagrangian_with_bias_forces<L>)
            predict_dynamics(x);
        else
            predict(x);
        return iterate(x, true);
    }

    // The iterations, the predictors and the linear ones' kept Jacobian (variational_solve.hpp).
    newton_report solve_linear(const phase_state<dim>& x);
    newton_report iterate(const phase_state<dim>& x, bool newton);
    void refresh(const lagrangian_terms<dim>& t);
    void predict_kept(const phase_state<dim>& x);
    void predict_dynamics(const phase_state<dim>& x);
    void taylor_increments(const vec<dim>& v, const vec<dim>& a, const vec<dim>* j = nullptr);
    void taylor_from_dynamics(const phase_state<dim>& x); // from vk_ = q̇_j, acc_ = q̈_j
    void dynamics_rhs(const phase_state<dim>& x);         // rhs_ = f − b at (q_j, q̇_j = vk_)
    // The articulated iteration (variational_articulated.hpp).
    void articulated_setup();
    newton_report solve_articulated(const phase_state<dim>& x);
    bool predict_articulated(const phase_state<dim>& x);
    void choose_iteration();
    void restore_steps(const phase_state<dim>& x, std::span<const double> in);

    /// The Taylor predictor from (q_j, p_j), second derivatives left in terms_[0].
    void predict(const phase_state<dim>& x);

    // The step's equations at its quadrature points (variational_points.hpp).
    /// L and its first (and, if `second`, second) derivatives at every quadrature point
    /// (q_k, v_k) for the current increments.
    void evaluate_points(const vec<dim>& q, bool second);
    /// (q_k, v_k) of quadrature point k for the current increments from q_j = q.
    void set_point(const vec<dim>& q, int k);
    [[nodiscard]] double point_time(int k) const {
        return t_ + tab_.quad.nodes[static_cast<std::size_t>(k)] * h_;
    }
    /// f at point k joins L_q there (and its Jacobians are evaluated if `jacobian`).
    void add_force(int k, const vec<dim>& q, const vec<dim>& v, double t, bool jacobian);
    void add_jacobian_block(int k, int i, int l); // variational_solve.hpp
    /// The residual F (rows i = 0 … s−1) and, if `jacobian`, its Jacobian in the increments.
    void assemble(const vec<dim>& p, bool jacobian);

    system_type sys_;
    [[no_unique_address]] F force_;
    double h_;
    newton_options opt_;
    scheme_spec spec_;
    galerkin::tableau tab_;
    int s_ = 0, r_ = 0, d_ = 0;
    Eigen::Matrix<double, dim, Eigen::Dynamic> x_;
    vec<dim> qk_, vk_, dp_, dq_, acc_, lq0_,
        lv0_, // lq0_, lv0_: L_q, L_v at (q_j, v) in predict_kept
        rhs_; // a right-hand side of the predictor's solves
    std::vector<lagrangian_terms<dim>> terms_;
    std::vector<force_terms<dim>> fterms_;      // the force at each quadrature point (if forced)
    double t_ = 0.0, work_ = 0.0, t_bar_ = 0.0; // t_bar_: the time of (q̄, v̄), if timed
    double total_work_ = 0.0, work_carry_ = 0.0;
    double t_step_ = 0.0; // the last step's t_j
    Eigen::VectorXd res_, delta_;
    Eigen::MatrixXd jac_, jinv_; // jinv_: the kept Jacobian's inverse (linear iterations)
    mat<dim> lqvt_;              // assemble(): a point's (∂²L/∂q∂q̇)ᵀ
    Eigen::MatrixXd ainv_;       // h A⁻¹ (s × s) of the articulated iteration
    iteration_choice choice_;    // the automatic choice of it (off: none)
    small_lu lu_;
    vec<dim> q_bar_, v_bar_;     // where the kept Jacobian was taken
    Eigen::LDLT<mat<dim>> mbar_; // ∂²L/∂q̇² there, factorised: the kept predictor's mass matrix
    Eigen::LDLT<mat<dim>> ldlt_; // the full predictor's factorisations
    // The robot predictor's M(q_j) (predict_dynamics), by small_ldlt at run-time size.
    std::conditional_t<dim == dynamic, small_ldlt, Eigen::LDLT<mat<dim>>> mass_;
    bool kept_ = false;
    bool linearised_ = false; // Newton converged with a linearisation below ε: reuse its terms
    double rate_ = 0.0;       // the slowest contraction of the last linear iteration
    compensated_update<dim> sum_;
    // The robot predictors' jerk: the acceleration M⁻¹(f − b) at the last step's start (a0_), and
    // the state that step ended at (q_end_, p_end_), where the next step may continue it; a_next_
    // this step's, which commit() makes a0_ (a step solved again by Newton predicts twice).
    static constexpr bool jerk_history =
        lagrangian_with_bias_forces<L> && (!forced || force_continuous_in_time<F>());
    vec<dim> a0_, a_next_, q_end_, p_end_;
    bool a0_taken_ = false, continues_ = false;
    // This step's Taylor increments; the last step's converged increments less its own (its
    // miss, where miss_valid_: that step took the jerk), which the next prediction adds.
    Eigen::Matrix<double, dim, Eigen::Dynamic> x_taylor_, x_miss_;
    bool jerk_taken_ = false, miss_valid_ = false;
    bool second_order_ = false; // this step's retake from the second-order start (step())
};

} // namespace varsym::general

#include "varsym/schemes/variational_articulated.hpp"
#include "varsym/schemes/variational_failure.hpp"
#include "varsym/schemes/variational_history.hpp"
#include "varsym/schemes/variational_points.hpp"
#include "varsym/schemes/variational_sensitivity.hpp"
#include "varsym/schemes/variational_solve.hpp"
