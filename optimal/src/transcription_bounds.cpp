// optimal/src/transcription_bounds.cpp: bounds on the steps' polynomials in the DMOC
// transcription (transcription.hpp), rows g_lower ≤ g ≤ g_upper after the end target's:
// - q̇(τ) = Σ_l ℓ_l'(τ) Q_{ks+l} / h within control_problem::velocity_lower, velocity_upper at
//   each step's interior quadrature points, and at its ends (τ = 0, 1) where the node velocities
//   are not unknowns of their own (with constraints; transcription_nodes.cpp);
// - q(τ) = Σ_l ℓ_l(τ) Q_{ks+l} within the position bounds at the quadrature points that are not
//   control values (gauss-s; at the control values the bounds are the unknowns' own).
// Linear in the control values at a fixed horizon (no Hessian); with a free horizon the
// velocity rows have ∂g/∂T = −g/T. Nothing without bounds.
#include <cmath>

#include "varsym/optimize/transcription.hpp"

namespace varsym::optimal {

namespace {

/// ℓ_i(τ) (or ℓ_i'(τ) if `slope`) of the control nodes, (s + 1) × points.
matrix lagrange_at(const std::vector<double>& nodes, const std::vector<double>& at, bool slope) {
    const auto s = static_cast<int>(nodes.size()) - 1;
    matrix out(s + 1, std::ssize(at));
    for (int i = 0; i <= s; ++i)
        for (std::size_t e = 0; e < at.size(); ++e) {
            double value = 1.0, derivative = 0.0; // by the product rule
            for (int m = 0; m <= s; ++m) {
                if (m == i) continue;
                const auto mi = static_cast<std::size_t>(m), ii = static_cast<std::size_t>(i);
                const double inv = 1.0 / (nodes[ii] - nodes[mi]), x = at[e] - nodes[mi];
                derivative = derivative * x * inv + value * inv;
                value *= x * inv;
            }
            out(i, static_cast<Eigen::Index>(e)) = slope ? derivative : value;
        }
    return out;
}

std::vector<int> bounded(const vector& lower, const vector& upper) {
    std::vector<int> out;
    for (Eigen::Index i = 0; i < lower.size(); ++i)
        if (std::isfinite(lower(i)) || std::isfinite(upper(i))) out.push_back(static_cast<int>(i));
    return out;
}

} // namespace

void dmoc_transcription::setup_path_bounds() {
    const auto near = [](double a, double b) { return std::abs(a - b) < 1e-12; };
    std::vector<double> inner; // quadrature nodes that are not control values
    for (const double c : tab_.quad.nodes) {
        bool control = false;
        for (const double d : tab_.control)
            control = control || near(c, d);
        if (!control) inner.push_back(c);
    }
    path_bounds_[0] = {false, bounded(p_.position_lower, p_.position_upper),
                       lagrange_at(tab_.control, inner, false)};
    // q̇ at 0, the quadrature nodes and 1 (a Lobatto rule's ends once); with node velocities
    // (transcription_nodes.cpp), which bound q̇ at the nodes exactly, at the interior ones only.
    std::vector<double> at;
    if (!nodes_) at.push_back(0.0);
    for (const double c : tab_.quad.nodes)
        if (!near(c, 0.0) && !near(c, 1.0)) at.push_back(c);
    if (!nodes_) at.push_back(1.0);
    path_bounds_[1] = {true, bounded(p_.velocity_lower, p_.velocity_upper),
                       lagrange_at(tab_.control, at, true)};
}

void dmoc_transcription::constraint_bounds(vector& lower, vector& upper) const {
    lower = upper = vector::Zero(constraints());
    int row = path_row();
    for (const path_bound& b : path_bounds_) {
        const vector &lo = b.velocity ? p_.velocity_lower : p_.position_lower,
                     &hi = b.velocity ? p_.velocity_upper : p_.position_upper;
        for (int k = 0; k < n_; ++k)
            for (Eigen::Index e = 0; e < b.weights.cols(); ++e)
                for (const int i : b.coordinates) {
                    lower(row) = lo(i);
                    upper(row++) = hi(i);
                }
    }
}

void dmoc_transcription::add_path_residual(cvector x, vector& e) const {
    const double h = h_of(x);
    int row = path_row();
    for (const path_bound& b : path_bounds_)
        for (int k = 0; k < n_; ++k)
            for (Eigen::Index at = 0; at < b.weights.cols(); ++at)
                for (const int i : b.coordinates) {
                    double v = 0.0;
                    for (int l = 0; l <= s_; ++l)
                        v += b.weights(l, at) * x((k * s_ + l) * d_ + i);
                    e(row++) = b.velocity ? v / h : v;
                }
}

/// Each row against its step's s + 1 control values of its coordinate; with a free horizon the
/// velocity rows' entries in the T column (jacobian_pattern's, already there) are −g/T.
void dmoc_transcription::add_path_jacobian(cvector x, sparsity* pattern,
                                           std::vector<double>* values) const {
    const double h = values ? h_of(x) : 1.0;
    vector e;
    if (values && p_.free_time) {
        e.setZero(constraints());
        add_path_residual(x, e);
    }
    const std::size_t blocks = step_jacobian_size();
    int row = path_row();
    for (const path_bound& b : path_bounds_)
        for (int k = 0; k < n_; ++k)
            for (Eigen::Index at = 0; at < b.weights.cols(); ++at)
                for (const int i : b.coordinates) {
                    for (int l = 0; l <= s_; ++l)
                        pattern ? pattern->add(row, (k * s_ + l) * d_ + i)
                                : values->push_back(b.weights(l, at) / (b.velocity ? h : 1.0));
                    if (values && p_.free_time && b.velocity)
                        (*values)[blocks + static_cast<std::size_t>(row)] = -e(row) / (n_ * h);
                    ++row;
                }
}

} // namespace varsym::optimal
