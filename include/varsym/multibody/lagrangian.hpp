// varsym/multibody/lagrangian.hpp: a multibody model as a Lagrangian of run-time dimension for
// the variational engines: L(q, q̇) = ½ q̇ᵀM(q)q̇ − V(q) with its derivatives by the recursive
// algorithms (algorithms.hpp): gradient() in O(n), derivatives() in O(n²), never by automatic
// differentiation. One shared constant model; one workspace per thread, so that one Lagrangian
// serves an ensemble's threads and an evaluation allocates nothing once sized.
// The members that run the algorithms are templates with a defaulted parameter
// (`template <class = void>`), called as plain members: a source that includes this header and
// never calls them does not compile them (docs/development.md).
#pragma once

#include <memory>
#include <utility>

#include "varsym/autodiff/second_order.hpp"
#include "varsym/multibody/algorithms.hpp"
#include "varsym/multibody/articulated.hpp"
#include "varsym/systems/lagrangian.hpp"

namespace varsym::multibody {

/// One thread's factorisation of a robot's M(q) (robot_lagrangian::factor_mass): articulated
/// (articulated.hpp), or dense with mimic joints.
struct mass_factorisation {
    articulated_factor aba;
    Eigen::MatrixXd dense;
    Eigen::LLT<Eigen::MatrixXd> llt;
};

class robot_lagrangian {
  public:
    static constexpr int dim = dynamic;
    /// Several threads may call one robot_lagrangian at once (one workspace per thread).
    static constexpr bool concurrent = true;
    /// A multibody model (recursive derivatives): optimal control solves its problems with
    /// IPOPT's iterative refinement where the residual asks for it only (optimal/solve.hpp).
    static constexpr bool multibody = true;

    explicit robot_lagrangian(std::shared_ptr<const tree> m) : m_(std::move(m)) {
        if (!m_ || m_->dof() < 1)
            throw std::invalid_argument("a robot needs at least one moving joint");
        m_->check();
    }

    [[nodiscard]] int dimension() const { return m_->dof(); }
    [[nodiscard]] const tree& robot() const { return *m_; }
    [[nodiscard]] const std::shared_ptr<const tree>& shared() const { return m_; }

    /// L(q, q̇) [J].
    template <class = void>
    double operator()(const vec<dynamic>& q, const vec<dynamic>& v) const {
        workspace& w = work();
        kinematics(*m_, w, q, false);
        velocities(*m_, w, v);
        return lagrangian_value(*m_, w);
    }

    /// L, ∂L/∂q and ∂L/∂q̇ (O(n)).
    template <class = void>
    void gradient(const vec<dynamic>& q, const vec<dynamic>& v,
                  lagrangian_terms<dynamic>& t) const {
        size(t, false);
        t.value = lagrangian_gradient(*m_, work(), q, v, t.lq, t.lv);
    }

    /// gradient() and the second derivatives (O(n²)); lvv is M(q).
    template <class = void>
    void derivatives(const vec<dynamic>& q, const vec<dynamic>& v,
                     lagrangian_terms<dynamic>& t) const {
        size(t, true);
        t.value = lagrangian_derivatives(*m_, work(), q, v, t.lq, t.lv, t.lqq, t.lqv, t.lvv);
    }

    /// M(q) = ∂²L/∂q̇² alone, by the composite-rigid-body algorithm (O(n²); no velocity terms):
    /// what velocity(q, p) and the steppers' predictor factorise.
    template <class = void>
    void mass_matrix(const vec<dynamic>& q, mat<dynamic>& out) const {
        const int n = m_->dof();
        out.resize(n, n);
        multibody::mass_matrix(*m_, work(), q, out);
    }

    /// Factorises M(q) for solve_mass and mass_diagonal on this thread: by the articulated-body
    /// algorithm in O(n) (articulated.hpp), or, with mimic joints, the composite-rigid-body M by
    /// Cholesky. False where M(q) is not positive definite.
    template <class = void>
    bool factor_mass(const vec<dynamic>& q) const {
        auto& f = factor<>();
        if (m_->mimics.empty()) return multibody::factor_mass(*m_, work(), q, f.aba);
        mass_matrix(q, f.dense);
        f.aba.diagonal = f.dense.diagonal();
        f.llt.compute(f.dense);
        return f.llt.info() == Eigen::Success;
    }
    /// x ← M(q)⁻¹x at the q of this thread's last factor_mass, for each column of x (O(n) a
    /// column without mimic joints).
    template <class X = vec<dynamic>>
    void solve_mass(Eigen::MatrixBase<X>& x) const {
        auto& f = factor<>();
        if (m_->mimics.empty())
            multibody::solve_mass(*m_, f.aba, x);
        else
            f.llt.solveInPlace(x);
    }
    /// M(q)'s diagonal at the q of this thread's last factor_mass.
    template <class = void>
    [[nodiscard]] const Eigen::VectorXd& mass_diagonal() const {
        return factor<>().aba.diagonal;
    }

