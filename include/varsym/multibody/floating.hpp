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
// gives L's derivatives in (x, u, θ). The maps at the point, by hand: with P δ = Im(conj(û) ⊗ δ)
// and the rotation vector θ = 2 Im(conj(û) ⊗ (u + δ))/|u + δ| = (2/n)(1 − û·δ/n) P δ + O(δ³)
// (n = |u|), the XYZ angles are, by the Baker–Campbell–Hausdorff formula,
//   φ = θ − ½ (θ_y θ_z, −θ_x θ_z, θ_x θ_y) + O(δ³),   A = ∂φ/∂u = (2/n) P;                  (Q3)
// their rates φ̇ = E(φ)⁻¹ ω = (1 + E₁(φ) + E₂(φ)) ω + O(φ³) with
//   E₁(φ) ω = (−φ₃ ω_y, φ₃ ω_x, −φ₂ ω_x),  E₂(φ) ω = (½(φ₂² − φ₃²) ω_x, −½ φ₃² ω_y, φ₂ φ₃ ω_y),
//   (Q4)
// and ω = 2 B(u, u̇)/|u|², B bilinear; their second derivatives follow by the product rule (Q5).
// tests/multibody/test_floating.cpp checks the whole against AD of a second implementation.
//
// Why a quaternion: world rotations act on (x, u) linearly (x ↦ Qx, u ↦ q_Q ⊗ u) and leave g
// and L (without gravity) invariant, so the Galerkin discrete Lagrangians are invariant and the
// discrete Noether theorem conserves the total angular momentum to round-off, as translations
// conserve the linear momentum; no Euler-angle singularity (docs/robots.md).
// Functions and members that run the tree's algorithms, and the chart's helpers they call, are
// templates with a defaulted parameter (`template <class = void>`), called as plain functions: a
// source that includes this header and never calls them does not compile them
// (docs/development.md).
#pragma once

#include <array>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <utility>

#include <Eigen/Geometry>

#include "varsym/multibody/algorithms.hpp"
#include "varsym/multibody/unit_quaternion.hpp"
#include "varsym/systems/lagrangian.hpp"

