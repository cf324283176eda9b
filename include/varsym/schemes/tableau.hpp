// varsym/schemes/tableau.hpp: the tables of one member of the variational family (rule × degree
// s): control nodes, quadrature, Lagrange basis values and slopes at the quadrature points, and
// the stiffness matrix A. Shared by the separable family (galerkin.hpp) and the general engine
// (variational.hpp). See docs/design.md, "The family".
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "varsym/quadrature/rules.hpp"

namespace varsym::galerkin {

enum class rule_kind { lobatto, gauss };

/// Largest degree offered (order 16). It bounds the storage a stepper reserves; double precision
/// already stops measuring orders at s = 5 or 6.
inline constexpr int max_degree = 8;

/// The tables of one member: control nodes d_i, quadrature (c_k, w_k), ℓ_i(c_k), ℓ_i'(c_k), A.
struct tableau {
    int degree = 0;
    rule_kind kind = rule_kind::lobatto;
    std::vector<double> control; ///< d_0 … d_s (Gauss–Lobatto nodes on [0, 1])
    quadrature::rule quad;       ///< c_k, w_k
    Eigen::MatrixXd phi;         ///< (s+1) × r: ℓ_i(c_k)
    Eigen::MatrixXd dphi;        ///< (s+1) × r: ℓ_i'(c_k)
    Eigen::MatrixXd stiffness;   ///< (s+1) × (s+1): A_il
    /// What rounding to double left out of dphi (entry minus its double): the general engine's
    /// velocities use dphi + dphi_lo, ℓ_i'(c_k) to ~1e-19.
    Eigen::MatrixXd dphi_lo;

    /// A table as a double plus what rounding left out of it (hi + lo holds the long double
    /// value to ~1e-19 relative); applied as hi·x + lo·x.
    struct split {
        Eigen::MatrixXd hi, lo;
    };
    /// The coefficients of a step's equations i = 0 … s−1 in the increments X_l = Q_l − q_j
    /// (l = 1 … s), for the discrete Lagrangian whose points q_k = q_j + Σ_{l≥1} phi(l, k) X_l
    /// use phi as stored (docs/design.md, "Round-off that tilts the map"):
    ///   kinetic (s × s): A_il for l ≥ 1, with row 0 = −Σ_{i≥1} A_il (row sums of A are zero);
    ///   wphi (s × r):  w_k ℓ_i(c_k), with ℓ_0(c_k) = 1 − Σ_{l≥1} phi(l, k);
    ///   wdphi (s × r): w_k ℓ_i'(c_k), with ℓ_0'(c_k) = −Σ_{l≥1} ℓ_l'(c_k);
    ///   weights_lo: w_k − quad.weights[k].
    /// Built in double-double from the long double tables, so the identities the step relies on
    /// (the equations summed give p_{j+1} = p_j − h Σ_k w_k ∇V(q_k)) hold to ~1e-31 for the
    /// values as applied, not to the ulp of each entry (long double alone would leave ~1e-19 |A|;
    /// no difference between the two was measured on the pendulum). With plainly rounded tables
    /// they miss by ~1e-16 relative, always the same way, and the energy drifts linearly (+2.6e-9
    /// over 10⁵ pendulum periods at gauss-6, h = T/20).
    split kinetic, wphi, wdphi;
    std::vector<double> weights_lo;
    /// The previous step's polynomial continued over the next step, in increments (s × s):
    /// X_next = X_prev E with E(m−1, l−1) = ℓ_m(1 + d_l) − [m = s] (m, l = 1 … s), since
    /// q(t_j + d_l h) − q_j = Σ_m ℓ_m(1 + d_l) X_prev,m − X_prev,s. A starting guess only.
    Eigen::MatrixXd extrapolation;
    /// A separable step's equations (galerkin.hpp) in closed form: X = h² M⁻¹ G K + h v cᵀ with
    /// G = ∇V at the points, v = M⁻¹ p_j, K = (A⁻¹ U)ᵀ (sweep, r × s) and c = −A⁻¹ e_0 (flight,
    /// 1 × s; the control nodes d_1 … d_s), for A and U as kinetic and wphi apply them. Solved
    /// in long double and refined once against a double-double residual, so that hi + lo hold
    /// them far below an ulp (tests/schemes/test_iteration.cpp checks 1e-18 in long double, the
    /// limit of its arithmetic): the closed form's root is then the equations' own, not one
    /// tilted by a rounded K (docs/design.md, "Solving the step").
    split sweep, flight;
    /// The previous step's gradients at its quadrature points continued to this step's (HLW
    /// §VIII.6.1, "starting approximations"): ∇V at c_k ≈ Σ_m G_m E(m, k) over the nodes c_m − 1
    /// of the previous step and, for Gauss, 0 (∇V(q_j)); Lobatto's c_s − 1 is already 0.
    /// (r × r) for Lobatto, ((r + 1) × r) for Gauss.
    Eigen::MatrixXd force_extrapolation;

