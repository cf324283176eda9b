// varsym/schemes/tableau.hpp: the tables of one member of the variational family (rule × degree
// s): control nodes, quadrature, Lagrange basis values and slopes at the quadrature points, and
// the stiffness matrix A. Shared by the separable family (galerkin.hpp) and the general engine
// (variational.hpp). See docs/design.md, "The family".
#pragma once

#include <stdexcept>
#include <string>
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
        matrix_ld weights = matrix_ld::Zero(r, r);
        for (Eigen::Index k = 0; k < r; ++k)
            weights(k, k) = quad.weights[k];
        const matrix_ld stiffness = dphi * weights * dphi.transpose();

        tableau t;
        t.degree = s;
        t.kind = kind;
        t.control.assign(control.begin(), control.end());
        t.quad.nodes.assign(quad.nodes.begin(), quad.nodes.end());
        t.quad.weights.assign(quad.weights.begin(), quad.weights.end());
        t.phi = phi.cast<double>();
        t.dphi = dphi.cast<double>();
        t.stiffness = stiffness.cast<double>();
        return t;
    }
    [[nodiscard]] int order() const { return 2 * degree; }
};

/// Number of quadrature points of a member: s + 1 for Lobatto, s for Gauss.
constexpr int points(rule_kind kind, int s) {
    return kind == rule_kind::lobatto ? s + 1 : s;
}

} // namespace varsym::galerkin
