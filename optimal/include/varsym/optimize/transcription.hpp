// varsym/optimize/transcription.hpp: discrete mechanics and optimal control (DMOC; Ober-Blöbaum,
// Junge & Marsden 2011) at every member of the variational family, for a system of run-time size
// (system.hpp): one transcription compiled once in varsym::transcription for every system: a
// URDF robot, a typed Lagrangian or a C++ one (system_of.hpp). The unknowns are the control
// values Q of every step's polynomial (nodes shared between steps) and the controls u at the
// steps' quadrature points; the equations are the discrete Lagrange–d'Alembert equations of the
// trajectory, one per control value, with the boundary momenta; the running cost by the action's
// quadrature. Exact sparse derivatives from the system's own. See docs/optimal_control.md.
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include "varsym/optimal/problem.hpp"
#include "varsym/optimal/system.hpp"
#include "varsym/schemes/tableau.hpp"

namespace varsym::optimal {

/// The closure check's nodes of `system` under the trajectory's controls (q above p,
/// 2d × (N + 1)): its own replay where it has one, else the general engine over its derivatives
/// (optimal/src/replay_system.cpp), compiled once here.
matrix replay(const controlled_system& system, const trajectory& path);

/// The transcription of a control_problem for a controlled_system.
/// Unknowns x = (Q_0 … Q_{Ns}, u_{0,0} … u_{N−1,r−1}, [v_N], [Λ_0 … Λ_{Ns}], [T]):
/// Q_g = q((k + d_i) h) for g = k s + i, u_{k,j} = u((k + c_j) h). Equations E_g = 0,
/// g = 0 … N s, d each:
///   E_g = Σ_{(k,i): ks+i=g} h Σ_j w_j [ℓ_i(c_j) (∂L/∂q + f)(q_kj, v_kj, u_kj) + ℓ_i'(c_j)/h ∂L/∂q̇]
///         + [g = 0] p_start − [g = N s] p_end − G(Q_g)ᵀ Λ_g,
/// with q_kj = Σ_l ℓ_l(c_j) Q_{ks+l}, v_kj = Σ_l ℓ_l'(c_j) Q_{ks+l} / h: the discrete
/// Lagrange–d'Alembert equations (interior values, nodes between steps) and the discrete
/// Legendre transforms at both ends; and g(Q_g) = 0 between the ends with constraints. With a
/// free final state the final velocity v_N is d more unknowns, p_end = ∂L/∂q̇(Q_{Ns}, v_N), and
/// the free entries of Q_{Ns} and v_N are unbounded; the terminal cost is added. An end target
/// φ(Q_{Ns}) = 0 (control_problem::end_target) frees Q_{Ns} and adds its k rows after the
/// constraints' (or, with a weight w > 0, the terminal cost ½ w |φ(Q_{Ns})|² instead).
class dmoc_transcription final : public transcription {
  public:
    dmoc_transcription(std::shared_ptr<const controlled_system> system,
                       const control_problem& problem);

    [[nodiscard]] const control_problem& problem() const override { return p_; }
    [[nodiscard]] const controlled_system& system() const { return *sys_; }
    [[nodiscard]] const galerkin::tableau& table() const { return tab_; }
    [[nodiscard]] int variables() const override { return time_index() + (p_.free_time ? 1 : 0); }
    [[nodiscard]] int constraints() const override {
        return split_row(1) + (nodes_ ? (n_ - 1) * d_ : 0);
    }
    /// The equations' bounds (0), and the polynomials' bounds' rows'.
    void constraint_bounds(vector& lower, vector& upper) const override;

    void bounds(vector& lower, vector& upper) const override;
    /// The positions interpolated linearly between the ends (put on the constraints where
    /// possible), the controls zero (clipped into their bounds).
    [[nodiscard]] vector start() const override;
    [[nodiscard]] vector start_along(const std::function<vector(double)>& q) const override;
    [[nodiscard]] vector start_from(const trajectory& guess) const override;

