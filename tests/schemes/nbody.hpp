// tests/schemes/nbody.hpp: the gravitational N-body system of the library (problems/nbody.hpp,
// G = 1) with a small planetary system to start from: the large-d system of the dimension tests.
#pragma once

#include <cmath>
#include <vector>

#include "varsym/problems/nbody.hpp"

namespace varsym::test {

template <int D>
using gravity = nbody::gravity<D>;
template <int D>
using gravity_lagrangian = nbody::gravity_lagrangian<D>;

/// A central body of mass 1 and B − 1 bodies of masses 1e-3/k on slightly inclined, nearly
/// circular orbits of radii 5(k + 1): a small planetary system, total momentum zero.
struct planetary_start {
    std::vector<double> masses;
    Eigen::VectorXd q, p;
    explicit planetary_start(int bodies) : masses(bodies), q(3 * bodies), p(3 * bodies) {
        masses[0] = 1.0;
        q.setZero();
        p.setZero();
        for (int k = 1; k < bodies; ++k) {
            masses[k] = 1e-3 / k;
            const double r = 5.0 * (k + 1), angle = 2.4 * k, tilt = 0.02 * k;
            const double speed = std::sqrt(1.0 / r);
            q.segment<3>(3 * k) << r * std::cos(angle), r * std::sin(angle), r * tilt * 0.1;
            p.segment<3>(3 * k) << -masses[k] * speed * std::sin(angle),
                masses[k] * speed * std::cos(angle), masses[k] * speed * tilt;
            p.segment<3>(0) -= p.segment<3>(3 * k);
        }
    }
    [[nodiscard]] Eigen::VectorXd mass_diagonal() const {
        Eigen::VectorXd d(q.size());
        for (Eigen::Index i = 0; i < d.size(); ++i)
            d(i) = masses[i / 3];
        return d;
    }
};

/// Total linear momentum Σ p_i and angular momentum Σ q_i × p_i.
template <class V>
Eigen::Vector3d total_momentum(const V& p) {
    Eigen::Vector3d s = Eigen::Vector3d::Zero();
    for (Eigen::Index i = 0; i < p.size() / 3; ++i)
        s += p.template segment<3>(3 * i);
    return s;
}
template <class V>
Eigen::Vector3d angular_momentum(const V& q, const V& p) {
    Eigen::Vector3d s = Eigen::Vector3d::Zero();
    for (Eigen::Index i = 0; i < q.size() / 3; ++i)
        s += Eigen::Vector3d(q.template segment<3>(3 * i))
                 .cross(Eigen::Vector3d(p.template segment<3>(3 * i)));
    return s;
}

} // namespace varsym::test
