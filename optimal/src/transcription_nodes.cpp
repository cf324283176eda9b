// optimal/src/transcription_nodes.cpp: the node velocities of the DMOC transcription
// (transcription.hpp), unknowns where velocity bounds are given (and no holonomic constraints):
// at each node between steps, n = 1 … N−1, the velocity V_n with p_n = ∂L/∂q̇(Q_{ns}, V_n) the
// node's momentum, within the bounds (the unknowns' own, so exactly). The node's equation, step
// n−1's end contribution plus step n's start contribution, is split at p_n:
//   E⁻_n = (step n−1's terms) − ∂L/∂q̇(Q_{ns}, V_n) = 0   (the node's row),
//   E⁺_n = (step n's terms)   + ∂L/∂q̇(Q_{ns}, V_n) = 0   (split_row(n)),
// whose sum is the original equation; V_n is the velocity the discrete Legendre transform gives
// at the node (unpack's). Nothing without node velocities.
#include "varsym/optimize/transcription.hpp"

namespace varsym::optimal {

void dmoc_transcription::add_node_residual(cvector x, vector& e) const {
    lagrangian_terms<dynamic> lt;
    const double h = h_of(x);
    for (int n = 1; nodes_ && n < n_; ++n) {
        sys_->gradient(x.segment(n * s_ * d_, d_), x.segment(node_velocity_index(n), d_), n * h,
                       lt);
        e.segment(n * s_ * d_, d_) -= lt.lv;
        e.segment(split_row(n), d_) += lt.lv;
    }
}

/// Rows E⁻_n and E⁺_n against (Q_{ns}, V_n): ∓ (∂²L/∂q̇∂q, ∂²L/∂q̇²).
void dmoc_transcription::add_node_jacobian(cvector x, sparsity* pattern,
                                           std::vector<double>* values) const {
    lagrangian_terms<dynamic> lt;
    const double h = values ? h_of(x) : 1.0;
    for (int n = 1; nodes_ && n < n_; ++n) {
        if (values)
            sys_->derivatives(x.segment(n * s_ * d_, d_), x.segment(node_velocity_index(n), d_),
                              n * h, lt);
        for (const double sign : {-1.0, 1.0}) {
            const int base = sign < 0 ? n * s_ * d_ : split_row(n);
            for (int row = 0; row < d_; ++row)
                for (int col = 0; col < 2 * d_; ++col) {
                    const int unknown =
                        col < d_ ? n * s_ * d_ + col : node_velocity_index(n) + col - d_;
                    pattern ? pattern->add(base + row, unknown)
                            : values->push_back(
                                  sign * (col < d_ ? lt.lqv(col, row) : lt.lvv(row, col - d_)));
                }
        }
    }
}

/// The lower triangle over (Q_{ns}, V_n) of (λ⁺ − λ⁻)ᵀ ∂L/∂q̇(Q_{ns}, V_n): L's third
/// derivatives contracted, as at a free end.
void dmoc_transcription::add_node_hessian(cvector x, cvector lambda, sparsity* pattern,
                                          std::vector<double>* values) const {
    matrix he;
    const double h = values ? h_of(x) : 1.0;
    for (int n = 1; nodes_ && n < n_; ++n) {
        const auto index = [&](int i) {
            return i < d_ ? n * s_ * d_ + i : node_velocity_index(n) + i - d_;
        };
        if (values)
            sys_->third(x.segment(n * s_ * d_, d_), x.segment(node_velocity_index(n), d_), n * h,
                        vector::Zero(d_),
                        vector(lambda.segment(split_row(n), d_) - lambda.segment(n * s_ * d_, d_)),
                        he);
        for (int row = 0; row < 2 * d_; ++row)
            for (int col = 0; col <= row; ++col)
                pattern ? pattern->add(index(row), index(col)) : values->push_back(he(row, col));
    }
}

} // namespace varsym::optimal
