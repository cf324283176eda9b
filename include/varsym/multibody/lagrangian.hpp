// varsym/multibody/lagrangian.hpp: a multibody model as a Lagrangian of run-time dimension for
// the variational engines: L(q, q̇) = ½ q̇ᵀM(q)q̇ − V(q) with its derivatives by the recursive
// algorithms (algorithms.hpp): gradient() in O(n), derivatives() in O(n²), never by automatic
// differentiation. One shared constant model; one workspace per thread, so that one Lagrangian
// serves an ensemble's threads and an evaluation allocates nothing once sized.
#pragma once

#include <memory>
#include <utility>

#include "varsym/multibody/algorithms.hpp"
#include "varsym/systems/lagrangian.hpp"

namespace varsym::multibody {

class robot_lagrangian {
  public:
    static constexpr int dim = dynamic;

    explicit robot_lagrangian(std::shared_ptr<const model> m) : m_(std::move(m)) {
        if (!m_ || m_->dof() < 1)
            throw std::invalid_argument("a robot needs at least one moving joint");
        m_->check();
    }

    [[nodiscard]] int dimension() const { return m_->dof(); }
    [[nodiscard]] const model& robot() const { return *m_; }
    [[nodiscard]] const std::shared_ptr<const model>& shared() const { return m_; }

    /// L(q, q̇) [J].
    double operator()(const vec<dynamic>& q, const vec<dynamic>& v) const {
        workspace& w = work();
        kinematics(*m_, w, q);
        velocities(*m_, w, v);
        return lagrangian_value(*m_, w);
    }

    /// L, ∂L/∂q and ∂L/∂q̇ (O(n)).
    void gradient(const vec<dynamic>& q, const vec<dynamic>& v,
                  lagrangian_terms<dynamic>& t) const {
        size(t, false);
        t.value = lagrangian_gradient(*m_, work(), q, v, t.lq, t.lv);
    }

    /// gradient() and the second derivatives (O(n²)); lvv is M(q).
    void derivatives(const vec<dynamic>& q, const vec<dynamic>& v,
                     lagrangian_terms<dynamic>& t) const {
        size(t, true);
        t.value = lagrangian_derivatives(*m_, work(), q, v, t.lq, t.lv, t.lqq, t.lqv, t.lvv);
    }

    /// The calling thread's workspace (sized on first use by the algorithms).
    static workspace& work() {
        thread_local workspace w;
        return w;
    }

  private:
    std::shared_ptr<const model> m_;

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
