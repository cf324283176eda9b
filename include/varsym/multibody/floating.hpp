// varsym/multibody/floating.hpp: a robot with a free-floating base (tree::with_base(free)) as a
// Lagrangian in coordinates where the symmetries of free flight act linearly, and the unit
// quaternion's constraint.
//
// Coordinates (dimension dof + 1 of the tree): the base's position x (base_x, base_y, base_z
// [m, world]), its orientation as a quaternion u = (w, v) (base_qw, base_qx, base_qy, base_qz),
// then the joints θ. With û = u/|u| and R(û) the rotation (world from base),
//   ω = W(u) u̇ = 2 Im(ū ⊗ u̇)/|u|²   (the base's angular velocity in its own frame),        (Q1)
//   L(x, u, θ, ẋ, u̇, θ̇) = L_tree(R(û), x; θ; ẋ, ω, θ̇) + ½ κ (u·u̇)²,                       (Q2)
// with holonomic constraint g(u) = u·u − 1 = 0 (schemes/constrained.hpp: RATTLE-type, every
// member of the family). The last term gives u̇'s radial direction, which moves nothing, a mass
// κ (4/3 of the trace of the root link's inertia): it vanishes on the constraint's velocities
// (u·u̇ = 0), and the mass matrix is regular.
//
// L_tree and its derivatives come from the recursive algorithms over the tree with its six
// virtual base joints (three prismatic along the world's axes, three revolute: R = C Rx Ry Rz),
// taken in a chart centred at the point of evaluation: C = R(û), the world's origin moved to x
// (so the spatial algebra keeps its precision far from the origin; L adds M g·x, the potential's
// part the move leaves out), the base's coordinates c = 0 and their rates ċ = (ẋ, ω). The chain
// rule through the chart's maps φ(u) (the XYZ angles of R(û₀)ᵀR(û)) and φ̇(u, u̇) = E(φ)⁻¹ W u̇
// gives L's derivatives in (x, u, θ); the maps' first and second derivatives at the point are
// taken by automatic differentiation (autodiff/second_order.hpp: 8 variables).
//
// Why a quaternion: world rotations act on (x, u) linearly (x ↦ Qx, u ↦ q_Q ⊗ u) and leave g
// and L (without gravity) invariant, so the Galerkin discrete Lagrangians are invariant and the
// discrete Noether theorem conserves the total angular momentum to round-off, as translations
// conserve the linear momentum; no Euler-angle singularity (docs/robots.md).
#pragma once

#include <cmath>
#include <memory>
#include <stdexcept>
#include <utility>

#include <Eigen/Geometry>

#include "varsym/autodiff/second_order.hpp"
#include "varsym/multibody/algorithms.hpp"
#include "varsym/systems/lagrangian.hpp"

