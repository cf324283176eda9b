// varsym/lie/lgvi.hpp: the Lie group variational integrator of a rigid body (Lee, Leok &
// McClamroch 2005), order 2, and its symmetric compositions of orders 4 and 6.
//
// The discrete Lagrangian of a step of size τ from R_k to R_{k+1} = R_k F_k, F_k ∈ SO(3), is
//   L_d = (1/τ) tr[(I − F_k) J_d] − (τ/2) (U(R_k) + U(R_{k+1})),  J_d = ½ tr(J) I − J,     (R3)
// and its discrete Euler–Poincaré equations, with μ_k = Π_k + (τ/2) M_k (docs/rigid_bodies.md),
//   vee(F_k J_d − J_d F_kᵀ) = τ μ_k,                                                     (R4)
//   R_{k+1} = R_k F_k,   Π_{k+1} = F_kᵀ μ_k + (τ/2) M_{k+1}.                              (R5)
// In the Cayley chart F = cay(f), (R4) reads 2 (J f + f × J f) = τ μ (1 + fᵀf)              (R6)
// and is solved by Newton's method for f ∈ ℝ³ with its exact 3×3 Jacobian. R stays on SO(3)
// with no projection: cay(f) is orthogonal for every f, and R and Π are advanced by their
// increments R G and Gᵀμ + (τ/2)(M_k + M_{k+1}) (G = F − I) in extended precision.
#pragma once

#include <algorithm>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>

#include "varsym/lie/rigid_body.hpp"
#include "varsym/solvers/newton.hpp"

namespace varsym::lie {

/// The step sizes, as fractions of h, of the symmetric composition of order `order` (2, 4, 6)
/// of the order-2 map: order 4 is Yoshida's triple jump (Yoshida 1990; Hairer, Lubich & Wanner,
/// Geometric Numerical Integration, 2nd ed., §V.3.2, eq. (3.5)); order 6 is Kahan & Li's
/// 9-stage composition (Kahan & Li 1997; HLW §V.3.2, eq. (3.11)).
inline std::span<const double> composition_steps(int order) {
    static const double cbrt2 = std::cbrt(2.0);
    static const double g4 = 1.0 / (2.0 - cbrt2);
    static const double order2[] = {1.0};
    static const double order4[] = {g4, -cbrt2 * g4, g4};
    static constexpr double a = 0.39216144400731413927925056, b = 0.33259913678935943859974864,
                            c = -0.70624617255763935980996482, d = 0.08221359629355080023149045,
                            e = 0.79854399093482996339895035;
    static constexpr double order6[] = {a, b, c, d, e, d, c, b, a};
    switch (order) {
    case 2:
        return order2;
    case 4:
        return order4;
    case 6:
        return order6;
    default:
        throw std::invalid_argument("the rigid-body integrator has order 2, 4 or 6, not " +
                                    std::to_string(order));
    }
}

/// One-step map of a rigid body: the order-2 LGVI (R3)–(R6), composed to order 4 or 6.
/// Deterministic in (R, Π, carries): a checkpointed run resumes bit for bit. (A template only so
/// that a file which includes this header without using it compiles none of it: use `lgvi`.)
template <int Unused = 0>
class basic_lgvi {
  public:
    basic_lgvi(const rigid_body& body, double h, int order = 2, newton_options opt = {})
        : body_(body), h_(h), order_(order), steps_(composition_steps(order)), opt_(opt) {
        if (!(std::isfinite(h) && h > 0.0))
            throw std::invalid_argument("the time step must be finite and positive");
    }

    /// The largest h|Ω| at which the step equation (R4) has a solution for a body turning about
    /// a principal axis k: there vee(F J_d − J_d Fᵀ) = I_k sin α for a turn α, so (R4) needs
    /// τ|Ω| = sin α ≤ 1 in every sub-step τ = γh: h|Ω| ≤ 1/max|γ| (1, 0.59, 1.25 for orders
    /// 2, 4, 6). A guide for other motions, not a bound.
    static double step_limit(int order) {
        double g = 0.0;
        for (double gamma : composition_steps(order))
            g = std::max(g, std::abs(gamma));
        return 1.0 / g;
    }

    [[nodiscard]] double step_size() const { return h_; }
    [[nodiscard]] int order() const { return order_; }
    [[nodiscard]] const rigid_body& body() const { return body_; }

