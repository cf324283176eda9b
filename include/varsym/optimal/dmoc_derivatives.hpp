// varsym/optimal/dmoc_derivatives.hpp: the equations of the DMOC transcription (dmoc.hpp), their
// sparse Jacobian and the Hessian of the Lagrangian, and the trajectory of a result. Included by
// dmoc.hpp; see its comment for the unknowns and equations.
#pragma once

namespace varsym::optimal {

template <lagrangian L, control_force F, class C>
void dmoc<L, F, C>::residual(cvector x, vector& e) const {
    e.setZero(constraints());
    add_step_equations(x, e, false);
    e.head<D>() += p_start_;                            // p_0 = −D₁L_d − f⁻
    e.segment<D>((points_ - 1) * D) -= end_momentum(x); // p_N = D₂L_d + f⁺
    add_constraint_residual(x, e);
}

/// Adds each step's terms to the equations of its control values (the discrete forced
/// Euler–Lagrange equations), or, if `end_only`, to its last control value's only: then e holds
/// p_{k+1} = D₂L_d + f⁺ at the nodes, the discrete Legendre transform (unpack).
template <lagrangian L, control_force F, class C>
void dmoc<L, F, C>::add_step_equations(cvector x, vector& e, bool end_only) const {
    const double h = h_of(x);
    lagrangian_terms<D> lt;
    for (int k = 0; k < n_; ++k)
        for (int j = 0; j < r_; ++j) {
            vec<D> q, v;
            point(x, k, j, q, v);
            const double t = (k + tab_.quad.nodes[static_cast<std::size_t>(j)]) * h;
            evaluate_gradient(l_, q, v, t, lt);
            const vec<D> force = f_(q, v, t, vec<M>(x.segment<M>(control_index(k * r_ + j))));
            const vec<D> lq = h * weight(j) * (lt.lq + force), lv = weight(j) * lt.lv;
            for (int i = end_only ? s_ : 0; i <= s_; ++i)
                e.segment<D>((k * s_ + i) * D) += tab_.phi(i, j) * lq + tab_.dphi(i, j) * lv;
        }
}

template <lagrangian L, control_force F, class C>
sparsity dmoc<L, F, C>::jacobian_pattern() const {
    sparsity s;
    const int w = (s_ + 1) * D;
    for (int k = 0; k < n_; ++k) {
        for (int row = 0; row < w; ++row)
            for (int col = 0; col < w; ++col)
                s.add(k * s_ * D + row, k * s_ * D + col);
        for (int row = 0; row < w; ++row)
            for (int col = 0; col < r_ * M; ++col)
                s.add(k * s_ * D + row, control_index(k * r_) + col);
    }
    if (p_.free_time) // ∂E/∂T: every equation depends on h = T/N
        for (int row = 0; row < constraints(); ++row)
            s.add(row, time_index());
    for (int row = 0; free_end_ && row < D; ++row) // −∂L/∂q̇(Q_{Ns}, v_N)
        for (int col = 0; col < 2 * D; ++col)
            s.add((points_ - 1) * D + row, end_index(col));
    add_constraint_jacobian(vector(), &s, nullptr);
    return s;
}

template <lagrangian L, control_force F, class C>
void dmoc<L, F, C>::jacobian(cvector x, std::vector<double>& values) const {
    const double h = h_of(x);
    const int w = (s_ + 1) * D;
    const std::size_t blocks =
        static_cast<std::size_t>(n_) * static_cast<std::size_t>(w * (w + r_ * M));
    const std::size_t end = blocks + (p_.free_time ? static_cast<std::size_t>(constraints()) : 0);
    values.assign(end + (free_end_ ? 2 * D * D : 0), 0.0);
    if (free_end_) { // −∂L/∂q̇(Q_{Ns}, v_N): −L_q̇q, −L_q̇q̇
        lagrangian_terms<D> lt;
        evaluate(l_, vec<D>(x.segment<D>((points_ - 1) * D)),
                 vec<D>(x.segment<D>(end_velocity_index())), n_ * h, lt);
        for (int row = 0; row < D; ++row)
            for (int col = 0; col < 2 * D; ++col)
                values[end + static_cast<std::size_t>(row * 2 * D + col)] =
                    col < D ? -lt.lqv(col, row) : -lt.lvv(row, col - D);
    }
    Eigen::MatrixXd bq(w, w), bu(w, r_ * M);
    lagrangian_terms<D> lt;
    control_terms<F> ft;
    std::size_t at = 0;
    for (int k = 0; k < n_; ++k) {
        bq.setZero();
        bu.setZero();
        for (int j = 0; j < r_; ++j) {
            vec<D> q, v;
            point(x, k, j, q, v);
            const double t = (k + tab_.quad.nodes[static_cast<std::size_t>(j)]) * h;
            evaluate(l_, q, v, t, lt);
            ft.evaluate(f_, q, v, t, vec<M>(x.segment<M>(control_index(k * r_ + j))));
            const double hw = h * weight(j);
            const mat<D> qq = hw * (lt.lqq + ft.fq), qv = weight(j) * (lt.lqv + ft.fv),
                         vq = weight(j) * lt.lqv.transpose(), vv = weight(j) / h * lt.lvv;
            if (p_.free_time) {
                // dE_i/dh = w_j [ℓ_i (L_q + f) − ℓ_i (L_qv + f_v) v − ℓ_i'/h L_vv v], v = V/h
                // (an autonomous system: t = (k + c_j) h is not differentiated); dT = N dh.
                const vec<D> along = weight(j) * (lt.lq + ft.f - (lt.lqv + ft.fv) * v),
                             across = -weight(j) / h * (lt.lvv * v);
                for (int i = 0; i <= s_; ++i)
                    for (int a = 0; a < D; ++a)
                        values[blocks + static_cast<std::size_t>((k * s_ + i) * D + a)] +=
                            (tab_.phi(i, j) * along(a) + tab_.dphi(i, j) * across(a)) / n_;
            }
            for (int i = 0; i <= s_; ++i) {
                const double pi = tab_.phi(i, j), di = tab_.dphi(i, j);
                for (int m = 0; m <= s_; ++m) {
                    const double pm = tab_.phi(m, j), dm = tab_.dphi(m, j);
                    bq.block<D, D>(i * D, m * D) +=
                        pi * pm * qq + pi * dm * qv + di * pm * vq + di * dm * vv;
                }
                bu.block<D, M>(i * D, j * M) += hw * pi * ft.fu;
            }
        }
        for (int row = 0; row < w; ++row)
            for (int col = 0; col < w; ++col)
                values[at++] = bq(row, col);
        for (int row = 0; row < w; ++row)
            for (int col = 0; col < r_ * M; ++col)
                values[at++] = bu(row, col);
    }
    add_constraint_jacobian(x, nullptr, &values);
}

/// σ ∇²J + Σ_g λ_gᵀ ∇²E_g: each quadrature point's h w_j ψ with ψ = aᵀ(∂L/∂q + f) +
/// (b/h)ᵀ ∂L/∂q̇, a = Σ_i ℓ_i(c_j) λ_{ks+i}, b = Σ_i ℓ_i'(c_j) λ_{ks+i}, pulled back to
/// (Q_{ks} … Q_{ks+s}, u_kj) through z = (q, v, u) = G (Q, u).
template <lagrangian L, control_force F, class C>
void dmoc<L, F, C>::hessian(cvector x, double sigma, cvector lambda,
                            std::vector<double>& values) const {
    const double h = h_of(x);
    const int w = (s_ + 1) * D + r_ * M, wq = (s_ + 1) * D;
    values.assign(static_cast<std::size_t>(n_) * static_cast<std::size_t>(w * (w + 1) / 2), 0.0);
    Eigen::MatrixXd hk(w, w), g = Eigen::MatrixXd::Zero(2 * D + M, w);
    Eigen::Matrix<double, 2 * D + M, 2 * D + M> hz;
    std::size_t at = 0;
    for (int k = 0; k < n_; ++k) {
        hk.setZero();
        for (int j = 0; j < r_; ++j) {
            vec<D> q, v, a = vec<D>::Zero(), b = vec<D>::Zero();
            point(x, k, j, q, v);
            for (int i = 0; i <= s_; ++i) {
                a += tab_.phi(i, j) * lambda.segment<D>((k * s_ + i) * D);
                b += tab_.dphi(i, j) / h * lambda.segment<D>((k * s_ + i) * D);
            }
            const double t = (k + tab_.quad.nodes[static_cast<std::size_t>(j)]) * h;
            const vec<M> u = x.segment<M>(control_index(k * r_ + j));
            typename cost_type::zmat hc;
            (void)cost_type::evaluate(l_, f_, p_.cost, p_.effort, q, v, t, u, nullptr, &hc);
            hz = contracted_force_hessian(f_, q, v, t, u, a) + sigma * hc;
            hz.template topLeftCorner<2 * D, 2 * D>() += contracted_third(l_, q, v, t, a, b);
            g.setZero();
            for (int l = 0; l <= s_; ++l) {
                g.block<D, D>(0, l * D).diagonal().setConstant(tab_.phi(l, j));
                g.block<D, D>(D, l * D).diagonal().setConstant(tab_.dphi(l, j) / h);
            }
            g.block<M, M>(2 * D, wq + j * M).setIdentity();
            hk.noalias() += h * weight(j) * (g.transpose() * hz * g);
        }
        for (int row = 0; row < w; ++row)
            for (int col = 0; col <= row; ++col)
                values[at++] = hk(row, col);
    }
    if (free_end_) {
        // −λ_Nᵀ ∂L/∂q̇(Q_{Ns}, v_N) and σ times the terminal cost, over (Q_{Ns}, v_N).
        const vec<D> lambda_end = lambda.segment<D>((points_ - 1) * D);
        mat<2 * D> he = contracted_third(l_, vec<D>(x.segment<D>((points_ - 1) * D)),
                                         vec<D>(x.segment<D>(end_velocity_index())), n_ * h,
                                         vec<D>::Zero(), vec<D>(-lambda_end));
        he.diagonal() +=
            sigma *
            (vec<2 * D>() << p_.cost.terminal_position, p_.cost.terminal_velocity).finished();
        for (int row = 0; row < 2 * D; ++row)
            for (int col = 0; col <= row; ++col)
                values.push_back(he(row, col));
    }
    add_constraint_hessian(x, lambda, nullptr, &values);
}

/// The trajectory of a solver's result (its last iterate if it did not converge).
template <lagrangian L, control_force F, class C>
trajectory dmoc<L, F, C>::unpack(const nlp_result& result) const {
    const vector& x = result.x;
    if (x.size() != variables())
        throw std::invalid_argument("unpack: the result has " + std::to_string(x.size()) +
                                    " unknowns, the transcription " + std::to_string(variables()) +
                                    " (" + result.message + ")");
    const double h = h_of(x);
    trajectory out;
    out.scheme = p_.scheme;
    out.h = h;
    out.degree = s_;
    out.control_nodes = tab_.control;
    out.cost = cost(x);
    out.points.resize(D, points_);
    for (int g = 0; g < points_; ++g)
        out.points.col(g) = x.segment<D>(g * D);
    out.node_times.resize(n_ + 1);
    out.q.resize(D, n_ + 1);
    out.p.resize(D, n_ + 1);
    out.v.resize(D, n_ + 1);
    out.costate.resize(D, n_ + 1);
    // p_{k+1} = D₂L_d + f⁺: step k's contribution to its end node's equation.
    vector e_end = vector::Zero(constraints());
    add_step_equations(x, e_end, true);
    const lagrangian_system<L> sys(l_);
    for (int n = 0; n <= n_; ++n) {
        out.node_times(n) = n * h;
        out.q.col(n) = x.segment<D>(n * s_ * D);
        out.p.col(n) = n == 0 ? vec<D>(p_start_) : vec<D>(e_end.segment<D>(n * s_ * D));
        out.v.col(n) = sys.velocity(vec<D>(out.q.col(n)), vec<D>(out.p.col(n)), n * h);
        if (K > 0 && n > 0) {
            vec<D> p = out.p.col(n), v = out.v.col(n);
            tangent_node(out.q.col(n), p, v, n * h);
            out.p.col(n) = p;
            out.v.col(n) = v;
        }
        if (result.lambda.size() == constraints())
            out.costate.col(n) = -result.lambda.segment<D>(n * s_ * D);
        else
            out.costate.col(n).setConstant(std::nan(""));
    }
    out.control_times.resize(n_ * r_);
    out.u.resize(M, n_ * r_);
    for (int k = 0; k < n_; ++k)
        for (int j = 0; j < r_; ++j) {
            out.control_times(k * r_ + j) = (k + tab_.quad.nodes[static_cast<std::size_t>(j)]) * h;
            out.u.col(k * r_ + j) = x.segment<M>(control_index(k * r_ + j));
        }
    return out;
}

} // namespace varsym::optimal