namespace varsym::multibody {

/// The chart's maps at u (and u̇) about the unit quaternion u0 (Q2): φ, the XYZ angles of
/// R(u0)ᵀ R(û), and φ̇ = E(φ)⁻¹ W(u) u̇ (E: ω = E(φ) φ̇ for R = Rx Ry Rz(φ)). Any scalar T.
template <class T>
void chart_maps(const Eigen::Quaterniond& u0, const Eigen::Matrix<T, 4, 1>& u,
                const Eigen::Matrix<T, 4, 1>& ud, Eigen::Matrix<T, 3, 1>& phi,
                Eigen::Matrix<T, 3, 1>& phid) {
    using std::asin, std::atan2, std::cos, std::sin, std::sqrt;
    const T n2 = u.squaredNorm();
    const T n = sqrt(n2);
    // r = conj(u0) ⊗ û, (w, x, y, z).
    const T w = u(0) / n, x = u(1) / n, y = u(2) / n, z = u(3) / n;
    const double a = u0.w(), b = -u0.x(), c = -u0.y(), d = -u0.z();
    const T rw = a * w - b * x - c * y - d * z;
    const T rx = a * x + b * w + c * z - d * y;
    const T ry = a * y - b * z + c * w + d * x;
    const T rz = a * z + b * y - c * x + d * w;
    const T m02 = 2.0 * (rx * rz + rw * ry), m12 = 2.0 * (ry * rz - rw * rx);
    const T m22 = 1.0 - 2.0 * (rx * rx + ry * ry), m01 = 2.0 * (rx * ry - rw * rz);
    const T m00 = 1.0 - 2.0 * (ry * ry + rz * rz);
    phi(0) = atan2(-m12, m22);
    phi(1) = asin(m02);
    phi(2) = atan2(-m01, m00);
    // ω = 2 Im(ū ⊗ u̇)/|u|² = 2 (w v̇ − ẇ v − v × v̇)/|u|² (Q1).
    const Eigen::Matrix<T, 3, 1> v(u(1), u(2), u(3)), vd(ud(1), ud(2), ud(3));
    const Eigen::Matrix<T, 3, 1> om = (2.0 / n2) * (u(0) * vd - ud(0) * v - v.cross(vd));
    const T cb = cos(phi(1)), sb = sin(phi(1)), cc = cos(phi(2)), sc = sin(phi(2));
    phid(0) = (cc * om(0) - sc * om(1)) / cb;
    phid(1) = sc * om(0) + cc * om(1);
    phid(2) = om(2) - sb * phid(0);
}

/// The motion of a floating robot: its root link's pose and velocity, and the whole robot's
/// momenta (world frame; the angular momentum about the world's origin) and centre of mass.
struct base_motion {
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity(); ///< world from root link
    vec3 position = vec3::Zero();                                    ///< the root link's origin [m]
    vec3 velocity = vec3::Zero();                                    ///< of that origin [m/s]
    vec3 angular_velocity = vec3::Zero();                            ///< [rad/s]
    vec3 momentum = vec3::Zero();         ///< total linear momentum [N s]
    vec3 angular_momentum = vec3::Zero(); ///< total, about the world's origin [N m s]
    vec3 centre_of_mass = vec3::Zero();   ///< [m]
};

/// Sums over the bodies at the workspace's last kinematics and velocities: momenta (about the
/// computation's origin) and the centre of mass.
inline void add_momenta(const tree& m, const workspace& w, base_motion& out) {
    double mass = 0.0;
    for (std::size_t i = 0; i < m.bodies.size(); ++i) {
        out.angular_momentum += w.h[i].head<3>();
        out.momentum += w.h[i].tail<3>();
        out.centre_of_mass += m.bodies[i].mass * w.x[i].point(m.bodies[i].com);
        mass += m.bodies[i].mass;
    }
    if (mass > 0.0) out.centre_of_mass /= mass;
}

/// The motion of a robot in its tree's own coordinates (a fixed or planar base) at (q, q̇).
inline base_motion tree_motion(const tree& m, const vec<dynamic>& q, const vec<dynamic>& qd) {
    thread_local workspace w;
    w.chart.setIdentity();
    kinematics(m, w, q);
    velocities(m, w, qd);
    base_motion out;
    if (m.base_coordinates() > 0) {
        const auto k = static_cast<std::size_t>(m.base_coordinates() - 1);
        out.orientation = Eigen::Quaterniond(w.x[k].rotation);
        out.position = w.x[k].origin;
        out.angular_velocity = w.v[k].head<3>();
        out.velocity = w.v[k].tail<3>() + out.angular_velocity.cross(out.position);
    }
    add_momenta(m, w, out);
    return out;
}

/// A robot with a free base as a Lagrangian in (x, u, θ) (Q1)–(Q2), for the general engine's
/// constrained stepper with unit_quaternion. One shared tree; per-thread scratch.
class free_robot {
  public:
    static constexpr int dim = dynamic;

    explicit free_robot(std::shared_ptr<const tree> m) : m_(std::move(m)) {
        if (!m_ || m_->base != base_kind::free)
            throw std::invalid_argument("free_robot needs a tree with a free base");
        m_->check();
        for (const body& b : m_->bodies)
            mass_ += b.mass;
        kappa_ = 4.0 * std::max(m_->root.inertia.trace() / 3.0, 1e-9 * m_->root.mass);
    }

    [[nodiscard]] int dimension() const { return m_->dof() + 1; }
    [[nodiscard]] const tree& robot() const { return *m_; }
    [[nodiscard]] const std::shared_ptr<const tree>& shared() const { return m_; }

    /// L(q, q̇) [J].
    double operator()(const vec<dynamic>& q, const vec<dynamic>& v) const {
        scratch& s = work();
        chart(q, v, s);
        workspace& w = s.w;
        kinematics(*m_, w, s.c);
        velocities(*m_, w, s.cd);
        return lagrangian_value(*m_, w) + tail(q, v);
    }

    /// L, ∂L/∂q and ∂L/∂q̇.
    void gradient(const vec<dynamic>& q, const vec<dynamic>& v,
                  lagrangian_terms<dynamic>& t) const {
        scratch& s = work();
        chart(q, v, s);
        size(t, false);
        const double value = lagrangian_gradient(*m_, s.w, s.c, s.cd, s.t.lq, s.t.lv);
        maps<ad::first_order<8>>(q, v, s);
        first(q, v, s, t);
        t.value = value + tail(q, v);
    }

    /// gradient() and the second derivatives.
    void derivatives(const vec<dynamic>& q, const vec<dynamic>& v,
                     lagrangian_terms<dynamic>& t) const {
        scratch& s = work();
        chart(q, v, s);
        size(t, true);
        const double value =
            lagrangian_derivatives(*m_, s.w, s.c, s.cd, s.t.lq, s.t.lv, s.t.lqq, s.t.lqv, s.t.lvv);
        maps<ad::second_order<8>>(q, v, s);
        first(q, v, s, t);
        second(q, v, s, t);
        t.value = value + tail(q, v);
    }

