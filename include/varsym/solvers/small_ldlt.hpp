// varsym/solvers/small_ldlt.hpp: the factorisation A = L D Lᵀ (L unit lower triangular, D
// diagonal; Cholesky without square roots) of a symmetric positive definite matrix of run-time
// size: a robot's mass matrix M(q) in the general engine's predictor (q̇ = M⁻¹p and
// q̈ = M⁻¹(f − b), two solves with one factorisation each step) and in the momentum's projection
// onto the constraints (systems/constraints.hpp).
//
// Eigen's LDLT at run-time size pivots on the diagonal, divides by D in every solve and goes
// through its generic triangular kernels; at a robot's 6–12 joints its cost is the latency of
// those divisions and the kernels' set-up (docs/performance.md, "The step's linear algebra", has
// the timings). Here: plain column-oriented loops, D⁻¹ kept from the factorisation (the solves
// multiply), no pivoting. LDLᵀ without pivoting is backward stable for any positive definite
// matrix, as Cholesky is, whose factor is L D^½ (Higham, Accuracy and Stability of Numerical
// Algorithms, 2nd ed., §10.1); a pivot of D that is not positive, or is NaN, stops it and is
// reported (A not positive definite to working precision, or NaN in it).
#pragma once

#include <cassert>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "varsym/types.hpp"

namespace varsym {

class small_ldlt {
  public:
    /// Above this many rows Eigen's LDLT takes over (with its check of D): the loops here took
    /// 1.03 and 1.17 times its time (factorisation and two solves) at 50 and 100 rows, and
    /// 0.73–0.86 times at 20–32 rows.
    static constexpr Eigen::Index unblocked_limit = 32;

    /// Factors the symmetric a (its lower triangle is read) and returns true; returns false
    /// where a pivot is not positive or is NaN (a is not positive definite to working
    /// precision, or a NaN reached a pivot), after which solve() must not be called.
    template <class M>
    bool compute(const Eigen::MatrixBase<M>& a) {
        n_ = a.rows();
        if (n_ > unblocked_limit) {
            eigen_.compute(a);
            return ok_ = eigen_.info() == Eigen::Success && (eigen_.vectorD().array() > 0.0).all();
        }
        l_ = a;
        d_inverse_.resize(n_);
        const Eigen::Index n = n_;
        double* m = l_.data();
        for (Eigen::Index k = 0; k < n; ++k) {
            double* ck = m + k * n; // column k: a_ik less the earlier columns' terms, i ≥ k
            if (!(ck[k] > 0.0)) return ok_ = false; // also NaN
            const double inverse = 1.0 / ck[k];
            d_inverse_(k) = inverse;
            // The trailing lower triangle less l_ik d_k l_jk = a_ik (a_jk / d_k).
            for (Eigen::Index j = k + 1; j < n; ++j) {
                double* cj = m + j * n;
                const double f = ck[j] * inverse;
                for (Eigen::Index i = j; i < n; ++i)
                    cj[i] -= ck[i] * f;
            }
            for (Eigen::Index i = k + 1; i < n; ++i)
                ck[i] *= inverse; // l_ik
        }
        return ok_ = true;
    }

    /// x = a⁻¹ b (x may be b itself): L y = b forwards, D⁻¹, then Lᵀ x = y backwards.
    void solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) const {
        assert(ok_ && b.size() == n_ && "small_ldlt: a solve without a factorisation");
        if (n_ > unblocked_limit) {
            detail::solve_into(eigen_, b, x);
            return;
        }
        x = b;
        const Eigen::Index n = n_;
        const double* m = l_.data();
        double* y = x.data();
        for (Eigen::Index j = 0; j < n; ++j) {
            const double* cj = m + j * n;
            const double yj = y[j];
            for (Eigen::Index i = j + 1; i < n; ++i)
                y[i] -= cj[i] * yj;
        }
        for (Eigen::Index j = 0; j < n; ++j)
            y[j] *= d_inverse_(j);
        for (Eigen::Index j = n - 1; j >= 0; --j) {
            const double* cj = m + j * n;
            double s = y[j];
            for (Eigen::Index i = j + 1; i < n; ++i)
                s -= cj[i] * y[i];
            y[j] = s;
        }
    }

    [[nodiscard]] Eigen::Index rows() const { return n_; }

  private:
    Eigen::Index n_ = 0;
    bool ok_ = false;
    Eigen::MatrixXd l_;
    Eigen::VectorXd d_inverse_;
    Eigen::LDLT<Eigen::MatrixXd> eigen_;
};

/// types.hpp's solve_positive_definite and solve_symmetric_again by small_ldlt (a run-time N),
/// for a matrix known to be symmetric: a robot's M(q).
template <int N>
bool solve_positive_definite(small_ldlt& f, const mat<N>& a, const vec<N>& b, vec<N>& x) {
    static_assert(N == dynamic, "small_ldlt is for run-time sizes");
    if (!f.compute(a)) return false;
    f.solve(b, x);
    return true;
}
template <int N>
void solve_symmetric_again(const small_ldlt& f, const mat<N>&, const vec<N>& b, vec<N>& x) {
    static_assert(N == dynamic, "small_ldlt is for run-time sizes");
    f.solve(b, x);
}

} // namespace varsym
