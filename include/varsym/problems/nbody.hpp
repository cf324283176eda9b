// varsym/problems/nbody.hpp: the gravitational N-body problem in three dimensions, d = 3B for
// B bodies, with d fixed at compile time or known only at run time.
//
// Units and conventions: q = (q_1, …, q_B) with q_i ∈ R³ the i-th body's position, masses m_i,
// p_i = m_i q̇_i; any consistent units (G given in them; problems/solar_system.hpp uses AU, days
// and solar masses). The energy, the total momentum Σ p_i and the angular momentum Σ q_i × p_i
// are conserved (without an external field).
#pragma once

#include <cmath>
#include <vector>

#include "varsym/systems/lagrangian.hpp"
#include "varsym/systems/separable.hpp"

namespace varsym::nbody {

/// V(q) = −G Σ_{i<j} m_i m_j / |q_i − q_j|, q_i the i-th body's 3 coordinates (d = 3B; D may
/// be `dynamic`). `field` adds a uniform external field, V += Σ_i m_i field·q_i, which breaks
/// the translation symmetry. Value, gradient and Hessian by hand.
template <int D>
struct gravity {
    std::vector<double> m;
    Eigen::Vector3d field = Eigen::Vector3d::Zero();
    double G = 1.0;

    [[nodiscard]] int bodies() const { return static_cast<int>(m.size()); }
    [[nodiscard]] double value(const vec<D>& q) const {
        double v = 0.0;
        for (int i = 0; i < bodies(); ++i)
            for (int j = i + 1; j < bodies(); ++j)
                v -= G * m[i] * m[j] /
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
                const Eigen::Vector3d f = (G * m[i] * m[j] / (n * n * n)) * r;
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
                const double n = r.norm(), c = G * m[i] * m[j] / (n * n * n);
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

/// The same system as a Lagrangian L = ½ Σ m_i |q̇_i|² − V(q) for automatic derivatives
/// (D fixed; no external field).
template <int D>
struct gravity_lagrangian {
    static constexpr int dim = D;
    std::vector<double> m;
    double G = 1.0;

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
                l += (G * m[i] * m[j]) / sqrt(dx * dx + dy * dy + dz * dz);
            }
        return l;
    }
};

} // namespace varsym::nbody