    /// Builds the tables in long double (64-bit mantissa) and rounds each entry once to double,
    /// so that their errors stay at half an ulp: the scheme's period is then right to ~1 ulp.
    static tableau make(rule_kind kind, int s) {
        using LD = long double;
        if (s < 1 || s > max_degree)
            throw std::invalid_argument("degree must be between 1 and " +
                                        std::to_string(max_degree) + ", got " + std::to_string(s));
        const auto control = quadrature::gauss_lobatto<LD>(s + 1).nodes;
        const auto quad = kind == rule_kind::lobatto ? quadrature::gauss_lobatto<LD>(s + 1)
                                                     : quadrature::gauss_legendre<LD>(s);
        const auto r = static_cast<Eigen::Index>(quad.size());
        using matrix_ld = Eigen::Matrix<LD, Eigen::Dynamic, Eigen::Dynamic>;
        matrix_ld phi(s + 1, r), dphi(s + 1, r);
        for (int i = 0; i <= s; ++i)
            for (Eigen::Index k = 0; k < r; ++k) {
                const LD x = quad.nodes[k];
                LD value = 1, slope = 0;
                for (int m = 0; m <= s; ++m) {
                    if (m == i) continue;
                    const LD inv = 1 / (control[i] - control[m]);
                    slope = slope * (x - control[m]) * inv + value * inv; // product rule
                    value *= (x - control[m]) * inv;
                }
                phi(i, k) = value;
                dphi(i, k) = slope;
            }
        if (kind == rule_kind::lobatto) phi.setIdentity(); // c_k = d_k: ℓ_i(c_k) = δ_ik exactly
        matrix_ld extrapolation(s, s);
        for (int m = 1; m <= s; ++m)
            for (int l = 1; l <= s; ++l) {
                const LD x = 1 + control[l];
                LD value = 1;
                for (int n = 0; n <= s; ++n)
                    if (n != m) value *= (x - control[n]) / (control[m] - control[n]);
                extrapolation(m - 1, l - 1) = value - (m == s ? 1 : 0);
            }
        matrix_ld stiffness(s + 1, s + 1); // A_il = Σ_k ℓ_i'(c_k) w_k ℓ_l'(c_k)
        for (int i = 0; i <= s; ++i)
            for (int l = 0; l <= i; ++l) {
                LD sum = 0;
                for (Eigen::Index k = 0; k < r; ++k)
                    sum += dphi(i, k) * quad.weights[k] * dphi(l, k);
                stiffness(i, l) = stiffness(l, i) = sum; // exactly symmetric
            }

        tableau t;
        t.degree = s;
        t.kind = kind;
        t.control.assign(control.begin(), control.end());
        t.quad.nodes.assign(quad.nodes.begin(), quad.nodes.end());
        t.quad.weights.assign(quad.weights.begin(), quad.weights.end());
        t.phi = phi.cast<double>();
        t.dphi = dphi.cast<double>();
        t.stiffness = stiffness.cast<double>();
        t.dphi_lo = (dphi - t.dphi.cast<LD>()).cast<double>();
        t.extrapolation = extrapolation.cast<double>();
        t.make_step_coefficients(stiffness, dphi, quad.weights);
        t.make_starts(quad.nodes);
        return t;
    }
    [[nodiscard]] int order() const { return 2 * degree; }

  private:
    /// A double-double h + l (Dekker): sums and products of the tables' long double values to
    /// ~1e-32, so that the derived entries below satisfy their identities far below an ulp.
    struct dd {
        double h = 0, l = 0;
        static dd of(long double x) {
            const double h = static_cast<double>(x);
            return {h, static_cast<double>(x - h)}; // exact: 64 bits fit in two doubles
        }
        static dd normalized(double s, double e) {
            const double h = s + e;
            return {h, e - (h - s)};
        }
        friend dd operator+(dd x, dd y) {
            const double s = x.h + y.h, v = s - x.h;
            const double e = (x.h - (s - v)) + (y.h - v); // two_sum: s + e = x.h + y.h exactly
            return normalized(s, e + x.l + y.l);
        }
        friend dd operator-(dd x) { return {-x.h, -x.l}; }
        friend dd operator*(dd x, dd y) {
            const double p = x.h * y.h;
            const double e = std::fma(x.h, y.h, -p); // two_prod: p + e = x.h y.h exactly
            return normalized(p, e + (x.h * y.l + x.l * y.h));
        }
    };

