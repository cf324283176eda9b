// varsym/solvers/small_lu.hpp: the LU factorisation with partial pivoting of a step's Newton
// matrix (the general engine's and the constrained stepper's), of run-time size.
//
// Eigen's PartialPivLU factors a matrix of more than 16 rows by blocks (panels and GEMM
// kernels); below about 60 rows their set-up costs more than it saves. At the 18 unknowns of a
// 9-joint robot's gauss-2 or Simpson step Eigen's factorisation took 1.54 µs, the unblocked one
// here 1.06 µs (docs/performance.md, "The step's linear algebra"; clang 14 -O3, no -march).
// Above `unblocked_limit` rows it hands the matrix to Eigen's. Same algorithm as Eigen's
// unblocked path (the largest magnitude in the column as pivot, right-looking rank-1 updates),
// so the same factors where the rounding of the updates agrees. The solves multiply by U's
// reciprocal diagonal, kept from the factorisation, where Eigen's divide: back substitution is a
// chain of n divisions, each waiting for the last, and multiplying took a solve of 18 unknowns
// from 250 to 200 ns. A zero pivot is skipped as Eigen skips it, and the solves then return
// infinities or NaN, which the steppers' finiteness checks catch. (detail::solve_small,
// types.hpp, is the family stepper's one-shot solve for n ≤ 8 in fixed storage; this one keeps
// its factors for the chord updates and the sensitivities' solves.)
#pragma once

#include <cassert>
#include <cmath>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "varsym/types.hpp"

namespace varsym {

class small_lu {
  public:
    /// Above this many rows Eigen's blocked factorisation takes over: the unblocked one's
    /// factorisation and solve took 0.93, 0.98 and 1.07 times Eigen's at 48, 60 and 80 rows,
    /// so the limit stays below the crossover (between 60 and 80) with a margin.
    static constexpr Eigen::Index unblocked_limit = 48;

    small_lu() = default;
    explicit small_lu(Eigen::Index n) { reserve(n); }

    /// Sizes the storage for n rows, so that compute() at that size allocates nothing.
    void reserve(Eigen::Index n) {
        if (n > unblocked_limit) {
            eigen_ = Eigen::PartialPivLU<Eigen::MatrixXd>(n);
        } else {
            lu_.resize(n, n);
            pivots_.resize(static_cast<std::size_t>(n));
            u_inverse_.resize(static_cast<std::size_t>(n));
        }
    }

    /// Factors the square matrix a: P a = L U, L unit lower triangular.
    template <class M>
    small_lu& compute(const Eigen::MatrixBase<M>& a) {
        n_ = a.rows();
        if (n_ > unblocked_limit) {
            eigen_.compute(a);
            return *this;
        }
        lu_ = a;
        pivots_.resize(static_cast<std::size_t>(n_));
        u_inverse_.resize(static_cast<std::size_t>(n_));
        const Eigen::Index n = n_;
        double* m = lu_.data();
        for (Eigen::Index k = 0; k < n; ++k) {
            double* ck = m + k * n;
            Eigen::Index p = k;
            double biggest = std::abs(ck[k]);
            for (Eigen::Index i = k + 1; i < n; ++i)
                if (std::abs(ck[i]) > biggest) {
                    biggest = std::abs(ck[i]);
                    p = i;
                }
            pivots_[static_cast<std::size_t>(k)] = p;
            if (p != k)
                for (Eigen::Index j = 0; j < n; ++j)
                    std::swap(m[k + j * n], m[p + j * n]);
            const double inverse = 1.0 / ck[k];
            u_inverse_[static_cast<std::size_t>(k)] = inverse; // the solves multiply by it
            if (biggest == 0.0) continue; // a zero pivot: the solves' infinities (as Eigen's)
            for (Eigen::Index i = k + 1; i < n; ++i)
                ck[i] *= inverse;
            for (Eigen::Index j = k + 1; j < n; ++j) {
                double* cj = m + j * n;
                const double f = cj[k];
                if (f == 0.0) continue;
                for (Eigen::Index i = k + 1; i < n; ++i)
                    cj[i] -= ck[i] * f;
            }
        }
        return *this;
    }

    /// x = a⁻¹ b for a vector b (x may be b itself).
    void solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) const {
        assert(b.size() == n_ && "small_lu: a solve before compute(), or at another size");
        if (n_ > unblocked_limit) {
            detail::solve_into(eigen_, b, x);
            return;
        }
        x = b;
        solve_in_place(x.data());
    }

