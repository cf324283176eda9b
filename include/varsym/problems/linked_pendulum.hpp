// varsym/problems/linked_pendulum.hpp: the planar pendulum of n links (an unactuated serial
// arm), a Lagrangian whose mass matrix depends on q, with derivatives both by hand and through
// automatic differentiation (the general engine's benchmark at d = n; docs/autodiff.md).
//
// Units and conventions: link i (i = 0 … n−1, from the pivot) has length l_i and a point mass
// m_i at its far end; θ_i is its angle from the downward vertical (counter-clockwise), ω_i = θ̇_i;
// g is the gravitational acceleration. With μ_k = Σ_{j≥k} m_j (the mass carried by link k),
//   L = ½ Σ_ij a_ij cos(θ_i − θ_j) ω_i ω_j + Σ_i b_i cos θ_i,
//   a_ij = l_i l_j μ_max(i,j) + δ_ij J_i,  b_i = g l_i μ_i  (J_i: an optional rotational inertia)
// (n = 2 is problems/double_pendulum.hpp). The energy is conserved.
#pragma once

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "varsym/systems/lagrangian.hpp"

namespace varsym::linked_pendulum {

/// The Lagrangian for N links (N fixed at compile time, or `dynamic`: the number of masses
/// given), L written once for any scalar type (automatic derivatives), with gradient() and
/// derivatives() by hand beside it.
template <int N>
struct lagrangian {
    static constexpr int dim = N;
    mat<N> a; ///< a_ij = l_i l_j μ_max(i,j) (+ J_i on the diagonal)
    vec<N> b; ///< b_i = g l_i μ_i

    /// Links of masses m and lengths l (positive, N each) under gravity g ≥ 0; optionally a
    /// rotational inertia J_i ≥ 0 of each link [kg m²] besides its end mass (its kinetic energy
    /// ½ J_i θ̇_i²: a link's inertia about its centre of mass, or a joint's rotor).
    lagrangian(const std::vector<double>& m, const std::vector<double>& l, double g,
               const std::vector<double>& inertia = {}) {
        const int n = N == dynamic ? static_cast<int>(m.size()) : N;
        if (n < 1 || static_cast<int>(m.size()) != n || static_cast<int>(l.size()) != n)
            throw std::invalid_argument("a linked pendulum of " + std::to_string(n) +
                                        " links needs " + std::to_string(n) +
                                        " masses and lengths, got " + std::to_string(m.size()) +
                                        " and " + std::to_string(l.size()));
        if (!inertia.empty() && static_cast<int>(inertia.size()) != n)
            throw std::invalid_argument("give one moment of inertia per link (" +
                                        std::to_string(n) + "), got " +
                                        std::to_string(inertia.size()));
        for (int i = 0; i < n; ++i)
            if (!(std::isfinite(m[i]) && m[i] > 0.0 && std::isfinite(l[i]) && l[i] > 0.0))
                throw std::invalid_argument("link masses and lengths must be positive");
        for (double j : inertia)
            if (!(std::isfinite(j) && j >= 0.0))
                throw std::invalid_argument("link moments of inertia must be >= 0");
        if (!(std::isfinite(g) && g >= 0.0))
            throw std::invalid_argument("gravity must be finite and >= 0");
        vec<N> mu(n);
        a.resize(n, n);
        b.resize(n);
        double carried = 0.0;
        for (int i = n - 1; i >= 0; --i)
            mu(i) = carried += m[i];
        for (int i = 0; i < n; ++i) {
            b(i) = g * l[i] * mu(i);
            for (int j = 0; j < n; ++j)
                a(i, j) = l[i] * l[j] * mu(std::max(i, j));
            if (!inertia.empty()) a(i, i) += inertia[i];
        }
    }

    [[nodiscard]] int dimension() const { return static_cast<int>(b.size()); }

    template <class T>
    T operator()(const tvec<T, N>& q, const tvec<T, N>& v) const {
        using std::cos;
        T l(0.0);
        const int n = dimension();
        for (int i = 0; i < n; ++i) {
            l += (0.5 * a(i, i)) * v(i) * v(i) + b(i) * cos(q(i));
            for (int j = i + 1; j < n; ++j)
                l += a(i, j) * cos(q(i) - q(j)) * v(i) * v(j);
        }
        return l;
    }

    /// L, ∂L/∂q and ∂L/∂q̇ by hand: with c_kj = cos(θ_k − θ_j), s_kj = sin(θ_k − θ_j),
    ///   ∂L/∂ω_k = Σ_j a_kj c_kj ω_j,  ∂L/∂θ_k = −ω_k Σ_j a_kj s_kj ω_j − b_k sin θ_k.
    void gradient(const vec<N>& q, const vec<N>& v, lagrangian_terms<N>& t) const {
        scratch local; // unused at N = dynamic
        first_derivatives(q, v, t, N == dynamic ? work() : local);
    }

