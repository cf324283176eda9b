// varsym/multibody/algorithms.hpp: the recursive algorithms over a tree and a workspace
// (tree.hpp), in world coordinates (Featherstone's spatial notation, spatial.hpp): kinematics,
// the Lagrangian L = ½ Σ v_iᵀ I_i v_i − V(q), V = −Σ m_i g·c_i, with its first derivatives in
// O(n) and its second derivatives in O(n²) (the variational steppers' residuals and Newton
// Jacobians), the mass matrix, gravity and bias forces, and frame poses.
//
// The derivatives, with S_i the world motion subspace of joint i, v_i the velocity of body i,
// h^c_i, I^c_i and F^c_i the momentum, inertia and gravity wrench (I a_g, a_g = (0; g)) summed
// over body i's subtree, λ(i) its parent, u_i = S_i × v_λ(i) and α_i = S_i × a_g:
//   ∂L/∂q̇_j = S_jᵀ h^c_j,   ∂L/∂q_j = S_jᵀ (F^c_j − v_j ×* h^c_j)   (∂S_j/∂q_i = S_i × S_j)
// and, for i an ancestor of j or j itself (i ≼ j),
//   ∂²L/∂q_i∂q̇_j = −S_jᵀ I^c_j u_i,
//   ∂²L/∂q_i∂q_j = S_jᵀ (u_i ×* h^c_j + v_j ×* I^c_j u_i − I^c_j α_i),
//   ∂²L/∂q̇_i∂q̇_j = M_ij = S_iᵀ I^c_j S_j,
// and, for j a strict ancestor of i (j ≺ i), with dh_i = S_i ×* h^c_i − I^c_i u_i and
// dF_i = S_i ×* F^c_i − I^c_i α_i (the changes of i's subtree's momentum and gravity wrench),
//   ∂²L/∂q_i∂q̇_j = S_jᵀ dh_i,   ∂²L/∂q_i∂q_j = S_jᵀ (dF_i − v_j ×* dh_i);
// zero where neither joint is above the other. The world-frame quantities moving rigidly with
// joint i change by S_i × (motions) and S_i ×* (forces) and those changes cancel in each S_jᵀ(·)
// product; what is left are the terms in u_i and α_i (docs/robots.md derives them).
// These are derivatives in the joint positions θ of all bodies; with mimic joints (tree.hpp)
// each entry (i, j) is added, times a_i a_j (a = ∂θ/∂q: 1 or the multiplier), to the entry of
// the coordinates (c_i, c_j) that move them: Aᵀ (·) A, and Aᵀ (·) for the first derivatives.
#pragma once

#include <cassert>

#include <Eigen/Core>

#include "varsym/multibody/tree.hpp"