    /// X = a⁻¹ B, column by column, for a matrix B (returned).
    template <class B>
    [[nodiscard]] Eigen::MatrixXd solve(const Eigen::MatrixBase<B>& b) const {
        assert(b.rows() == n_ && "small_lu: a solve before compute(), or at another size");
        if (n_ > unblocked_limit) return eigen_.solve(b);
        Eigen::MatrixXd x = b;
        for (Eigen::Index c = 0; c < x.cols(); ++c)
            solve_in_place(x.col(c).data());
        return x;
    }

    /// out = −(rows first … first + count − 1 of a⁻¹ [I_k; 0]): k columns of the inverse, of
    /// which only those rows; a step's sensitivity ∂q_{j+1}/∂p_j, k = d. Bit for bit what
    /// solve() of [I_k; 0] gives in those rows: each column's forward substitution starts at its
    /// one after the permutation (the entries before it are zero, and so unchanged by the
    /// updates they would make), and the back substitution stops at row `first` (rows above it
    /// are not needed, and those below do not depend on them), up to (n − first)²/2 of its
    /// n²/2 multiply–adds. By solve() where a factor or a reciprocal pivot is not finite (a
    /// skipped update could then be 0 · ∞, NaN, not zero) or above unblocked_limit.
    void negated_inverse_rows(Eigen::Index k, Eigen::Index first, Eigen::Index count,
                              Eigen::MatrixXd& out) {
        assert(k <= n_ && first + count <= n_ && "small_lu: rows outside the matrix");
        bool finite = n_ <= unblocked_limit && lu_.allFinite();
        for (const double u : u_inverse_)
            finite = finite && std::isfinite(u);
        if (!finite) {
            Eigen::MatrixXd b = Eigen::MatrixXd::Zero(n_, k);
            b.topRows(k).setIdentity();
            out = -solve(b).middleRows(first, count);
            return;
        }
        const Eigen::Index n = n_;
        const double* m = lu_.data();
        column_.resize(n);
        double* x = column_.data();
        out.resize(count, k);
        for (Eigen::Index c = 0; c < k; ++c) {
            column_.setZero();
            x[c] = 1.0;
            for (Eigen::Index j = 0; j < n; ++j) {
                const Eigen::Index p = pivots_[static_cast<std::size_t>(j)];
                if (p != j) std::swap(x[j], x[p]);
            }
            Eigen::Index start = 0;
            while (x[start] == 0.0)
                ++start;
            for (Eigen::Index j = start; j < n; ++j) {
                const double xj = x[j];
                const double* cj = m + j * n;
                for (Eigen::Index i = j + 1; i < n; ++i)
                    x[i] -= cj[i] * xj;
            }
            for (Eigen::Index j = n - 1; j >= first; --j) {
                const double* cj = m + j * n;
                const double xj = x[j] *= u_inverse_[static_cast<std::size_t>(j)];
                for (Eigen::Index i = first; i < j; ++i)
                    x[i] -= cj[i] * xj;
            }
            out.col(c) = -column_.segment(first, count);
        }
    }

    [[nodiscard]] Eigen::Index rows() const { return n_; }

  private:
    /// The permutation, then L y = P b forwards, then U x = y backwards, column-oriented.
    void solve_in_place(double* x) const {
        const Eigen::Index n = n_;
        const double* m = lu_.data();
        for (Eigen::Index k = 0; k < n; ++k) {
            const Eigen::Index p = pivots_[static_cast<std::size_t>(k)];
            if (p != k) std::swap(x[k], x[p]);
        }
        for (Eigen::Index j = 0; j < n; ++j) {
            const double xj = x[j];
            const double* cj = m + j * n;
            for (Eigen::Index i = j + 1; i < n; ++i)
                x[i] -= cj[i] * xj;
        }
        for (Eigen::Index j = n - 1; j >= 0; --j) {
            const double* cj = m + j * n;
            const double xj = x[j] *= u_inverse_[static_cast<std::size_t>(j)];
            for (Eigen::Index i = 0; i < j; ++i)
                x[i] -= cj[i] * xj;
        }
    }

    Eigen::Index n_ = 0;
    Eigen::MatrixXd lu_;
    Eigen::VectorXd column_; // negated_inverse_rows' scratch
    std::vector<Eigen::Index> pivots_;
    std::vector<double> u_inverse_; // 1/u_kk
    Eigen::PartialPivLU<Eigen::MatrixXd> eigen_;
};

} // namespace varsym
