// optimal/src/transcription_velocity.cpp: velocity bounds in the DMOC transcription
// (transcription.hpp; control_problem::velocity_lower, velocity_upper): q̇ of each step's
// polynomial, q̇(τ) = Σ_l ℓ_l'(τ) Q_{ks+l} / h, within its bounds at the step's ends (τ = 0, 1)
// and at its quadrature points: rows g_lower ≤ g ≤ g_upper after the end target's, linear in the
// control values at a fixed horizon (no Hessian); with a free horizon ∂g/∂T = −g/T. A URDF's
// <limit velocity> (models/src/robot.cpp). Nothing without bounds.
#include <cmath>

#include "varsym/optimal/transcription.hpp"

namespace varsym::optimal {

void dmoc_transcription::setup_velocity_bounds() {
    limited_.clear();
    for (int i = 0; i < d_; ++i)
        if (std::isfinite(p_.velocity_lower(i)) || std::isfinite(p_.velocity_upper(i)))
            limited_.push_back(i);
    // The evaluation points: 0, the quadrature nodes, 1 (a Lobatto rule's ends counted once).
    std::vector<double> at{0.0};
    for (const double c : tab_.quad.nodes)
        if (c > 1e-12 && c < 1.0 - 1e-12) at.push_back(c);
    at.push_back(1.0);
    velocity_weights_.setZero(s_ + 1, std::ssize(at));
    for (int i = 0; i <= s_; ++i)
        for (std::size_t e = 0; e < at.size(); ++e) {
            double value = 1.0, slope = 0.0; // ℓ_i and ℓ_i' at τ by the product rule
            for (int m = 0; m <= s_; ++m) {
                if (m == i) continue;
                const double inv = 1.0 / (tab_.control[static_cast<std::size_t>(i)] -
                                          tab_.control[static_cast<std::size_t>(m)]);
                const double x = at[e] - tab_.control[static_cast<std::size_t>(m)];
                slope = slope * x * inv + value * inv;
                value *= x * inv;
            }
            velocity_weights_(i, static_cast<Eigen::Index>(e)) = slope;
        }
}

void dmoc_transcription::constraint_bounds(vector& lower, vector& upper) const {
    lower = upper = vector::Zero(constraints());
    const auto points = velocity_weights_.cols();
    int row = velocity_row();
    for (int k = 0; k < n_; ++k)
        for (Eigen::Index e = 0; e < points; ++e)
            for (const int i : limited_) {
                lower(row) = p_.velocity_lower(i);
                upper(row++) = p_.velocity_upper(i);
            }
}

void dmoc_transcription::add_velocity_residual(cvector x, vector& e) const {
    const double h = h_of(x);
    int row = velocity_row();
    for (int k = 0; k < n_; ++k)
        for (Eigen::Index at = 0; at < velocity_weights_.cols(); ++at)
            for (const int i : limited_) {
                double v = 0.0;
                for (int l = 0; l <= s_; ++l)
                    v += velocity_weights_(l, at) * x((k * s_ + l) * d_ + i);
                e(row++) = v / h;
            }
}

/// Each row against its step's s + 1 control values of its coordinate; with a free horizon the
/// rows' entries in the T column (jacobian_pattern's, already there) are −g/T.
void dmoc_transcription::add_velocity_jacobian(cvector x, sparsity* pattern,
                                               std::vector<double>* values) const {
    const double h = values ? h_of(x) : 1.0;
    int row = velocity_row();
    vector e;
    if (values && p_.free_time) {
        e.setZero(constraints());
        add_velocity_residual(x, e);
    }
    const int w = (s_ + 1) * d_;
    const std::size_t blocks =
        static_cast<std::size_t>(n_) * static_cast<std::size_t>(w * (w + r_ * m_));
    for (int k = 0; k < n_; ++k)
        for (Eigen::Index at = 0; at < velocity_weights_.cols(); ++at)
            for (const int i : limited_) {
                for (int l = 0; l <= s_; ++l)
                    pattern ? pattern->add(row, (k * s_ + l) * d_ + i)
                            : values->push_back(velocity_weights_(l, at) / h);
                if (values && p_.free_time)
                    (*values)[blocks + static_cast<std::size_t>(row)] = -e(row) / (n_ * h);
                ++row;
            }
}

} // namespace varsym::optimal