    /// The motion at (q, q̇): base pose and velocity, momenta, centre of mass.
    [[nodiscard]] base_motion motion(const vec<dynamic>& q, const vec<dynamic>& v) const {
        scratch& s = work();
        chart(q, v, s);
        workspace& w = s.w;
        kinematics(*m_, w, s.c);
        velocities(*m_, w, s.cd);
        base_motion out;
        out.orientation = s.u0;
        out.position = q.head<3>();
        out.velocity = v.head<3>();
        out.angular_velocity = s.u0 * vec3(s.cd.segment<3>(3)); // ω in the world
        add_momenta(*m_, w, out); // about x, then moved to the world's origin
        out.centre_of_mass += out.position;
        out.angular_momentum += out.position.cross(out.momentum);
        return out;
    }

  private:
    struct scratch {
        workspace w;
        vec<dynamic> c, cd;                  // the chart's coordinates and rates (n + 6)
        lagrangian_terms<dynamic> t;         // L_tree's derivatives in them
        Eigen::Quaterniond u0;               // the chart's orientation: û
        Eigen::Matrix<double, 3, 4> a, b, d; // ∂φ/∂u, ∂φ̇/∂u, ∂φ̇/∂u̇
        Eigen::Matrix<double, 4, 4> hphi[3], hrate[3], hmixed[3]; // ∂²φ/∂u², ∂²φ̇/∂u², ∂²φ̇/∂u∂u̇
    };
    static scratch& work() {
        thread_local scratch s;
        return s;
    }

    std::shared_ptr<const tree> m_;
    double mass_ = 0.0, kappa_ = 1.0;

    /// The chart at q: C = R(û), origin x; c = (0, 0, θ), ċ = (ẋ, ω, θ̇).
    void chart(const vec<dynamic>& q, const vec<dynamic>& v, scratch& s) const {
        const int n = m_->dof();
        const Eigen::Vector4d u = q.segment<4>(3), ud = v.segment<4>(3);
        if (!(u.squaredNorm() > 0.0) || !u.allFinite())
            throw std::domain_error("the base's quaternion is zero or not finite");
        s.u0 = Eigen::Quaterniond(u(0), u(1), u(2), u(3)).normalized();
        s.w.chart = s.u0.toRotationMatrix();
        s.c.setZero(n);
        s.cd.resize(n);
        s.c.tail(n - 6) = q.tail(n - 6);
        s.cd.head<3>() = v.head<3>();
        const Eigen::Vector3d vv = u.tail<3>(), vd = ud.tail<3>();
        s.cd.segment<3>(3) = (2.0 / u.squaredNorm()) * (u(0) * vd - ud(0) * vv - vv.cross(vd));
        s.cd.tail(n - 6) = v.tail(n - 6);
    }

    /// M g·x and ½ κ (u·u̇)² (Q2).
    [[nodiscard]] double tail(const vec<dynamic>& q, const vec<dynamic>& v) const {
        const double r = q.segment<4>(3).dot(v.segment<4>(3));
        return mass_ * m_->gravity.dot(q.head<3>()) + 0.5 * kappa_ * r * r;
    }

    /// The chart's maps' derivatives at (u, u̇) by forward-mode AD over the scalar T.
    template <class T>
    void maps(const vec<dynamic>& q, const vec<dynamic>& v, scratch& s) const {
        constexpr bool second_order = !std::is_same_v<T, ad::first_order<8>>;
        Eigen::Matrix<T, 4, 1> u, ud;
        for (int i = 0; i < 4; ++i) {
            if constexpr (second_order) {
                u(i) = ad::variable<8>(q(3 + i), i);
                ud(i) = ad::variable<8>(v(3 + i), 4 + i);
            } else {
                u(i) = T(q(3 + i), 8, i);
                ud(i) = T(v(3 + i), 8, 4 + i);
            }
        }
        Eigen::Matrix<T, 3, 1> phi, phid;
        chart_maps<T>(s.u0, u, ud, phi, phid);
        for (int i = 0; i < 3; ++i) {
            if constexpr (second_order) {
                Eigen::Matrix<double, 8, 1> g;
                Eigen::Matrix<double, 8, 8> h;
                ad::unpack<8>(phi(i), g, h);
                s.a.row(i) = g.head<4>().transpose();
                s.hphi[i] = h.topLeftCorner<4, 4>();
                ad::unpack<8>(phid(i), g, h);
                s.b.row(i) = g.head<4>().transpose();
                s.d.row(i) = g.tail<4>().transpose();
                s.hrate[i] = h.topLeftCorner<4, 4>();
                s.hmixed[i] = h.topRightCorner<4, 4>();
            } else {
                s.a.row(i) = phi(i).derivatives().template head<4>().transpose();
                s.b.row(i) = phid(i).derivatives().template head<4>().transpose();
                s.d.row(i) = phid(i).derivatives().template tail<4>().transpose();
            }
        }
    }

