// varsym/solvers/compensated.hpp: compensated (Kahan) summation of the per-step increments of
// q and p, so that long runs accumulate round-off relative to the increments, not to |q|, |p|.
#pragma once

#include "varsym/types.hpp"

namespace varsym {

/// Applies x.q += Δq, x.p += Δp keeping the low-order bits lost by each addition and adding
/// them back at the next step (Kahan's compensated summation, as in Hairer's GNI codes).
/// Call add_q, then add_p, once per step. The carried bits are dropped when x was changed
/// between steps by someone else.
template <int D>
class compensated_update {
  public:
    compensated_update() {
        if constexpr (D != dynamic) // defined values, though unread until the first add_q
            for (auto* v : {&cq_, &cp_, &q_, &p_})
                v->setZero();
    }
    /// dq and dp: a vector, a column of a matrix or an expression, read while x is updated
    /// (no copy made): they must not refer to x.
    template <class Dq>
    void add_q(phase_state<D>& x, const Eigen::MatrixBase<Dq>& dq) {
        if (!valid_ || x.q != q_ || x.p != p_) {
            cq_.setZero(x.q.size());
            cp_.setZero(x.p.size());
        }
        add(x.q, dq, cq_);
    }
    template <class Dp>
    void add_p(phase_state<D>& x, const Eigen::MatrixBase<Dp>& dp) {
        add(x.p, dp, cp_);
        q_ = x.q;
        p_ = x.p;
        valid_ = true;
    }

    /// The low-order bits not yet added to x.q and x.p (what a checkpoint must keep).
    [[nodiscard]] const vec<D>& carry_q() const { return cq_; }
    [[nodiscard]] const vec<D>& carry_p() const { return cp_; }
    /// Continues a summation whose last sums were x and whose carries were cq, cp (a resumed
    /// run): the next step is then bit for bit the step the interrupted run would have taken.
    void restore(const phase_state<D>& x, const vec<D>& cq, const vec<D>& cp) {
        q_ = x.q;
        p_ = x.p;
        cq_ = cq;
        cp_ = cp;
        valid_ = true;
    }

  private:
    template <class Increment>
    static void add(vec<D>& sum, const Eigen::MatrixBase<Increment>& increment, vec<D>& carry) {
        for (Eigen::Index i = 0; i < sum.size(); ++i) {
            const double y = increment(i) + carry(i);
            const double t = sum(i) + y;
            carry(i) = (sum(i) - t) + y;
            sum(i) = t;
        }
    }
    vec<D> cq_{}, cp_{}, q_{}, p_{};
    bool valid_ = false;
};

/// Plain x.q += Δq, x.p += Δp with the interface of compensated_update: the baseline that
/// `make soak` compares compensated summation against.
template <int D>
struct plain_update {
    template <class Dq>
    void add_q(phase_state<D>& x, const Eigen::MatrixBase<Dq>& dq) {
        x.q += dq;
    }
    template <class Dp>
    void add_p(phase_state<D>& x, const Eigen::MatrixBase<Dp>& dp) {
        x.p += dp;
    }
};

} // namespace varsym