namespace varsym::multibody {

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
template <class = void>
void add_momenta(const tree& m, const workspace& w, base_motion& out) {
    double mass = 0.0;
    for (std::size_t i = 0; i < m.bodies.size(); ++i) {
        out.angular_momentum += w.h[i].head<3>();
        out.momentum += w.h[i].tail<3>();
        out.centre_of_mass += m.bodies[i].mass * w.com[i];
        mass += m.bodies[i].mass;
    }
    if (mass > 0.0) out.centre_of_mass /= mass;
}

/// The motion of a robot in its tree's own coordinates (a fixed or planar base) at (q, q̇).
template <class = void>
base_motion tree_motion(const tree& m, const vec<dynamic>& q, const vec<dynamic>& qd) {
    thread_local workspace w;
    w.chart.setIdentity();
    kinematics(m, w, q, false);
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
    template <class = void>
    double operator()(const vec<dynamic>& q, const vec<dynamic>& v) const {
        scratch& s = work();
        chart(q, v, s);
        workspace& w = s.w;
        kinematics(*m_, w, s.c, false);
        velocities(*m_, w, s.cd);
        return lagrangian_value(*m_, w) + tail(q, v);
    }

    /// L, ∂L/∂q and ∂L/∂q̇.
    template <class = void>
    void gradient(const vec<dynamic>& q, const vec<dynamic>& v,
                  lagrangian_terms<dynamic>& t) const {
        scratch& s = work();
        chart(q, v, s);
        size(t, false);
        const double value = lagrangian_gradient(*m_, s.w, s.c, s.cd, s.t.lq, s.t.lv);
        maps(q, v, s, false);
        first(q, v, s, t);
        t.value = value + tail(q, v);
    }

    /// gradient() and the second derivatives.
    template <class = void>
    void derivatives(const vec<dynamic>& q, const vec<dynamic>& v,
                     lagrangian_terms<dynamic>& t) const {
        scratch& s = work();
        chart(q, v, s);
        size(t, true);
        const double value =
            lagrangian_derivatives(*m_, s.w, s.c, s.cd, s.t.lq, s.t.lv, s.t.lqq, s.t.lqv, s.t.lvv);
        maps(q, v, s, true);
        first(q, v, s, t);
        second(q, v, s, t);
        t.value = value + tail(q, v);
    }

    /// M(q) = ∂²L/∂q̇² (L is quadratic in q̇ without a linear term, p = M(q)q̇), by the
    /// composite-rigid-body algorithm (floating_dynamics.hpp). The general engine's predictors
    /// and lagrangian_system::velocity solve with it.
    template <class = void>
    void mass_matrix(const vec<dynamic>& q, mat<dynamic>& out) const;

    /// b(q, q̇) = (∂²L/∂q̇∂q) q̇ − ∂L/∂q, so that M(q) q̈ + b = f are the Euler–Lagrange
    /// equations (floating_dynamics.hpp): a Newton–Euler pass, no second derivatives. Only right
    /// after mass_matrix(q) at the same q on this thread, with no free_robot evaluated there in
    /// between (their scratch is the thread's). The constrained stepper's predictor.
    template <class = void>
    void bias_forces_after_mass_matrix(const vec<dynamic>& q, const vec<dynamic>& v,
                                       vec<dynamic>& out) const;

    /// The motion at (q, q̇): base pose and velocity, momenta, centre of mass.
    template <class = void>
    [[nodiscard]] base_motion motion(const vec<dynamic>& q, const vec<dynamic>& v) const {
        scratch& s = work();
        chart(q, v, s);
        workspace& w = s.w;
        kinematics(*m_, w, s.c, false);
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
    template <class = void>
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
    template <class = void>
    [[nodiscard]] double tail(const vec<dynamic>& q, const vec<dynamic>& v) const {
        const double r = q.segment<4>(3).dot(v.segment<4>(3));
        return mass_ * m_->gravity.dot(q.head<3>()) + 0.5 * kappa_ * r * r;
    }

    /// The chart's maps' derivatives at (u, u̇) (Q3)–(Q5), second ones where `second`.
    template <class = void>
    static void maps(const vec<dynamic>& q, const vec<dynamic>& v, scratch& s, bool second) {
        const Eigen::Vector4d u = q.segment<4>(3), ud = v.segment<4>(3);
        const double n2 = u.squaredNorm(), n = std::sqrt(n2);
        const Eigen::Vector4d uh = u / n;
        // P δ = Im(conj(û) ⊗ δ), A = ∂φ/∂u = (2/n) P (Q3).
        Eigen::Matrix<double, 3, 4> p;
        p.col(0) = -uh.tail<3>();
        p.rightCols<3>() = uh(0) * mat3::Identity() - skew(vec3(uh.tail<3>()));
        s.a = (2.0 / n) * p;
        // ω = 2 f B, f = 1/|u|², B_i = uᵀ S_i u̇ (Q1): ∂B_i/∂u = S_i u̇, ∂B_i/∂u̇ = S_iᵀ u.
        const Eigen::Matrix4d* sm = bilinear();
        Eigen::Matrix<double, 3, 4> bu, bd; // ∂B/∂u, ∂B/∂u̇ (rows)
        vec3 b;
        for (int i = 0; i < 3; ++i) {
            bu.row(i) = (sm[i] * ud).transpose();
            bd.row(i) = (sm[i].transpose() * u).transpose();
            b(i) = bd.row(i).dot(ud);
        }
        const double f = 1.0 / n2;
        const Eigen::Vector4d df = (-2.0 / (n2 * n2)) * u;
        const vec3 om = 2.0 * f * b;
        Eigen::Matrix<double, 3, 4> wu; // ∂ω/∂u
        for (int i = 0; i < 3; ++i)
            wu.row(i) = 2.0 * (b(i) * df.transpose() + f * bu.row(i));
        s.d = 2.0 * f * bd; // ∂φ̇/∂u̇ = ∂ω/∂u̇ = W(u)
        // φ̇ = (1 + E₁(φ) + E₂(φ)) ω (Q4): ∂φ̇/∂u = ∂ω/∂u + J₁(ω) A.
        mat3 j1 = mat3::Zero();
        j1(0, 2) = -om(1);
        j1(1, 2) = om(0);
        j1(2, 1) = -om(0);
        s.b = wu + j1 * s.a;
        if (!second) return;
        const Eigen::Matrix4d d2f = (-2.0 / (n2 * n2)) * Eigen::Matrix4d::Identity() +
                                    (8.0 / (n2 * n2 * n2)) * u * u.transpose();
        // ∂²φ_i/∂u² (Q3): −(2/n²)(û P_i + P_iᵀ ûᵀ) − ½ ∂²c_i(Aδ), c = (θ_y θ_z, −θ_x θ_z, θ_x θ_y).
        auto sym = [](const Eigen::RowVector4d& x, const Eigen::RowVector4d& y) {
            return Eigen::Matrix4d(x.transpose() * y + y.transpose() * x);
        };
        for (int i = 0; i < 3; ++i)
            s.hphi[i] = (-2.0 / n2) *
                        Eigen::Matrix4d(uh * p.row(i) + p.row(i).transpose() * uh.transpose());
        s.hphi[0] -= 0.5 * sym(s.a.row(1), s.a.row(2));
        s.hphi[1] += 0.5 * sym(s.a.row(0), s.a.row(2));
        s.hphi[2] -= 0.5 * sym(s.a.row(0), s.a.row(1));
        // ∂²φ̇_i/∂u² = ∂²ω_i/∂u² + Σ_j J₁_ij ∂²φ_j/∂u² + Aᵀ M_i ∂ω/∂u + (·)ᵀ + Aᵀ G_i A (Q5), with
        // M_i = ∂²(E₁ω)_i/∂φ∂ω and G_i = ∂²(E₂ω)_i/∂φ²; the mixed ones ∂²ω_i/∂u∂u̇ + Aᵀ M_i W.
        mat3 m[3] = {mat3::Zero(), mat3::Zero(), mat3::Zero()};
        m[0](2, 1) = -1.0; // (E₁ω)₀ = −φ₃ ω_y
        m[1](2, 0) = 1.0;  // (E₁ω)₁ = φ₃ ω_x
        m[2](1, 0) = -1.0; // (E₁ω)₂ = −φ₂ ω_x
        mat3 g[3] = {mat3::Zero(), mat3::Zero(), mat3::Zero()};
        g[0](1, 1) = om(0); // (E₂ω)₀ = ½ (φ₂² − φ₃²) ω_x
        g[0](2, 2) = -om(0);
        g[1](2, 2) = -om(1);             // (E₂ω)₁ = −½ φ₃² ω_y
        g[2](1, 2) = g[2](2, 1) = om(1); // (E₂ω)₂ = φ₂ φ₃ ω_y
        for (int i = 0; i < 3; ++i) {
            const Eigen::Vector4d bui = bu.row(i).transpose();
            Eigen::Matrix4d h = 2.0 * (b(i) * d2f + df * bui.transpose() + bui * df.transpose());
            for (int j = 0; j < 3; ++j)
                h += j1(i, j) * s.hphi[j];
            const Eigen::Matrix4d cross = s.a.transpose() * m[i] * wu;
            h += cross + cross.transpose() + s.a.transpose() * g[i] * s.a;
            s.hrate[i] = h;
            s.hmixed[i] = 2.0 * (df * bd.row(i) + f * sm[i]) + s.a.transpose() * m[i] * s.d;
        }
    }

    /// S_i with Im(ū ⊗ u̇)_i = uᵀ S_i u̇, u = (w, v): w v̇ − ẇ v − v × v̇.
    static const Eigen::Matrix4d* bilinear() {
        static const auto make = [] {
            std::array<Eigen::Matrix4d, 3> out;
            for (int i = 0; i < 3; ++i) {
                Eigen::Matrix4d& m = out[static_cast<std::size_t>(i)];
                m.setZero();
                const int j = (i + 1) % 3, k = (i + 2) % 3;
                m(0, 1 + i) = 1.0;      // w v̇_i
                m(1 + i, 0) = -1.0;     // −ẇ v_i
                m(1 + j, 1 + k) = -1.0; // −(v_j v̇_k − v_k v̇_j)
                m(1 + k, 1 + j) = 1.0;
            }
            return out;
        };
        static const std::array<Eigen::Matrix4d, 3> s = make();
        return s.data();
    }

    /// ∂L/∂q, ∂L/∂q̇ by the chain rule: x and θ as they are, u through the maps.
    template <class = void>
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
    template <class = void>
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
    template <class = void>
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

} // namespace varsym::multibody

#include "varsym/multibody/floating_dynamics.hpp"
