// varsym/multibody/floating_dynamics.hpp: the free base's mass matrix and bias forces
// (free_robot, floating.hpp), for the predictors: M(q) q̈ + b(q, q̇) = f are its Euler–Lagrange
// equations without the quaternion's constraint force. Included by floating.hpp.
//
// With c(q) the chart's coordinates (x, φ(u), θ) and ċ = C q̇ (C = ∂c/∂q: identity on x and θ,
// A = ∂φ/∂u on u, (Q3)), L(q, q̇) = L_tree(c, ċ) + ½ κ (u·u̇)² (Q2) pulls the tree's equations
// back through C: with M_c and b_c the tree's mass matrix and bias forces in the chart,
//   M = Cᵀ M_c C + κ u uᵀ,                                                                  (Q6)
//   b = Cᵀ (b_c(c, ċ) + M_c κ_c) + κ |u̇|² u,   κ_c = (0, u̇ᵀ(∂²φ_i/∂u²) u̇, 0),              (Q7)
// κ_c the chart's own acceleration at q̈ = 0 (d/dt of C q̇ with q̈ = 0; only φ is curved), and
// κ |u̇|² u the radial term's (its ∂/∂q̇ is κ r u, r = u·u̇, whose rate at ü = 0, less its ∂/∂q,
// κ r u̇, leaves κ |u̇|² u). tests/multibody/test_floating.cpp checks b against L's second
// derivatives, (∂²L/∂q̇∂q) q̇ − ∂L/∂q.
#pragma once

namespace varsym::multibody {

/// M(q) (Q6): the tree's mass matrix in the chart by the composite-rigid-body algorithm (O(n²),
/// no second derivatives), through ċ's Jacobian (identity on x and θ, W(u) = ∂ω/∂u̇ = A on u
/// (Q1)), plus κ u uᵀ (Q2). Leaves the kinematics and M_c in this thread's scratch, which
/// bias_forces_after_mass_matrix reads.
template <class>
void free_robot::mass_matrix(const vec<dynamic>& q, mat<dynamic>& out) const {
    scratch& s = work();
    const int n = m_->dof();
    thread_local vec<dynamic> rest;
    rest.setZero(n + 1);
    chart(q, rest, s);
    s.t.lvv.resize(n, n);
    multibody::mass_matrix(*m_, s.w, s.c, s.t.lvv);
    const Eigen::Vector4d u = q.segment<4>(3);
    const Eigen::Matrix4d* sm = bilinear();
    for (int i = 0; i < 3; ++i)
        s.d.row(i) = (2.0 / u.squaredNorm()) * (sm[i].transpose() * u).transpose();
    out.setZero(n + 1, n + 1);
    expand(s.t.lvv, s.d, true, s.d, true, out); // (Q6)
    out.block<4, 4>(3, 3) += kappa_ * u * u.transpose();
}

/// b(q, q̇) (Q7) after mass_matrix(q) on this thread: the tree's Newton–Euler pass in the chart
/// on the kinematics mass_matrix left, its mass matrix M_c times the chart's curvature, both
/// pulled back through C, and the radial term's.
template <class>
void free_robot::bias_forces_after_mass_matrix(const vec<dynamic>& q, const vec<dynamic>& v,
                                               vec<dynamic>& out) const {
    scratch& s = work();
    const int n = m_->dof();
    chart(q, v, s); // ċ = (ẋ, ω, θ̇); the kinematics at c are mass_matrix(q)'s
    maps(q, v, s, true);
    vec<dynamic>& bc = s.t.lq;
    bc.resize(n);
    bias_forces_after_kinematics(*m_, s.w, s.cd, bc);
    const Eigen::Vector4d ud = v.segment<4>(3);
    vec3 curvature; // κ_c's φ part: u̇ᵀ (∂²φ_i/∂u²) u̇ (Q7)
    for (int i = 0; i < 3; ++i)
        curvature(i) = ud.dot(s.hphi[i] * ud);
    bc.noalias() += s.t.lvv.middleCols<3>(3) * curvature; // M_c from mass_matrix(q)
    out.resize(n + 1);
    out.head<3>() = bc.head<3>();
    out.segment<4>(3) = s.a.transpose() * bc.segment<3>(3) + // (Q7)
                        (kappa_ * ud.squaredNorm()) * q.segment<4>(3);
    out.tail(n - 6) = bc.tail(n - 6);
}

} // namespace varsym::multibody
