// optimal/src/transcription_structure.cpp: which entries of a step's blocks of the DMOC
// transcription's Jacobian and Hessian (transcription.hpp) can be non-zero. IPOPT factors the
// KKT matrix over the patterns it is given: every structural zero left in is a zero that
// MUMPS stores, eliminates and fills in from. A step's controls u_kj enter only through the
// force and the running cost at their own quadrature point j, so
//   - ∂E_i/∂u_kj = h w_j ℓ_i(c_j) ∂f/∂u: none where ℓ_i(c_j) = 0 (a Lobatto rule's control
//     values are its quadrature points: ℓ_i(c_j) = δ_ij exactly, tableau.hpp), and only B's
//     non-zeros where f = f₀ + B u (controlled_system::constant_input_matrix);
//   - the Hessian has no (u_kj, u_kj') entry for j ≠ j'; with f = f₀ + B u and a running cost of
//     the effort ½ uᵀRu alone, none between u_kj and the control values (f is linear in u, and
//     the effort depends on u only), and in (u_kj, u_kj) only R's non-zeros.
// The power and invariant costs, and a force of any other form, keep the blocks dense.
#include "varsym/optimize/transcription.hpp"

namespace varsym::optimal {

void dmoc_transcription::setup_structure() {
    const matrix* b = sys_->constant_input_matrix();
    const int wq = (s_ + 1) * d_, w = wq + r_ * m_;
    control_jacobian_.clear();
    for (int row = 0; row < wq; ++row)
        for (int col = 0; col < r_ * m_; ++col) {
            const int i = row / d_, j = col / m_;
            if (tab_.phi(i, j) == 0.0) continue;
            if (b != nullptr && (*b)(row % d_, col % m_) == 0.0) continue;
            control_jacobian_.emplace_back(row, col);
        }
    // The controls' Hessian: dense blocks unless f = f₀ + B u and the cost is the effort alone.
    const bool linear = b != nullptr && p_.cost.power == 0.0 && p_.cost.invariant == 0.0;
    step_hessian_.clear();
    for (int row = 0; row < w; ++row)
        for (int col = 0; col <= row; ++col) {
            if (row >= wq) {
                const int a = (row - wq) % m_, j = (row - wq) / m_;
                if (col < wq) { // (u_kj, Q_l): the force's and the cost's coupling
                    if (linear) continue;
                } else {
                    const int c = (col - wq) % m_, jc = (col - wq) / m_;
                    if (jc != j) continue; // two quadrature points never meet
                    if (linear && (p_.cost.effort == 0.0 || p_.effort(a, c) == 0.0)) continue;
                }
            }
            step_hessian_.emplace_back(row, col);
        }
}

} // namespace varsym::optimal
