// tests/schemes/nbody.hpp: a gravitational N-body system in three dimensions (G = 1), d = 3B for
// B bodies, with d fixed at compile time or known only at run time: the large-d system of the
// dimension tests. Potential, gradient and Hessian by hand; the same Lagrangian templated on the
// scalar for automatic derivatives.
#pragma once

#include <cmath>
#include <vector>

#include "varsym/systems/lagrangian.hpp"
#include "varsym/systems/separable.hpp"

namespace varsym::test {

/// V(q) = −Σ_{i<j} m_i m_j / |q_i − q_j|, q_i the i-th body's 3 coordinates.
/// `field` adds a uniform external field, V += Σ_i m_i field·q_i, which breaks the translation
/// symmetry (the negative control of the momentum tests).
template <int D>
struct gravity {
    std::vector<double> m;
    Eigen::Vector3d field = Eigen::Vector3d::Zero();

    [[nodiscard]] int bodies() const { return static_cast<int>(m.size()); }
    [[nodiscard]] double value(const vec<D>& q) const {
        double v = 0.0;
        for (int i = 0; i < bodies(); ++i)
            for (int j = i + 1; j < bodies(); ++j)
                v -= m[i] * m[j] /
                     (q.template segment<3>(3 * i) - q.template segment<3>(3 * j)).norm();
        for (int i = 0; i < bodies(); ++i)
            v += m[i] * field.dot(q.template segment<3>(3 * i));
        return v;
    }
    [[nodiscard]] vec<D> gradient(const vec<D>& q) const {
        vec<D> g = vec<D>::Zero(q.size());
        for (int i = 0; i < bodies(); ++i)
            for (int j = i + 1; j < bodies(); ++j) {
                const Eigen::Vector3d r =
                    q.template segment<3>(3 * i) - q.template segment<3>(3 * j);
                const double n = r.norm();
                const Eigen::Vector3d f = (m[i] * m[j] / (n * n * n)) * r;
                g.template segment<3>(3 * i) += f;
                g.template segment<3>(3 * j) -= f;
            }
        for (int i = 0; i < bodies(); ++i)
            g.template segment<3>(3 * i) += m[i] * field;
        return g;
    }
    [[nodiscard]] mat<D> hessian(const vec<D>& q) const {
        mat<D> h = mat<D>::Zero(q.size(), q.size());
        for (int i = 0; i < bodies(); ++i)
            for (int j = i + 1; j < bodies(); ++j) {
                const Eigen::Vector3d r =
                    q.template segment<3>(3 * i) - q.template segment<3>(3 * j);
                const double n = r.norm(), c = m[i] * m[j] / (n * n * n);
                // ∇²_r of −c₀/|r|: c₀ (I/|r|³ − 3 r rᵀ/|r|⁵)
                const Eigen::Matrix3d k =
                    c * (Eigen::Matrix3d::Identity() - (3.0 / (n * n)) * r * r.transpose());
                h.template block<3, 3>(3 * i, 3 * i) += k;
                h.template block<3, 3>(3 * j, 3 * j) += k;
                h.template block<3, 3>(3 * i, 3 * j) -= k;
                h.template block<3, 3>(3 * j, 3 * i) -= k;
            }
        return h;
    }
};

/// The same system as a Lagrangian for automatic derivatives (D fixed).
template <int D>
struct gravity_lagrangian {
    static constexpr int dim = D;
    std::vector<double> m;

    template <class T>
    T operator()(const tvec<T, D>& q, const tvec<T, D>& v) const {
        using std::sqrt;
        T l(0.0);
        for (int i = 0; i < D; ++i)
            l += (0.5 * m[i / 3]) * v(i) * v(i);
        for (int i = 0; i < D / 3; ++i)
            for (int j = i + 1; j < D / 3; ++j) {
                const T dx = q(3 * i) - q(3 * j), dy = q(3 * i + 1) - q(3 * j + 1),
                        dz = q(3 * i + 2) - q(3 * j + 2);
                l += (m[i] * m[j]) / sqrt(dx * dx + dy * dy + dz * dz);
            }
        return l;
    }
};

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
