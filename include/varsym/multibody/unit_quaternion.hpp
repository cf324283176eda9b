// varsym/multibody/unit_quaternion.hpp: the constraint |u| = 1 on a free base's quaternion, the
// coordinates 3 … 6 of a free_robot (floating.hpp), for the general engine's constrained stepper.
#pragma once

#include "varsym/systems/lagrangian_concepts.hpp"

namespace varsym::multibody {

/// The unit quaternion's constraint g = u·u − 1 on the coordinates 3 … 6 of a free_robot, with
/// its derivatives by hand (G = 2uᵀ there, Σ λ∇²g = 2λ on that block).
struct unit_quaternion {
    static constexpr int dim = dynamic, count = 1;
    int d = 7; ///< the robot's dimension

    template <class T>
    [[nodiscard]] tvec<T, 1> operator()(const tvec<T, dynamic>& q) const {
        tvec<T, 1> g;
        g(0) = q(3) * q(3) + q(4) * q(4) + q(5) * q(5) + q(6) * q(6) - 1.0;
        return g;
    }
    void jacobian(const vec<dynamic>& q, Eigen::Matrix<double, 1, dynamic>& g) const {
        g.setZero(1, d);
        g.middleCols<4>(3) = 2.0 * q.segment<4>(3).transpose();
    }
    void curvature(const vec<dynamic>&, const vec<1>& lambda, mat<dynamic>& h) const {
        h.setZero(d, d);
        h.block<4, 4>(3, 3).diagonal().setConstant(2.0 * lambda(0));
    }
};

} // namespace varsym::multibody