    [[nodiscard]] double cost(cvector x) const override;
    void cost_gradient(cvector x, vector& gradient) const override;
    void residual(cvector x, vector& e) const override;
    [[nodiscard]] sparsity jacobian_pattern() const override;
    void jacobian(cvector x, std::vector<double>& values) const override;
    /// Exact (to the system's third derivatives, a free final time's row included), except
    /// with the invariant cost, whose Hessian needs L's fourth derivatives.
    [[nodiscard]] bool has_hessian() const override { return p_.cost.invariant == 0.0; }
    [[nodiscard]] sparsity hessian_pattern() const override;
    void hessian(cvector x, double sigma, cvector lambda,
                 std::vector<double>& values) const override;
    [[nodiscard]] trajectory unpack(const nlp_result& result) const override;
    /// Threads for the steps' Jacobian and Hessian: 0 (the default) as many as this process may
    /// run on (its CPU affinity, at most its cgroup's CPU quota), 1 none. Used only where the
    /// system is concurrent(), the final time fixed and the steps' work worth a thread's start
    /// (evaluation_threads()). The values are the same to the bit with any number: each step's
    /// block is its own.
    void set_threads(int threads) {
        if (threads < 0)
            throw std::invalid_argument("threads: 0 (automatic), 1 (none) or more, not " +
                                        std::to_string(threads));
        threads_ = threads;
    }
    /// The threads jacobian() and hessian() use.
    [[nodiscard]] int evaluation_threads() const;
    [[nodiscard]] Eigen::MatrixXd replay(const trajectory& path) const override {
        return optimal::replay(*sys_, path);
    }
    [[nodiscard]] bool multibody() const override { return sys_->multibody(); }

  private:
    std::shared_ptr<const controlled_system> sys_;
    control_problem p_;
    galerkin::tableau tab_;
    int d_ = 1, m_ = 1, k_ = 0, t_ = 0; // t_: the end target's rows as constraints
    /// Bounds on the steps' polynomials (transcription_bounds.cpp): q at the quadrature points
    /// that are not control values ([0]), q̇ at the steps' ends and quadrature points ([1]), on
    /// the bounded coordinates; weights ℓ_l(τ_e) or ℓ_l'(τ_e), (s + 1) × points.
    struct path_bound {
        bool velocity = false;
        std::vector<int> coordinates;
        matrix weights;
        [[nodiscard]] int rows_per_step() const {
            return static_cast<int>(weights.cols() * std::ssize(coordinates));
        }
    };
    std::array<path_bound, 2> path_bounds_;
    int s_ = 1, r_ = 1, n_ = 1, points_ = 2;
    /// Each step's structural non-zeros (transcription_structure.cpp), the same for every step
    /// and every x: its Jacobian block over its controls (rows: its control values' equations,
    /// (s + 1) d; columns: its r m controls) and the lower triangle of its Hessian block
    /// (step_index's local numbering), in the order of the patterns and their values.
    std::vector<std::pair<int, int>> control_jacobian_, step_hessian_;
    void setup_structure();
    /// The Jacobian's values of the steps' blocks, before the free time's column.
    [[nodiscard]] std::size_t step_jacobian_size() const {
        const auto w = static_cast<std::size_t>((s_ + 1) * d_);
        return static_cast<std::size_t>(n_) * (w * w + control_jacobian_.size());
    }
    bool free_end_ = false;
    int threads_ = 0;
    double h_ = 1.0;
    vector p_start_, p_end_;