    /// Gaussian elimination with partial pivoting in long double, for the s × s system of
    /// make_starts. Plain loops: Eigen's LU and products in long double, instantiated in every
    /// translation unit that includes this header, cost each about 3 s of compile time.
    struct small_lu {
        using matrix_ld = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
        matrix_ld lu;
        std::vector<Eigen::Index> row; // row[i]: the row of the original system in place i

        explicit small_lu(matrix_ld a)
            : lu(std::move(a)), row(static_cast<std::size_t>(lu.rows())) {
            const Eigen::Index n = lu.rows();
            for (Eigen::Index i = 0; i < n; ++i)
                row[static_cast<std::size_t>(i)] = i;
            for (Eigen::Index k = 0; k < n; ++k) {
                Eigen::Index p = k;
                for (Eigen::Index i = k + 1; i < n; ++i)
                    if (std::abs(lu(i, k)) > std::abs(lu(p, k))) p = i;
                if (p != k) {
                    for (Eigen::Index j = 0; j < n; ++j)
                        std::swap(lu(k, j), lu(p, j));
                    std::swap(row[static_cast<std::size_t>(k)], row[static_cast<std::size_t>(p)]);
                }
                for (Eigen::Index i = k + 1; i < n; ++i) {
                    lu(i, k) /= lu(k, k);
                    for (Eigen::Index j = k + 1; j < n; ++j)
                        lu(i, j) -= lu(i, k) * lu(k, j);
                }
            }
        }
        [[nodiscard]] matrix_ld solve(const matrix_ld& b) const {
            const Eigen::Index n = lu.rows();
            matrix_ld x(n, b.cols());
            for (Eigen::Index c = 0; c < b.cols(); ++c) {
                for (Eigen::Index i = 0; i < n; ++i) { // L y = P b
                    long double v = b(row[static_cast<std::size_t>(i)], c);
                    for (Eigen::Index j = 0; j < i; ++j)
                        v -= lu(i, j) * x(j, c);
                    x(i, c) = v;
                }
                for (Eigen::Index i = n - 1; i >= 0; --i) { // U x = y
                    long double v = x(i, c);
                    for (Eigen::Index j = i + 1; j < n; ++j)
                        v -= lu(i, j) * x(j, c);
                    x(i, c) = v / lu(i, i);
                }
            }
            return x;
        }
    };

    template <class LDMatrix, class LDWeights>
    void make_step_coefficients(const LDMatrix& a_ld, const LDMatrix& dphi_ld, const LDWeights& w) {
        const int s = degree;
        const auto r = static_cast<Eigen::Index>(w.size());
        std::vector<dd> a(static_cast<std::size_t>(s * s)), u(static_cast<std::size_t>(s * r)),
            g(static_cast<std::size_t>(s * r));
        const auto idx = [s](Eigen::Index i, Eigen::Index j) {
            return static_cast<std::size_t>(j * s + i);
        };
        for (int l = 1; l <= s; ++l) {
            dd column;
            for (int i = 1; i <= s; ++i)
                column = column + dd::of(a_ld(i, l));
            a[idx(0, l - 1)] = -column;
            for (int i = 1; i < s; ++i)
                a[idx(i, l - 1)] = dd::of(a_ld(i, l));
        }
        weights_lo.resize(static_cast<std::size_t>(r));
        for (Eigen::Index k = 0; k < r; ++k) {
            const dd wk = dd::of(w[k]);
            dd value{1.0, 0.0}, slope;
            for (int l = 1; l <= s; ++l) {
                value = value + -dd{phi(l, k), 0.0};    // ℓ_l(c_k) as the points use it
                slope = slope + -dd::of(dphi_ld(l, k)); // ℓ_l'(c_k) as dphi + dphi_lo holds it
            }
            u[idx(0, k)] = wk * value;
            g[idx(0, k)] = wk * slope;
            for (int i = 1; i < s; ++i) {
                u[idx(i, k)] = wk * dd{phi(i, k), 0.0};
                g[idx(i, k)] = wk * dd::of(dphi_ld(i, k));
            }
            weights_lo[static_cast<std::size_t>(k)] = wk.l;
        }
        auto split_of = [&](const std::vector<dd>& m, Eigen::Index cols) {
            split out{Eigen::MatrixXd(s, cols), Eigen::MatrixXd(s, cols)};
            for (Eigen::Index j = 0; j < cols; ++j)
                for (int i = 0; i < s; ++i) {
                    out.hi(i, j) = m[idx(i, j)].h;
                    out.lo(i, j) = m[idx(i, j)].l;
                }
            return out;
        };
        kinetic = split_of(a, s);
        wphi = split_of(u, r);
        wdphi = split_of(g, r);
    }

