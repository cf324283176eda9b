// varsym/contact/stepper.hpp: hard contact with Coulomb friction inside the variational step.
//
// A step of the chosen member of the family (the general engine, with the free base's
// quaternion constraint if any), Inner, maps (q_j, p_j) to (q_{j+1}, p_{j+1}); its first equation
// is the discrete Euler–Lagrange equation p_j + D₁L_d(q_j, q_{j+1}) = 0 (variational.hpp). The
// contact impulses enter it as a discrete Lagrange–d'Alembert impulse at the step's start:
//   p_j + J(q_j)ᵀ λ + D₁L_d(q_j, q_{j+1}) = 0,   p_{j+1} = D₂L_d(q_j, q_{j+1}),          (K1)
// with J's rows per contact i the normal n·∂P_i/∂q and the tangents t·∂F_i/∂q (P_i the point
// that defines the gap, F_i the body's material point at the contact where it begins: at q_j,
// or where the free step's path meets the obstacle), and λ = (γ_i, b_i)
// solving, at the step's end,
//   φ_i(q_{j+1}) ≥ 0 ⊥ γ_i ≥ 0,  (μγ_i, b_i) ∈ K ⊥ (η_i, d_i) ∈ K,                         (K2)
// d_i = T(F_i(q_{j+1}) − F_i(q_c)) the slip since the contact began (q_c: q_j, or the onset
// in the step, stepper_step.hpp) (cone_solver.hpp): the gap at the end
// of every step is non-negative, impacts are inelastic (the normal velocity is removed, not
// reversed), friction sticks inside the cone and slides on its boundary against the slip
// (maximal dissipation). As Dojo's integrator (Howell et al. 2022) with J taken at q_j.
//
// Solution (cold): the step without impulses first; if no gap is negative at its end, λ = 0
// solves (K2) and the step is the family member's own (free flight costs one check of the
// gaps). Otherwise
// Newton's method on λ through the step: with S = ∂q_{j+1}/∂p_j (the step's own Jacobian), the
// gaps and slips are linearised as (φ, d) ≈ (φ, d)(λ_k) + G S Jᵀ (λ − λ_k), the linear conic
// complementarity problem is solved by the interior-point method (cone_solver.hpp), the step is
// taken again with the new impulses, until the gaps and slips at its end agree with their
// linearisation to `tolerance` [m] (the gaps to a tenth of it while S is the warm start's kept
// one, with which the linearisations converge linearly). The contacts solved for are the pairs
// whose gap is below the free step's largest point motion and the last step's; a pair found
// below zero at the end joins them. Warm start, where the last step had pressing contacts: no
// free step; the step with the last step's contacts and impulses is taken first (from the
// scheme's predictor; where the inner stepper offers it, the free base's, by chord updates on the
// saddle-point matrix last assembled, in this or an earlier step, Newton's where they do not
// contract), S from the matrix that take ends with (no second derivatives; taken at the step
// instead where a linearisation misses its prediction by more than the tolerance, misses the
// gaps' tenth twice, or the interior point stalls), and the free step's end estimated from them
// to first order, q_{j+1} − S Jᵀλ, chooses the contacts and places the onsets (a robot standing
// converges in two linearisations); should that fail, or no gap at the estimate be negative, the
// free step and the cold start from λ = 0 follow. Where the inner stepper offers it (the free
// base's constrained stepper, start_next_near), each step taken with impulses starts from the
// last one taken from q_j, moved to first order for the change of kick Jᵀλ by the saddle-point
// matrix last assembled (from q_j, or the one the warm take kept), and iterates by chord updates
// on its LU: no predictor and no second derivatives where the start is as close as a retake's (a
// take that fails from there is taken again from the predictor).
//
// The contact's work over a step is the kick's change of the energy at q_j,
// E(q_j, p_j + Jᵀλ) − E(q_j, p_j) (for L = ½ q̇ᵀM(q)q̇ − V(q), exactly q̇(q_j, p_j + Jᵀλ/2)·Jᵀλ:
// one velocity); the inner step from the kicked state does the rest (its forces'
// work and its own error). total_work() includes it, so E − E₀ − W is the scheme's own error in
// and out of contact.
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "varsym/contact/cone_solver.hpp"
#include "varsym/contact/geometry.hpp"
#include "varsym/solvers/compensated.hpp"
#include "varsym/solvers/newton.hpp"
#include "varsym/solvers/small_ldlt.hpp"
#include "varsym/systems/lagrangian_concepts.hpp"