    [[nodiscard]] int control_index(int c) const { return points_ * d_ + c * m_; }
    [[nodiscard]] int end_velocity_index() const { return points_ * d_ + n_ * r_ * m_; }
    /// (Q_{Ns}, v_N)'s local index i < 2d as an unknown's.
    [[nodiscard]] int end_index(int i) const {
        return i < d_ ? (points_ - 1) * d_ + i : end_velocity_index() + i - d_;
    }
    [[nodiscard]] int multiplier_index(int g) const {
        return end_velocity_index() + (free_end_ ? d_ : 0) + g * k_;
    }
    [[nodiscard]] int time_index() const {
        return multiplier_index(points_) + (nodes_ ? (n_ - 1) * d_ : 0);
    }
    // Node velocities (transcription_nodes.cpp), with velocity bounds and no constraints: the
    // velocities V_n at the nodes between steps (n = 1 … N−1) are unknowns, bounded, and each
    // such node's equation is split in two, step n−1's end −∂L/∂q̇(Q_{ns}, V_n) = 0 (its row)
    // and step n's start +∂L/∂q̇(Q_{ns}, V_n) = 0 (a row of its own after the bounds' rows).
    bool nodes_ = false;
    [[nodiscard]] int node_velocity_index(int n) const {
        return multiplier_index(points_) + (n - 1) * d_;
    }
    [[nodiscard]] int split_row(int n) const { return path_row() + path_rows() + (n - 1) * d_; }
    /// The first row of step k's equation for its control value i.
    [[nodiscard]] int row_of(int k, int i) const {
        return nodes_ && i == 0 && k > 0 ? split_row(k) : (k * s_ + i) * d_;
    }
    void add_node_residual(cvector x, vector& e) const;
    void add_node_jacobian(cvector x, sparsity* pattern, std::vector<double>* values) const;
    void add_node_hessian(cvector x, cvector lambda, sparsity* pattern,
                          std::vector<double>* values) const;
    [[nodiscard]] double h_of(cvector x) const { return p_.free_time ? x(time_index()) / n_ : h_; }
    /// The unknown of step k's local index: its control values, then its controls.
    [[nodiscard]] int step_index(int k, int local) const {
        const int wq = (s_ + 1) * d_;
        return local < wq ? k * s_ * d_ + local : control_index(k * r_) + (local - wq);
    }
    [[nodiscard]] double weight(int j) const {
        return tab_.quad.weights[static_cast<std::size_t>(j)];
    }
    [[nodiscard]] double point_time(int k, int j, double h) const {
        return (k + tab_.quad.nodes[static_cast<std::size_t>(j)]) * h;
    }
    /// q and q̇ at step k's quadrature point j.
    void point(cvector x, int k, int j, vector& q, vector& v) const;
    [[nodiscard]] vector control(cvector x, int k, int j) const {
        return x.segment(control_index(k * r_ + j), m_);
    }
    double terminal_cost(cvector x, vector* gradient) const;
    [[nodiscard]] vector end_momentum(cvector x) const;
    /// The running cost at step k's point j with its gradient (2d + m) and Hessian in z.
    double integrand(cvector x, int k, int j, vector* g, matrix* hz) const;
    void add_step_equations(cvector x, vector& e, bool end_only) const;
    /// Steps first … last − 1 of jacobian() and hessian() (one thread's part).
    void step_jacobians(cvector x, double h, int first, int last,
                        std::vector<double>& values) const;
    void step_hessians(cvector x, double sigma, cvector lambda, double h, int first, int last,
                       std::vector<double>& values, vector* time_row) const;
    // A free final time's Hessian row (transcription_time.cpp): step k's point j's terms, then
    // the bounds' velocity rows' and the row's pattern or values after every other entry.
    struct time_point { // a quadrature point as step_hessians has it
        const vector &q, &v, &u, &cost_gradient, &a, &b; // b = Σ ℓ_i' λ_i / h
        double t;
    };
    void add_time_point(const time_point& at, double sigma, int k, int j, double h,
                        const matrix& hz, vector& row) const;
    void add_time_hessian(cvector x, cvector lambda, vector* row, sparsity* pattern,
                          std::vector<double>* values) const;
    // The constraints' parts (transcription_constraints.cpp; nothing without constraints).
    void check_boundary_constraints() const;
    void add_constraint_residual(cvector x, vector& e) const;
    void add_constraint_jacobian(cvector x, sparsity* pattern, std::vector<double>* values) const;
    void add_constraint_hessian(cvector x, cvector lambda, sparsity* pattern,
                                std::vector<double>* values) const;
    // The end target's parts (transcription_constraints.cpp; nothing without one).
    [[nodiscard]] int target_row() const { return points_ * d_ + (points_ - 2) * k_; }
    // The polynomials' bounds' rows after the target's (transcription_bounds.cpp): per kind,
    // per step, per evaluation point, per bounded coordinate.
    [[nodiscard]] int path_row() const { return target_row() + t_; }
    [[nodiscard]] int path_rows() const {
        return n_ * (path_bounds_[0].rows_per_step() + path_bounds_[1].rows_per_step());
    }
    void setup_path_bounds();
    void add_path_residual(cvector x, vector& e) const;
    void add_path_jacobian(cvector x, sparsity* pattern, std::vector<double>* values) const;
    /// ½ w |φ(Q_{Ns})|² with its gradient added to `gradient` (a terminal cost; else 0).
    double target_cost(cvector x, vector* gradient) const;
    void add_target_residual(cvector x, vector& e) const;
    /// The first guess of Q_{Ns}: q_end, or with an end target the nearest zero of φ from q_end
    /// within the position bounds (damped Gauss–Newton, converging where the target is reachable
    /// and stopping at the least |φ| where it is not).
    [[nodiscard]] vector end_guess() const;
    void add_target_jacobian(cvector x, sparsity* pattern, std::vector<double>* values) const;
    /// Adds to `he` (over Q_{Ns}) Σ λ_a ∇²φ_a, or σ w (JᵀJ + Σ φ_a ∇²φ_a) for the cost.
    void add_target_hessian(cvector x, double sigma, cvector lambda, matrix& he) const;
};

/// The running cost c(q, q̇, t, u) (cost_weights: effort, invariant, power) of a system at one
/// point, with its gradient and Hessian (effort and power only) in z = (q, q̇, u).
double running_cost_at(const controlled_system& s, const cost_weights& w, const matrix& effort,
                       const vector& q, const vector& v, double t, const vector& u,
                       vector* gradient, matrix* hessian);

/// The transcription of `problem` for `system`.
inline std::unique_ptr<dmoc_transcription>
transcribe(std::shared_ptr<const controlled_system> system, const control_problem& problem) {
    return std::make_unique<dmoc_transcription>(std::move(system), problem);
}

} // namespace varsym::optimal