    /// Advances x by h. On failure (Newton did not converge in a sub-step) x is unchanged and
    /// the report says so; `iterations` counts the linear solves of all sub-steps.
    newton_report step(body_state& x) {
        if (!valid_ || x.R != last_.R || x.pi != last_.pi) { // x was set from outside
            low_r_.setZero();
            low_pi_.setZero();
        }
        // R and Π in extended precision: the double and its low-order part.
        wide_state y{x.R.cast<wide>() + low_r_.cast<wide>(),
                     x.pi.cast<wide>() + low_pi_.cast<wide>()};
        newton_report total;
        for (double gamma : steps_) {
            const newton_report rep = substep(gamma * h_, y);
            total.iterations += rep.iterations;
            total.residual = std::max(total.residual, rep.residual);
            if (!rep.converged) {
                total.residual = rep.residual;
                return total;
            }
        }
        total.converged = true;
        x.R = y.R.template cast<double>();
        x.pi = y.pi.template cast<double>();
        low_r_ = (y.R - x.R.template cast<wide>()).template cast<double>();
        low_pi_ = (y.pi - x.pi.template cast<wide>()).template cast<double>();
        last_ = x;
        valid_ = true;
        return total;
    }

    /// The low-order parts of R and Π that the doubles in the state do not hold (what a
    /// checkpoint keeps with the state).
    [[nodiscard]] const mat3& carry_R() const { return low_r_; }
    [[nodiscard]] const vec3& carry_pi() const { return low_pi_; }
    /// Continues from x with these low parts: the next step is the one the saved run would take.
    void restore(const body_state& x, const mat3& carry_r, const vec3& carry_pi) {
        last_ = x;
        low_r_ = carry_r;
        low_pi_ = carry_pi;
        valid_ = true;
    }

  private:
    /// The precision R and Π are accumulated in (x87 extended on x86-64 Linux, 64-bit mantissa;
    /// quad precision on AArch64 Linux): their per-step rounding is then ~2⁻⁶⁴ |G|, so that
    /// ‖RᵀR − I‖ and the momenta stay at the round-off of the last conversion to double.
    using wide = long double;
    using wmat3 = Eigen::Matrix<wide, 3, 3>;
    using wvec3 = Eigen::Matrix<wide, 3, 1>;
    struct wide_state {
        wmat3 R;
        wvec3 pi;
    };

    /// One step of the order-2 map with step size τ.
    newton_report substep(double tau, wide_state& x) const {
        const mat3& j = body_.inertia();
        const mat3 r_k = x.R.template cast<double>();
        const vec3 m0 = body_.moment(r_k);
        const wvec3 mu_w = x.pi + wide(0.5 * tau) * m0.template cast<wide>(); // μ_k (R4)
        const vec3 mu = mu_w.template cast<double>();
        vec3 f = 0.5 * tau * body_.omega(mu); // the linearised (R6): 2 J f = τ μ
        newton_report rep;
        double previous = std::numeric_limits<double>::infinity();
        for (rep.iterations = 1; rep.iterations <= opt_.max_iterations; ++rep.iterations) {
            const vec3 jf = j * f;
            const vec3 r = 2.0 * (jf + f.cross(jf)) - tau * (1.0 + f.squaredNorm()) * mu; // (R6)
            const mat3 dr =
                2.0 * (j + so3::hat(f) * j - so3::hat(jf)) - 2.0 * tau * mu * f.transpose();
            rep.residual = r.lpNorm<Eigen::Infinity>();
            const vec3 delta = dr.partialPivLu().solve(r);
            const double step = delta.lpNorm<Eigen::Infinity>();
            if (!std::isfinite(step) || !std::isfinite(rep.residual)) return rep;
            f -= delta;
            // Converged when the update is below tolerance relative to f, or has stopped
            // decreasing at round-off. Not on a predicted next update: stopping one update short
            // leaves an error of one sign step after step, and Π₃ of the symmetric top drifts.
            const double size = f.lpNorm<Eigen::Infinity>();
            const double eps = std::numeric_limits<double>::epsilon();
            if (step <= opt_.tolerance * size ||
                (step >= 0.5 * previous && step <= 64.0 * eps * size)) {
                rep.converged = true;
                break;
            }
            previous = step;
        }
        if (!rep.converged) {
            rep.iterations = opt_.max_iterations;
            return rep;
        }
        // F_k = I + G in extended precision (orthogonal to its round-off for every f).
        const wmat3 g = so3::cayley_increment<wide>(f.cast<wide>());
        x.R += x.R * g; // R_{k+1} = R_k F_k                                              (R5)
        const vec3 m1 = body_.moment(x.R.template cast<double>());
        x.pi += g.transpose() * mu_w +
                wide(0.5 * tau) * (m0 + m1).template cast<wide>(); // Π_{k+1} (R5)
        return rep;
    }

    rigid_body body_;
    double h_;
    int order_;
    std::span<const double> steps_;
    newton_options opt_;
    mat3 low_r_ = mat3::Zero();
    vec3 low_pi_ = vec3::Zero();
    body_state last_;
    bool valid_ = false;
};

using lgvi = basic_lgvi<>;

} // namespace varsym::lie