namespace varsym::contact {

struct contact_options {
    double tolerance = 1e-12; ///< [m] on the gaps and slips at a step's end
    int max_iterations = 30;  ///< linearisations per step
};

/// What the last step's contacts did.
struct contact_report {
    int active = 0;           ///< contacts with a normal impulse
    double normal = 0.0;      ///< Σ γ_i [N s]
    double friction = 0.0;    ///< Σ |b_i| [N s]
    double penetration = 0.0; ///< max(0, −min φ) at the step's end [m]
    double work = 0.0;        ///< the impulses' work over the step [J]
    int iterations = 0;       ///< linearisations (0: no contact)
};

template <class Inner>
class contact_stepper : public Inner {
    // The inner stepper iterates a warm step with the matrix it last assembled, kept across
    // steps (the free base's constrained stepper): reuse_next(), save_kept(), restore_kept().
    static constexpr bool reuses = requires(Inner & i) { i.reuse_next(); };
    // The history's layout after the inner stepper's: where it reuses, its kept matrix,
    // multipliers and the warm take's miss (save_kept(), none without warm pairs) and their count;
    // the warm start's pairs and impulses (4 numbers a pair), their count, a tag, then the fixed
    // part (contact_report, the work). Where it reuses, the tag before the kept matrix was 6.2e7
    // (older_tag), and before the kept miss (constrained_stepper::save_kept) 6.3e7 (old_tag).
    static constexpr int fixed_size = 8;
    static constexpr double older_tag = 6.2e7, old_tag = 6.3e7,
                            history_tag = reuses ? 6.4e7 : older_tag;

  public:
    static constexpr int dim = Inner::dim;

    contact_stepper(Inner inner, std::shared_ptr<const multibody::tree> t,
                    std::vector<obstacle> world, contact_options o = {})
        : Inner(std::move(inner)), kin_(t), points_(contact_points(*t)), world_(std::move(world)),
          opt_(o), onset_kin_(t) {
        if (kin_.dimension() != this->system().dimension())
            throw std::invalid_argument("contact: the robot's coordinates are not the system's");
        for (const obstacle& w : world_)
            if (!(w.friction >= 0.0 && std::isfinite(w.friction)))
                throw std::invalid_argument("the friction coefficient of " + w.name +
                                            " must be finite and >= 0");
        // A contact step takes the inner step several times from one state: Newton each time,
        // not an automatic choice that would count every take as a step.
        if constexpr (requires(Inner & i) { i.keep_newton(); }) Inner::keep_newton();
    }

    [[nodiscard]] const contact_report& last_contact() const { return last_; }
    /// The last step's pressing contacts, six numbers each in the world frame: the contact
    /// point [m] (at q_j, or where the contact began within the step) and the impulse
    /// γ n + b₁ t₁ + b₂ t₂ on the robot [N s] (n = t₁ × t₂, the normal there). Empty after a
    /// step without contact and after a restore; a failed step leaves the last good one's.
    [[nodiscard]] const std::vector<double>& last_impulses() const { return impulses_; }
    [[nodiscard]] double contact_work() const { return work_ + carry_; }
    [[nodiscard]] double total_work() const { return Inner::total_work() + contact_work(); }
    [[nodiscard]] int pairs() const { return static_cast<int>(points_.size() * world_.size()); }

    newton_report step(phase_state<dim>& x);

    std::string diagnose(const phase_state<dim>& x) {
        return failure_.empty() ? Inner::diagnose(x) : failure_;
    }

    /// The tangent map of a step without contact; refused across one (not differentiable).
    void step_jacobian(const phase_state<dim>& from, Eigen::MatrixXd& out) {
        if (last_.iterations > 0)
            throw std::invalid_argument("the step's tangent map is not defined across a contact "
                                        "(its impulses switch on and off)");
        Inner::step_jacobian(from, out);
    }
    /// The inner stepper's approximation of that block is the contact step's own (warm start).
    void kept_position_sensitivity(Eigen::MatrixXd& out) = delete;
    /// Its block ∂q_{j+1}/∂p_j alone, refused across a contact as step_jacobian is.
    void position_sensitivity(const phase_state<dim>& from, Eigen::MatrixXd& out) {
        if (last_.iterations > 0)
            throw std::invalid_argument("the step's tangent map is not defined across a contact "
                                        "(its impulses switch on and off)");
        Inner::position_sensitivity(from, out);
    }

    /// The inner stepper's history (and where it reuses its matrix across steps, that matrix
    /// and its multipliers while contacts press, and their count), then the last step's contacts
    /// and impulses (the warm start), their count, a tag, the contact's work with its carry and
    /// the last step's report: a resumed run takes the steps the straight one would have.
    void save_history(std::vector<double>& out) const;
    /// Puts back what save_history gave (empty: starts afresh); throws std::invalid_argument
    /// for a history that save_history did not write for this robot and world.
    void restore_history(const phase_state<dim>& x, const std::vector<double>& in);