    /// b = C(q, q̇)q̇ + g(q) = (∂²L/∂q̇∂q) q̇ − ∂L/∂q by the recursive Newton–Euler algorithm
    /// (O(n)): M(q)q̈ + b = f is the motion, from which the predictor takes its acceleration.
    template <class = void>
    void bias_forces(const vec<dynamic>& q, const vec<dynamic>& v, vec<dynamic>& out) const {
        out.resize(m_->dof());
        multibody::bias_forces(*m_, work(), q, v, out);
    }

    /// bias_forces(q, v, out) at the q of this thread's last mass_matrix (or factor_mass) call,
    /// with no robot evaluated on this thread between (the workspace is every robot_lagrangian's on
    /// the thread, a force's evaluations of the robot included): that call's kinematics are kept
    /// (the predictor's q̇ = M⁻¹p between the two saves one tree pass).
    template <class = void>
    void bias_forces_after_mass_matrix(const vec<dynamic>& v, vec<dynamic>& out) const {
        out.resize(m_->dof());
        multibody::bias_forces_after_kinematics(*m_, work(), v, out);
    }

    /// The Hessian in z = (q, q̇) (2n square) of aᵀ ∂L/∂q + bᵀ ∂L/∂q̇: L's third derivatives
    /// contracted with (a, b), which an optimal control transcription's exact Hessian needs.
    /// Exact: the rates along (a, b) of the second derivatives, by the same O(n²) algorithm
    /// run over dual numbers (a value and one directional derivative: ad::first_order<1>).
    template <class = void>
    void third(const vec<dynamic>& q, const vec<dynamic>& v, const vec<dynamic>& a,
               const vec<dynamic>& b, mat<dynamic>& out) const {
        using E = ad::first_order<1>;
        using dvec = Eigen::Matrix<E, Eigen::Dynamic, 1>;
        using dmat = Eigen::Matrix<E, Eigen::Dynamic, Eigen::Dynamic>;
        thread_local basic_workspace<E> w; // no allocation once sized
        thread_local dvec qe, ve, lq, lv;
        thread_local dmat lqq, lqv, lvv;
        const int n = m_->dof();
        qe.resize(n);
        ve.resize(n);
        lq.resize(n);
        lv.resize(n);
        lqq.resize(n, n);
        lqv.resize(n, n);
        lvv.resize(n, n);
        for (int i = 0; i < n; ++i) {
            qe(i) = E(q(i), Eigen::Matrix<double, 1, 1>(a(i)));
            ve(i) = E(v(i), Eigen::Matrix<double, 1, 1>(b(i)));
        }
        lagrangian_derivatives(*m_, w, qe, ve, lq, lv, lqq, lqv, lvv);
        const auto rate = [](const E& x) { return x.derivatives()(0); };
        out.resize(2 * n, 2 * n);
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                out(i, j) = rate(lqq(i, j));
                out(i, n + j) = out(n + j, i) = rate(lqv(i, j));
                out(n + i, n + j) = rate(lvv(i, j));
            }
    }

    /// The calling thread's workspace (sized on first use by the algorithms).
    static workspace& work() {
        thread_local workspace w;
        return w;
    }

  private:
    std::shared_ptr<const tree> m_;

    /// The calling thread's factorisation of M (factor_mass).
    template <class = void>
    static mass_factorisation& factor() {
        thread_local mass_factorisation f;
        return f;
    }

    void size(lagrangian_terms<dynamic>& t, bool second) const {
        const int n = m_->dof();
        t.lq.resize(n);
        t.lv.resize(n);
        if (!second) return;
        t.lqq.resize(n, n);
        t.lqv.resize(n, n);
        t.lvv.resize(n, n);
    }
};

} // namespace varsym::multibody
