// varsym/optimal/input_system.hpp: a Lagrangian L driven by inputs through a constant input
// matrix, with optional linear damping: f = B u − C q̇ (joint torques, a push, the inputs on named
// coordinates of a typed Lagrangian), as a controlled_system (system.hpp) for the one compiled
// transcription. L's first and second derivatives are its own (by hand, as a URDF robot's recursive
// ones and a typed Lagrangian's symbolic ones, or automatic for a C++ Lagrangian of fixed
// dimension, the ones its simulation already uses). The third derivatives the exact Hessian needs
// are exact too (lagrangian_part::third): the robot's dual numbers, the typed L's code run along
// a direction, nested AD for a C++ L of fixed dimension; only a C++ L of run-time dimension (the
// arm) takes a central difference of its exact second ones (controlled_system::third).
#pragma once

#include <memory>
#include <utility>

#include "varsym/optimal/transcription.hpp"
#include "varsym/systems/lagrangian.hpp"
#include "varsym/systems/lagrangian_time.hpp"

namespace varsym::optimal {

template <lagrangian L>
class input_system final : public lagrangian_part<L> {
  public:
    using lagrangian_part<L>::dimension;

    /// L, the input matrix B (d × m: column j is the generalized force of unit input j) and
    /// the damping C (d × d, symmetric positive semi-definite [N m s/rad, N s/m]; empty: none).
    input_system(L l, matrix b, matrix damping = {})
        : lagrangian_part<L>(std::move(l)), b_(std::move(b)), c_(std::move(damping)) {
        const int d = dimension();
        if (b_.b().rows() != d)
            throw std::invalid_argument("the input matrix has " + std::to_string(b_.b().rows()) +
                                        " rows; the system has " + std::to_string(d) +
                                        " coordinates");
        if (c_.size() != 0 && (c_.rows() != d || c_.cols() != d || !c_.allFinite()))
            throw std::invalid_argument("the damping matrix must be finite and d x d");
    }

    [[nodiscard]] int inputs() const override { return static_cast<int>(b_.b().cols()); }

    void force(const vector& q, const vector& v, double t, const vector& u, input_terms& out,
               bool jacobians) const override {
        (void)q, (void)t;
        b_.evaluate(u, out, jacobians);
        if (c_.size() == 0) return;
        out.f.noalias() -= c_ * v;
        if (jacobians) out.fv = -c_;
    }

  private:
    input_matrix b_;
    matrix c_;
};

/// The transcription of `problem` for L driven by f = B u − C q̇.
template <lagrangian L>
std::unique_ptr<dmoc_transcription> transcribe_inputs(L l, matrix b, const control_problem& problem,
                                                      matrix damping = {}) {
    return transcribe(
        std::make_shared<const input_system<L>>(std::move(l), std::move(b), std::move(damping)),
        problem);
}

} // namespace varsym::optimal