    /// ∂L/∂q, ∂L/∂q̇ by the chain rule: x and θ as they are, u through the maps.
    void first(const vec<dynamic>& q, const vec<dynamic>& v, const scratch& s,
               lagrangian_terms<dynamic>& t) const {
        const int n = m_->dof();
        const Eigen::Vector4d u = q.segment<4>(3), ud = v.segment<4>(3);
        const double r = u.dot(ud);
        t.lq.head<3>() = s.t.lq.head<3>();
        t.lv.head<3>() = s.t.lv.head<3>();
        t.lq.segment<4>(3) = s.a.transpose() * s.t.lq.segment<3>(3) +
                             s.b.transpose() * s.t.lv.segment<3>(3) + kappa_ * r * ud;
        t.lv.segment<4>(3) = s.d.transpose() * s.t.lv.segment<3>(3) + kappa_ * r * u;
        t.lq.tail(n - 6) = s.t.lq.tail(n - 6);
        t.lv.tail(n - 6) = s.t.lv.tail(n - 6);
    }

    /// out += Rᵀ in C, R and C the chart's Jacobians (n + 6 → n + 7): identity on x and θ where
    /// `rid` (`cid`), zero there otherwise; `ra` (`ca`) on u.
    static void expand(const mat<dynamic>& in, const Eigen::Matrix<double, 3, 4>& ra, bool rid,
                       const Eigen::Matrix<double, 3, 4>& ca, bool cid, mat<dynamic>& out) {
        const Eigen::Index nc = in.rows(), k = nc - 6;
        thread_local mat<dynamic> tmp;
        tmp.setZero(nc, nc + 1);
        if (cid) {
            tmp.leftCols<3>() = in.leftCols<3>();
            tmp.rightCols(k) = in.rightCols(k);
        }
        tmp.middleCols<4>(3) = in.middleCols<3>(3) * ca;
        if (rid) {
            out.topRows<3>() += tmp.topRows<3>();
            out.bottomRows(k) += tmp.bottomRows(k);
        }
        out.middleRows<4>(3) += ra.transpose() * tmp.middleRows<3>(3);
    }

    /// The second derivatives: the chain rule's products and the maps' curvature.
    void second(const vec<dynamic>& q, const vec<dynamic>& v, const scratch& s,
                lagrangian_terms<dynamic>& t) const {
        const Eigen::Vector4d u = q.segment<4>(3), ud = v.segment<4>(3);
        const double r = u.dot(ud);
        const mat<dynamic>& lcc = s.t.lqq;
        const mat<dynamic>& lcd = s.t.lqv; // ∂²L/∂c∂ċ
        const mat<dynamic>& ldd = s.t.lvv;
        thread_local mat<dynamic> ldc;
        ldc = lcd.transpose();
        t.lqq.setZero();
        t.lqv.setZero();
        t.lvv.setZero();
        expand(lcc, s.a, true, s.a, true, t.lqq);
        expand(lcd, s.a, true, s.b, false, t.lqq);
        expand(ldc, s.b, false, s.a, true, t.lqq);
        expand(ldd, s.b, false, s.b, false, t.lqq);
        expand(lcd, s.a, true, s.d, true, t.lqv);
        expand(ldd, s.b, false, s.d, true, t.lqv);
        expand(ldd, s.d, true, s.d, true, t.lvv);
        for (int i = 0; i < 3; ++i) {
            t.lqq.block<4, 4>(3, 3) += s.t.lq(3 + i) * s.hphi[i] + s.t.lv(3 + i) * s.hrate[i];
            t.lqv.block<4, 4>(3, 3) += s.t.lv(3 + i) * s.hmixed[i];
        }
        t.lqq.block<4, 4>(3, 3) += kappa_ * ud * ud.transpose();
        t.lqv.block<4, 4>(3, 3) += kappa_ * (ud * u.transpose() + r * Eigen::Matrix4d::Identity());
        t.lvv.block<4, 4>(3, 3) += kappa_ * u * u.transpose();
    }

    void size(lagrangian_terms<dynamic>& t, bool second) const {
        const int n = m_->dof(), nq = n + 1;
        scratch& s = work();
        s.t.lq.resize(n);
        s.t.lv.resize(n);
        t.lq.resize(nq);
        t.lv.resize(nq);
        if (!second) return;
        s.t.lqq.resize(n, n);
        s.t.lqv.resize(n, n);
        s.t.lvv.resize(n, n);
        t.lqq.resize(nq, nq);
        t.lqv.resize(nq, nq);
        t.lvv.resize(nq, nq);
    }
};

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