    /// gradient() and the second derivatives by hand:
    ///   ∂²L/∂ω_k∂ω_j = a_kj c_kj,
    ///   ∂²L/∂θ_k∂ω_m = −δ_km Σ_j a_kj s_kj ω_j − ω_k a_km s_km,
    ///   ∂²L/∂θ_k∂θ_m = a_km c_km ω_k ω_m (m ≠ k),  −ω_k Σ_{j≠k} a_kj c_kj ω_j − b_k cos θ_k (m =
    ///   k).
    void derivatives(const vec<N>& q, const vec<N>& v, lagrangian_terms<N>& t) const {
        scratch local; // unused at N = dynamic
        scratch& w = N == dynamic ? work() : local;
        first_derivatives(q, v, t, w);
        t.lvv = w.ac;
        t.lqv = -(v.asDiagonal() * w.as);
        t.lqv.diagonal() -= w.sw;
        t.lqq = v.asDiagonal() * w.ac * v.asDiagonal();
        // t.lv = Σ_j a_kj c_kj ω_j includes j = k: a_kk ω_k, taken out below.
        for (int k = 0; k < dimension(); ++k)
            t.lqq(k, k) = -v(k) * (t.lv(k) - w.ac(k, k) * v(k)) - b(k) * std::cos(q(k));
    }

    /// The Hessian in (q, q̇) (2n square) of dqᵀ ∂L/∂q + dvᵀ ∂L/∂q̇: the rates of the second
    /// derivatives above along (dq, dv), by hand (an optimal control transcription's exact
    /// Hessian needs them). With δ_kj = dq_k − dq_j, d c_kj = −s_kj δ_kj, d s_kj = c_kj δ_kj:
    ///   d L_q̇q̇(k, j) = −a_kj s_kj δ_kj,
    ///   d L_qq̇(k, m) = −δ_km Σ_j a_kj (c_kj δ_kj ω_j + s_kj dv_j) − dv_k a_km s_km
    ///                  − ω_k a_km c_km δ_km,
    ///   d L_qq(k, m) = a_km (c_km (dv_k ω_m + ω_k dv_m) − s_km δ_km ω_k ω_m)  (m ≠ k),
    ///   d L_qq(k, k) = −Σ_{j≠k} a_kj (c_kj (dv_k ω_j + ω_k dv_j) − s_kj δ_kj ω_k ω_j)
    ///                  + b_k sin θ_k dq_k.
    void third(const vec<N>& q, const vec<N>& v, const vec<N>& dq, const vec<N>& dv,
               mat<dynamic>& out) const {
        const int n = dimension();
        scratch local; // unused at N = dynamic
        scratch& w = N == dynamic ? work() : local;
        trig(q, w);
        out.setZero(2 * n, 2 * n);
        for (int k = 0; k < n; ++k) {
            double diagonal = b(k) * std::sin(q(k)) * dq(k), sum = 0.0;
            for (int j = 0; j < n; ++j) {
                if (j == k) continue;
                const double akj = a(k, j), c = w.c(k, j), sn = w.s(k, j), d = dq(k) - dq(j);
                out(n + k, n + j) = -akj * sn * d;
                out(k, n + j) = -dv(k) * akj * sn - v(k) * akj * c * d;
                sum += akj * (c * d * v(j) + sn * dv(j));
                const double qq = akj * (c * (dv(k) * v(j) + v(k) * dv(j)) - sn * d * v(k) * v(j));
                out(k, j) = qq;
                diagonal -= qq;
            }
            out(k, n + k) = -sum;
            out(k, k) = diagonal;
        }
        out.bottomLeftCorner(n, n) = out.topRightCorner(n, n).transpose();
    }

  private:
    /// The matrices and vectors of one evaluation. At N = dynamic one set per thread (the
    /// Lagrangian stays const and shareable), so that an evaluation allocates nothing once they
    /// have the size (the arm of 6 links on the general engine: 94 → 15 allocations a gauss-2
    /// step); at a fixed N on the stack.
    struct scratch {
        mat<N> c, s, ac, as;
        vec<N> cq, sq, sw;
    };
    static scratch& work() {
        thread_local scratch w;
        return w;
    }
    /// L, ∂L/∂q and ∂L/∂q̇ (gradient()), leaving a_kj c_kj, a_kj s_kj and Σ_j a_kj s_kj ω_j in w
    /// for the second derivatives.
    void first_derivatives(const vec<N>& q, const vec<N>& v, lagrangian_terms<N>& t,
                           scratch& w) const {
        trig(q, w);
        w.ac = a.cwiseProduct(w.c);
        w.as = a.cwiseProduct(w.s);
        t.lv.noalias() = w.ac * v;
        w.sw.noalias() = w.as * v;
        t.value = 0.5 * v.dot(t.lv) + b.dot(q.array().cos().matrix());
        t.lq = -v.cwiseProduct(w.sw) - b.cwiseProduct(q.array().sin().matrix());
    }
    /// c_ij = cos(θ_i − θ_j) and s_ij = sin(θ_i − θ_j) from 2N sines and cosines.
    static void trig(const vec<N>& q, scratch& w) {
        w.cq = q.array().cos().matrix();
        w.sq = q.array().sin().matrix();
        w.c.noalias() = w.cq * w.cq.transpose();
        w.c.noalias() += w.sq * w.sq.transpose();
        w.s.noalias() = w.sq * w.cq.transpose();
        w.s.noalias() -= w.cq * w.sq.transpose();
    }
};

/// The same Lagrangian without its hand derivatives: the general engine differentiates it
/// automatically (to compare the two in tests and benchmarks).
template <int N>
struct automatic {
    static constexpr int dim = N;
    lagrangian<N> l;
    template <class T>
    T operator()(const tvec<T, N>& q, const tvec<T, N>& v) const {
        return l(q, v);
    }
};

} // namespace varsym::linked_pendulum