    template <class LDNodes>
    void make_starts(const LDNodes& c) {
        using LD = long double;
        using matrix_ld = Eigen::Matrix<LD, Eigen::Dynamic, Eigen::Dynamic>;
        const auto r = static_cast<Eigen::Index>(c.size());
        const int s = degree;
        const matrix_ld a = kinetic.hi.cast<LD>() + kinetic.lo.cast<LD>();
        matrix_ld rhs(s, r + 1); // [U, −e_0]: A [Kᵀ, c] = [U, −e_0]
        rhs.leftCols(r) = wphi.hi.cast<LD>() + wphi.lo.cast<LD>();
        rhs.col(r).setZero();
        rhs(0, r) = -1;
        const small_lu lu(a);
        const matrix_ld x0 = lu.solve(rhs);
        // The residual [U, −e_0] − A x0 in double-double (products of hi + lo values), then the
        // correction in long double: x = x0 + δ to ~1e-19 of δ.
        matrix_ld residual(s, r + 1);
        for (Eigen::Index j = 0; j <= r; ++j)
            for (int i = 0; i < s; ++i) {
                dd sum = j < r ? dd{wphi.hi(i, j), 0.0} + dd{wphi.lo(i, j), 0.0}
                               : dd{i == 0 ? -1.0 : 0.0, 0.0};
                for (int l = 0; l < s; ++l) {
                    const dd al = dd{kinetic.hi(i, l), 0.0} + dd{kinetic.lo(i, l), 0.0};
                    sum = sum + -(al * dd::of(x0(l, j)));
                }
                residual(i, j) = static_cast<LD>(sum.h) + static_cast<LD>(sum.l);
            }
        const matrix_ld delta = lu.solve(residual);
        sweep = {Eigen::MatrixXd(r, s), Eigen::MatrixXd(r, s)};
        flight = {Eigen::MatrixXd(1, s), Eigen::MatrixXd(1, s)};
        for (Eigen::Index j = 0; j <= r; ++j)
            for (int l = 0; l < s; ++l) {
                const dd x = dd::of(x0(l, j)) + dd::of(delta(l, j));
                (j < r ? sweep.hi(j, l) : flight.hi(0, l)) = x.h;
                (j < r ? sweep.lo(j, l) : flight.lo(0, l)) = x.l;
            }
        std::vector<LD> from;
        for (const LD ck : c)
            from.push_back(ck - 1);
        if (kind == rule_kind::gauss) from.push_back(0);
        const auto n = static_cast<Eigen::Index>(from.size());
        force_extrapolation.resize(n, r);
        for (Eigen::Index m = 0; m < n; ++m)
            for (Eigen::Index k = 0; k < r; ++k) {
                const auto at = [&](Eigen::Index i) { return from[static_cast<std::size_t>(i)]; };
                LD value = 1;
                for (Eigen::Index o = 0; o < n; ++o)
                    if (o != m) value *= (c[static_cast<std::size_t>(k)] - at(o)) / (at(m) - at(o));
                force_extrapolation(m, k) = static_cast<double>(value);
            }
    }

  public:
    /// A step's own polynomial of degree s through its control values, q(τ) = q_j + Σ_{l≥1}
    /// ℓ_l(τ) X_l (t = t_j + τh, τ ∈ [0, 1]), from q_j and the increments X (d × s): q(τ) and
    /// dq/dτ. The dense output of the family stepper and the general engine.
    template <class Q, class X>
    void polynomial(const Q& q_j, const X& x, double tau, Q& q, Q& dq) const {
        q = q_j;
        dq.setZero(q_j.size());
        for (int l = 1; l <= degree; ++l) {
            double value = 1.0, slope = 0.0;
            const double dl = control[static_cast<std::size_t>(l)];
            for (int m = 0; m <= degree; ++m) {
                if (m == l) continue;
                const double dm = control[static_cast<std::size_t>(m)], inv = 1.0 / (dl - dm);
                slope = slope * (tau - dm) * inv + value * inv; // product rule
                value *= (tau - dm) * inv;
            }
            q += value * x.col(l - 1);
            dq += slope * x.col(l - 1);
        }
    }
};

/// Number of quadrature points of a member: s + 1 for Lobatto, s for Gauss.
constexpr int points(rule_kind kind, int s) {
    return kind == rule_kind::lobatto ? s + 1 : s;
}

} // namespace varsym::galerkin