namespace varsym::multibody {

/// Body poses, joint motion subspaces S_i, centres of mass, gravity wrenches f_i = I_i (0; g)
/// and, where `inertias`, the world spatial inertias I_i at q (the mass matrix, its factorisation,
/// the second derivatives and the bias forces take them; the first derivatives do not: left out,
/// they are a third of this pass). Over the workspace's scalar S (the algorithms down to
/// lagrangian_derivatives take any; the model's data are double and enter as S).
template <class S, class Q>
void kinematics(const tree& m, basic_workspace<S>& w, const Eigen::MatrixBase<Q>& q,
                bool inertias = true) {
    const int n = m.body_count();
    w.resize(n);
    w.has_inertias = inertias;
    const vec3_of<S> g = m.gravity.template cast<S>();
    for (int i = 0; i < n; ++i) {
        const auto k = static_cast<std::size_t>(i);
        const body& b = m.bodies[k];
        basic_pose<S> placement = b.placement.template cast<S>();
        if (i == m.chart_body())
            placement.rotation = w.chart.template cast<S>() * placement.rotation;
        const basic_pose<S> joint =
            b.parent < 0 ? placement : w.x[static_cast<std::size_t>(b.parent)] * placement;
        const vec3_of<S> a = joint.rotation * b.axis.template cast<S>();
        const S qi = m.joint_position(q, i);
        // Head and tail as fixed-size blocks: a comma initializer's first block is of run-time
        // size (Eigen 3.4), and its copy was a loop that was not inlined.
        if (b.kind == joint_kind::revolute) {
            w.s[k].template head<3>() = a; // rotation about the axis through the joint
            w.s[k].template tail<3>() = joint.origin.cross(a);
            w.x[k] = {joint.rotation * axis_angle(b.axis, qi), joint.origin};
        } else {
            w.s[k].template head<3>().setZero();
            w.s[k].template tail<3>() = a;
            w.x[k] = {joint.rotation, joint.origin + a * qi};
        }
        const mat3_of<S>& r = w.x[k].rotation;
        const vec3_of<S> c = w.x[k].point(b.com);
        w.com[k] = c;
        if (inertias)
            set_spatial_inertia<S>(w.inertia[k], b.mass, c,
                                   r * b.inertia.template cast<S>() * r.transpose());
        const S mass(b.mass);
        w.gravity[k].template head<3>() = mass * c.cross(g);
        w.gravity[k].template tail<3>() = mass * g;
    }
}

/// Body velocities v_i = v_λ(i) + S_i q̇_i and momenta h_i = I_i v_i (after kinematics, with or
/// without the inertias: h_i from the body's mass, centre of mass and rotated inertia).
template <class S, class V>
void velocities(const tree& m, basic_workspace<S>& w, const Eigen::MatrixBase<V>& qd) {
    // The last body's velocity, kept in registers for a child just after its parent (a chain's
    // next body): no store and reload on the way down (the same additions).
    vec6_of<S> last = vec6_of<S>::Zero();
    for (int i = 0; i < m.body_count(); ++i) {
        const auto k = static_cast<std::size_t>(i);
        const int p = m.bodies[k].parent;
        vec6_of<S> v = w.s[k] * S(m.joint_rate(qd, i));
        if (p >= 0) v += p == i - 1 ? last : w.v[static_cast<std::size_t>(p)];
        w.v[k] = v;
        last = v;
        // h = I v without I: f = m (v_o + ω × c), n = I_c ω + c × f, I_c ω = R I_b Rᵀ ω.
        const body& b = m.bodies[k];
        const mat3_of<S>& r = w.x[k].rotation;
        const vec3_of<S> om = v.template head<3>();
        const vec3_of<S> f = S(b.mass) * (v.template tail<3>() + om.cross(w.com[k]));
        const vec3_of<S> body_om = r.transpose() * om;
        const vec3_of<S> ib = b.inertia.template cast<S>() * body_om;
        w.h[k].template head<3>() = r * ib + w.com[k].cross(f);
        w.h[k].template tail<3>() = f;
    }
}

/// L = T − V from the bodies' velocities and momenta (after velocities): T = ½ Σ v_iᵀ h_i,
/// V = −Σ m_i g·c_i.
template <class S>
S lagrangian_value(const tree& m, const basic_workspace<S>& w) {
    S t(0.0), minus_v(0.0);
    const vec3_of<S> g = m.gravity.template cast<S>();
    for (std::size_t k = 0; k < m.bodies.size(); ++k) {
        t += w.v[k].dot(w.h[k]);
        minus_v += S(m.bodies[k].mass) * g.dot(w.com[k]); // m g·c
    }
    return S(0.5) * t + minus_v;
}

/// The energy E = T + V = 2T − L at (q, q̇) (kinematics, velocities and L in one call).
template <class Q, class V>
double energy(const tree& m, workspace& w, const Eigen::MatrixBase<Q>& q,
              const Eigen::MatrixBase<V>& qd) {
    kinematics(m, w, q, false);
    velocities(m, w, qd);
    double t = 0.0;
    for (std::size_t k = 0; k < m.bodies.size(); ++k)
        t += 0.5 * w.v[k].dot(w.h[k]);
    return 2.0 * t - lagrangian_value(m, w);
}

/// The subtree sums of the momenta and gravity wrenches (and, with inertias, of the spatial
/// inertias), leaves first: h^c_i, F^c_i (I^c_i). The per-body fields are left as they are.
template <class S>
void subtree_sums(const tree& m, basic_workspace<S>& w, bool inertias) {
    assert(!inertias || w.has_inertias);
    const auto n = static_cast<std::size_t>(m.body_count());
    for (std::size_t k = 0; k < n; ++k) {
        w.h_c[k] = w.h[k];
        w.gravity_c[k] = w.gravity[k];
        if (inertias) w.inertia_c[k] = w.inertia[k];
    }
    // Leaves first. A body whose parent comes just before it hands its sums on in registers
    // (carry), the others through the parent's entry: the same additions in the same order (the
    // body just after a parent is its last child), without a store and reload per body.
    vec6_of<S> carry_h = vec6_of<S>::Zero(), carry_g = vec6_of<S>::Zero();
    bool carried = false;
    for (int i = m.body_count() - 1; i >= 0; --i) {
        const auto k = static_cast<std::size_t>(i);
        if (carried) {
            w.h_c[k] += carry_h;
            w.gravity_c[k] += carry_g;
            if (inertias) w.inertia_c[k] += w.inertia_c[k + 1];
        }
        const int p = m.bodies[k].parent;
        carried = p >= 0 && p == i - 1;
        if (carried) {
            carry_h = w.h_c[k];
            carry_g = w.gravity_c[k];
        } else if (p >= 0) {
            const auto pk = static_cast<std::size_t>(p);
            w.h_c[pk] += w.h_c[k];
            w.gravity_c[pk] += w.gravity_c[k];
            if (inertias) w.inertia_c[pk] += w.inertia_c[k];
        }
    }
}

/// L(q, q̇), ∂L/∂q and ∂L/∂q̇ in O(n): value, lq, lv (sized n).
template <class S, class Q, class V, class Out>
S lagrangian_gradient(const tree& m, basic_workspace<S>& w, const Eigen::MatrixBase<Q>& q,
                      const Eigen::MatrixBase<V>& qd, Eigen::MatrixBase<Out>& lq,
                      Eigen::MatrixBase<Out>& lv, bool keep_inertias = false) {
    kinematics(m, w, q, keep_inertias);
    velocities(m, w, qd);
    const S value = lagrangian_value(m, w);
    subtree_sums(m, w, keep_inertias);
    for (int j = 0; j < m.dof(); ++j) {
        const auto k = static_cast<std::size_t>(j);
        lv(j) = w.s[k].dot(w.h_c[k]);
        lq(j) = w.s[k].dot(w.gravity_c[k] - cross_force(w.v[k], w.h_c[k]));
    }
    for (int j = m.dof(); j < m.body_count(); ++j) { // mimic joints: Aᵀ (·)
        const auto k = static_cast<std::size_t>(j);
        const int c = m.coordinate(j);
        const S a(m.weight(j));
        lv(c) += a * w.s[k].dot(w.h_c[k]);
        lq(c) += a * w.s[k].dot(w.gravity_c[k] - cross_force(w.v[k], w.h_c[k]));
    }
    return value;
}

/// The first and second derivatives of L in O(n²) (the formulas at the top of this file):
/// lq, lv, and lqq, lqv (lqv(i, j) = ∂²L/∂q_i∂q̇_j), lvv = M(q). Returns L.
template <class S, class Q, class V, class Vec, class Mat>
S lagrangian_derivatives(const tree& m, basic_workspace<S>& w, const Eigen::MatrixBase<Q>& q,
                         const Eigen::MatrixBase<V>& qd, Eigen::MatrixBase<Vec>& lq,
                         Eigen::MatrixBase<Vec>& lv, Eigen::MatrixBase<Mat>& lqq,
                         Eigen::MatrixBase<Mat>& lqv, Eigen::MatrixBase<Mat>& lvv) {
    const S value = lagrangian_gradient(m, w, q, qd, lq, lv, true);
    const int n = m.body_count();
    const vec6_of<S> ag =
        (vec6_of<S>() << vec3_of<S>::Zero(), m.gravity.template cast<S>()).finished();
    lqq.setZero();
    lqv.setZero();
    lvv.setZero();
    for (int i = 0; i < n; ++i) {
        const auto k = static_cast<std::size_t>(i);
        const int p = m.bodies[k].parent;
        if (p >= 0)
            w.u[k] = cross_motion(w.s[k], w.v[static_cast<std::size_t>(p)]);
        else
            w.u[k].setZero();
        w.alpha[k] = cross_motion(w.s[k], ag);
        w.dh[k] = cross_force(w.s[k], w.h_c[k]) - w.inertia_c[k] * w.u[k];
        w.df[k] = cross_force(w.s[k], w.gravity_c[k]) - w.inertia_c[k] * w.alpha[k];
        w.s_ic[k].noalias() = w.s[k].transpose() * w.inertia_c[k];
        // t = Sᵀ (v ×*), and r with r u = Sᵀ (u ×* h + v ×* I u): for u = (a; b), h = (n; f),
        // S = (s₁; s₂), Sᵀ (u ×* h) = a·(n × s₁ + f × s₂) + b·(f × s₁).
        const vec3_of<S> s1 = w.s[k].template head<3>(), s2 = w.s[k].template tail<3>();
        const vec3_of<S> om = w.v[k].template head<3>(), vo = w.v[k].template tail<3>();
        const vec3_of<S> hn = w.h_c[k].template head<3>(), fh = w.h_c[k].template tail<3>();
        w.t[k].template head<3>() = s1.cross(om).transpose(); // Sᵀ (v ×* g) = t g
        w.t[k].template tail<3>() = (s1.cross(vo) + s2.cross(om)).transpose();
        w.r[k].noalias() = w.t[k] * w.inertia_c[k];
        w.r[k].template head<3>() += (hn.cross(s1) + fh.cross(s2)).transpose();
        w.r[k].template tail<3>() += fh.cross(s1).transpose();
    }
    if (m.mimics.empty()) {
        for (int j = 0; j < n; ++j) {
            const auto jk = static_cast<std::size_t>(j);
            // i ≼ j: j itself and its ancestors.
            for (int i = j; i >= 0; i = m.bodies[static_cast<std::size_t>(i)].parent) {
                const auto ik = static_cast<std::size_t>(i);
                lqv(i, j) = -w.s_ic[jk].dot(w.u[ik]);
                lqq(i, j) = w.r[jk].dot(w.u[ik]) - w.s_ic[jk].dot(w.alpha[ik]);
                lvv(i, j) = lvv(j, i) = w.s_ic[jk].dot(w.s[ik]);
            }
            // j ≺ i, seen from i = j: its strict ancestors a take the (i = j, j = a) entries.
            for (int a = m.bodies[jk].parent; a >= 0;
                 a = m.bodies[static_cast<std::size_t>(a)].parent) {
                const auto ak = static_cast<std::size_t>(a);
                lqv(j, a) = w.s[ak].dot(w.dh[jk]);
                lqq(j, a) = w.s[ak].dot(w.df[jk]) - w.t[ak].dot(w.dh[jk]);
            }
        }
        return value;
    }
    // With mimic joints the same entries, each added to its coordinates' times a_i a_j.
    for (int j = 0; j < n; ++j) {
        const auto jk = static_cast<std::size_t>(j);
        const int cj = m.coordinate(j);
        const S aj(m.weight(j));
        for (int i = j; i >= 0; i = m.bodies[static_cast<std::size_t>(i)].parent) {
            const auto ik = static_cast<std::size_t>(i);
            const int ci = m.coordinate(i);
            const S aij = S(m.weight(i)) * aj;
            lqv(ci, cj) -= aij * w.s_ic[jk].dot(w.u[ik]);
            lqq(ci, cj) += aij * (w.r[jk].dot(w.u[ik]) - w.s_ic[jk].dot(w.alpha[ik]));
            const S mij = aij * w.s_ic[jk].dot(w.s[ik]);
            lvv(ci, cj) += mij;
            if (i != j) lvv(cj, ci) += mij;
        }
        for (int a = m.bodies[jk].parent; a >= 0;
             a = m.bodies[static_cast<std::size_t>(a)].parent) {
            const auto ak = static_cast<std::size_t>(a);
            const int ca = m.coordinate(a);
            const S aja = S(m.weight(a)) * aj;
            lqv(cj, ca) += aja * w.s[ak].dot(w.dh[jk]);
            lqq(cj, ca) += aja * (w.s[ak].dot(w.df[jk]) - w.t[ak].dot(w.dh[jk]));
        }
    }
    return value;
}

/// The joint-space mass matrix M(q) by the composite-rigid-body algorithm (O(n²)).
template <class Q, class Mat>
void mass_matrix(const tree& m, workspace& w, const Eigen::MatrixBase<Q>& q,
                 Eigen::MatrixBase<Mat>& out) {
    kinematics(m, w, q);
    subtree_sums(m, w, true);
    out.setZero();
    for (int j = 0; j < m.body_count(); ++j) { // M_θ, and Aᵀ M_θ A with mimic joints
        const auto jk = static_cast<std::size_t>(j);
        const vec6 ics = m.weight(j) * (w.inertia_c[jk] * w.s[jk]);
        const int cj = m.coordinate(j);
        for (int i = j; i >= 0; i = m.bodies[static_cast<std::size_t>(i)].parent) {
            const int ci = m.coordinate(i);
            const double mij = m.weight(i) * w.s[static_cast<std::size_t>(i)].dot(ics);
            out(ci, cj) += mij;
            if (i != j) out(cj, ci) += mij;
        }
    }
}

/// bias_forces at the q of the workspace's last kinematics (which mass_matrix also leaves).
template <class V, class Out>
void bias_forces_after_kinematics(const tree& m, workspace& w, const Eigen::MatrixBase<V>& qd,
                                  Eigen::MatrixBase<Out>& out) {
    assert(w.has_inertias);
    velocities(m, w, qd);
    const vec6 base = (vec6() << vec3::Zero(), -m.gravity).finished();
    for (int i = 0; i < m.body_count(); ++i) {
        const auto k = static_cast<std::size_t>(i);
        const int p = m.bodies[k].parent;
        // a_i = a_λ(i) + Ṡ_i θ̇_i, Ṡ_i = v_i × S_i; f_i = I_i a_i + v_i ×* I_i v_i (θ̈ = A q̈ = 0).
        w.a[k] = (p < 0 ? base : w.a[static_cast<std::size_t>(p)]) +
                 cross_motion(w.v[k], w.s[k]) * m.joint_rate(qd, i);
        w.force[k] = w.inertia[k] * w.a[k] + cross_force(w.v[k], w.h[k]);
    }
    out.setZero();
    for (int i = m.body_count() - 1; i >= 0; --i) { // Aᵀ τ_θ
        const auto k = static_cast<std::size_t>(i);
        out(m.coordinate(i)) += m.weight(i) * w.s[k].dot(w.force[k]);
        const int p = m.bodies[k].parent;
        if (p >= 0) w.force[static_cast<std::size_t>(p)] += w.force[k];
    }
}

/// The generalized forces of q̈ = 0 by the recursive Newton–Euler algorithm (Featherstone
/// §5.3, in world coordinates, gravity as the base's acceleration −a_g): the bias
/// C(q, q̇)q̇ + g(q) with M(q)q̈ + C(q, q̇)q̇ + g(q) = τ. With q̇ = 0 it is g(q) = ∂V/∂q.
template <class Q, class V, class Out>
void bias_forces(const tree& m, workspace& w, const Eigen::MatrixBase<Q>& q,
                 const Eigen::MatrixBase<V>& qd, Eigen::MatrixBase<Out>& out) {
    kinematics(m, w, q);
    bias_forces_after_kinematics(m, w, qd, out);
}

/// A named frame's pose in the world at the last kinematics.
inline pose frame_pose(const workspace& w, const frame& f) {
    return f.body < 0 ? f.offset : w.x[static_cast<std::size_t>(f.body)] * f.offset;
}

/// The frame's world Jacobian at the last kinematics (6 × n): its angular velocity (rows 0–2)
/// and its origin's velocity (rows 3–5) per joint rate. Column j is (S_j^ω; S_j^v + S_j^ω × o),
/// o the frame's origin, for joint j on the path from the frame's body to the root; else zero
/// (a mimic joint's column, times its multiplier, added to its master's).
inline void frame_jacobian(const tree& m, const workspace& w, const frame& f,
                           Eigen::MatrixXd& out) {
    out.setZero(6, m.dof());
    const vec3 o = frame_pose(w, f).origin;
    for (int j = f.body; j >= 0; j = m.bodies[static_cast<std::size_t>(j)].parent) {
        const vec6& s = w.s[static_cast<std::size_t>(j)];
        const vec6 column = (vec6() << s.head<3>(), s.tail<3>() + s.head<3>().cross(o)).finished();
        out.col(m.coordinate(j)) += m.weight(j) * column;
    }
}

} // namespace varsym::multibody