  private:
    struct pair_state {
        int pair;
        vec3 friction_point = vec3::Zero();          ///< F in its body's frame
        vec3 start = vec3::Zero();                   ///< F(q_j) in the world
        vec3 t1 = vec3::UnitX(), t2 = vec3::UnitY(); ///< the tangents at q_j
    };
    [[nodiscard]] const contact_point& point(int c) const {
        return points_[static_cast<std::size_t>(c) / world_.size()];
    }
    [[nodiscard]] const obstacle& plane(int c) const {
        return world_[static_cast<std::size_t>(c) % world_.size()];
    }
    /// φ of pair c at the last kinematics.
    [[nodiscard]] double gap(int c) const {
        const contact_point& p = point(c);
        vec3 n;
        return plane(c).distance(kin_.pose(p.body).point(p.point), n) - p.radius;
    }
    // What a step of the inner stepper (general::stepper's commit()) changes besides its
    // iterates: the clock, the work and the compensated sums, kept across trial steps. A
    // stepper with more running state than these needs it added here. (The predictor's jerk and
    // miss are not: they are taken only where a step starts exactly where the last committed
    // one ended.)
    void save() {
        saved_t_ = this->t_;
        saved_t_step_ = this->t_step_;
        saved_last_work_ = this->work_;
        saved_work_ = this->total_work_;
        saved_carry_ = this->work_carry_;
        saved_sum_ = this->sum_;
    }
    void restore() {
        this->t_ = saved_t_;
        this->t_step_ = saved_t_step_;
        this->work_ = saved_last_work_;
        this->total_work_ = saved_work_;
        this->work_carry_ = saved_carry_;
        this->sum_ = saved_sum_;
    }
    /// Rows of J (at the start, `start` true) or G (at the end) for the active pairs at the last
    /// kinematics, and the gaps and slips there.
    void rows(bool start, Eigen::MatrixXd& m, Eigen::VectorXd* values);
    bool take(phase_state<dim>& y, const Eigen::VectorXd& lambda, newton_report& rep);
    /// After a free step (no kick): whether a take may start near it (take()).
    void free_step_taken(bool converged) {
        near_ready_ = converged;
        last_kick_.setZero(from_.q.size());
    }
    bool select();
    bool warm(newton_report& total);
    void sensitivity(bool kept);
    bool iterate(newton_report& total);
    double onset(int c);
    double kick_work();
    void finish(phase_state<dim>& x);

    robot_kinematics kin_;
    std::vector<contact_point> points_;
    std::vector<obstacle> world_;
    contact_options opt_;
    contact_report last_;
    std::vector<double> impulses_; // last_impulses()
    double work_ = 0.0, carry_ = 0.0;
    std::string failure_;
    // Scratch.
    std::vector<pair_state> active_;
    std::vector<int> warm_pairs_; // the last step's contacts and their impulses
    Eigen::VectorXd warm_lambda_;
    phase_state<dim> from_, y_;
    double saved_t_ = 0.0, saved_t_step_ = 0.0, saved_last_work_ = 0.0, saved_work_ = 0.0,
           saved_carry_ = 0.0;
    Eigen::VectorXd lambda_, values_, predicted_;
    // Every pair's gap at q_j and at the free step's end (taken, or estimated by warm()); zeros
    // between warm()'s start and its select() (no onset).
    std::vector<double> start_gap_, end_gap_;
    std::vector<vec3> ends_; // the contact points at the free step's end
    Eigen::VectorXd q_free_, q_onset_;
    vec<dim> kick_, last_kick_, dkick_; // Jᵀλ of this take and of the last step from from_
    bool near_ready_ = false;           // that step converged: the next take may start near it
    bool s_kept_ = false;               // s_ from a kept factorisation (sensitivity())
    robot_kinematics onset_kin_;
    // kick_work()'s M(q_j), its factors and vectors.
    mat<dim> work_mass_;
    std::conditional_t<dim == dynamic, small_ldlt, Eigen::LDLT<mat<dim>>> work_factor_;
    vec<dim> work_v_, work_r_, work_dv_;
    compensated_update<dim> saved_sum_;
    Eigen::MatrixXd jac_, g_, s_;
    Eigen::Matrix<double, 3, Eigen::Dynamic> dp_;
};

} // namespace varsym::contact

#include "varsym/contact/stepper_finish.hpp"
#include "varsym/contact/stepper_history.hpp"
#include "varsym/contact/stepper_step.hpp"
