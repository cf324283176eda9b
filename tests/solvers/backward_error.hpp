// tests/solvers/backward_error.hpp: the normwise backward error of a computed solution, the
// measure the linear solvers' tests bound (Higham, Accuracy and Stability of Numerical
// Algorithms, 2nd ed., §7.1, Rigal and Gaches).
#pragma once

#include <Eigen/Dense>

namespace varsym::test {

/// ‖A x − b‖∞ / (‖A‖∞ ‖x‖∞ + ‖b‖∞): the smallest relative perturbation of A and b (in the
/// ∞-norm) of which x is the exact solution.
inline double backward_error(const Eigen::MatrixXd& a, const Eigen::VectorXd& x,
                             const Eigen::VectorXd& b) {
    const double norm_a = a.cwiseAbs().rowwise().sum().maxCoeff();
    return (a * x - b).lpNorm<Eigen::Infinity>() /
           (norm_a * x.lpNorm<Eigen::Infinity>() + b.lpNorm<Eigen::Infinity>());
}

} // namespace varsym::test
