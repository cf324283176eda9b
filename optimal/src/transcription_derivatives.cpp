// optimal/src/transcription_derivatives.cpp: the equations of the DMOC transcription
// (transcription.hpp), their sparse Jacobian and the Hessian of the Lagrangian, and the
// trajectory of a result. See transcription.hpp for the unknowns and equations.
#include <cassert>

#include <Eigen/LU>

#include "step_threads.hpp"
#include "varsym/optimize/transcription.hpp"

namespace varsym::optimal {

void dmoc_transcription::residual(cvector x, vector& e) const {
    e.setZero(constraints());
    add_step_equations(x, e, false);
    e.head(d_) += p_start_;                               // p_0 = −D₁L_d − f⁻
    e.segment((points_ - 1) * d_, d_) -= end_momentum(x); // p_N = D₂L_d + f⁺
    add_constraint_residual(x, e);
    add_target_residual(x, e);
    add_path_residual(x, e);
    add_node_residual(x, e);
}

/// Adds each step's terms to the equations of its control values (the discrete forced
/// Euler–Lagrange equations), or, if `end_only`, to its last control value's only: then e holds
/// p_{k+1} = D₂L_d + f⁺ at the nodes, the discrete Legendre transform (unpack).
void dmoc_transcription::add_step_equations(cvector x, vector& e, bool end_only) const {
    const double h = h_of(x);
    lagrangian_terms<dynamic> lt;
    input_terms ft;
    vector q, v, lq, lv, u(m_);
    for (int k = 0; k < n_; ++k)
        for (int j = 0; j < r_; ++j) {
            point(x, k, j, q, v);
            const double t = point_time(k, j, h);
            u = x.segment(control_index(k * r_ + j), m_);
            sys_->gradient(q, v, t, lt);
            sys_->force(q, v, t, u, ft, false);
            lq = h * weight(j) * (lt.lq + ft.f);
            lv = weight(j) * lt.lv;
            for (int i = end_only ? s_ : 0; i <= s_; ++i)
                e.segment(row_of(k, i), d_) += tab_.phi(i, j) * lq + tab_.dphi(i, j) * lv;
        }
}

sparsity dmoc_transcription::jacobian_pattern() const {
    sparsity s;
    const int w = (s_ + 1) * d_;
    for (int k = 0; k < n_; ++k) {
        for (int row = 0; row < w; ++row)
            for (int col = 0; col < w; ++col)
                s.add(row_of(k, row / d_) + row % d_, k * s_ * d_ + col);
        for (const auto& [row, col] : control_jacobian_)
            s.add(row_of(k, row / d_) + row % d_, control_index(k * r_) + col);
    }
    if (p_.free_time) // ∂E/∂T: every equation depends on h = T/N
        for (int row = 0; row < constraints(); ++row)
            s.add(row, time_index());
    for (int row = 0; free_end_ && row < d_; ++row) // −∂L/∂q̇(Q_{Ns}, v_N)
        for (int col = 0; col < 2 * d_; ++col)
            s.add((points_ - 1) * d_ + row, end_index(col));
    add_constraint_jacobian(vector(), &s, nullptr);
    add_target_jacobian(vector(), &s, nullptr);
    add_path_jacobian(vector(), &s, nullptr);
    add_node_jacobian(vector(), &s, nullptr);
    return s;
}

int dmoc_transcription::evaluation_threads() const {
    // One thread with a free final time (its column sums over neighbouring steps), or a system
    // that is not concurrent (a typed Lagrangian's tape). Automatic: at most one thread per
    // 2048 units of r d² a step (a robot's step costs about 0.2 µs a unit: the iiwa's, d = 7, 18
    // µs with gauss-2), so that each part is worth waking a worker for.
    if (threads_ == 1 || p_.free_time || !sys_->concurrent()) return 1;
    if (threads_ > 1) return std::min(threads_, n_);
    const long long work = 1LL * n_ * r_ * d_ * d_;
    return static_cast<int>(
        std::max(1LL, std::min({static_cast<long long>(detail::available_cpus()),
                                static_cast<long long>(n_), work / 2048})));
}

void dmoc_transcription::jacobian(cvector x, std::vector<double>& values) const {
    const double h = h_of(x);
    const std::size_t blocks = step_jacobian_size();
    const std::size_t end = blocks + (p_.free_time ? static_cast<std::size_t>(constraints()) : 0);
    values.assign(end + (free_end_ ? static_cast<std::size_t>(2 * d_ * d_) : 0), 0.0);
    lagrangian_terms<dynamic> lt;
    if (free_end_) { // −∂L/∂q̇(Q_{Ns}, v_N): −L_q̇q, −L_q̇q̇
        sys_->derivatives(x.segment((points_ - 1) * d_, d_), x.segment(end_velocity_index(), d_),
                          n_ * h, lt);
        for (int row = 0; row < d_; ++row)
            for (int col = 0; col < 2 * d_; ++col)
                values[end + static_cast<std::size_t>(row * 2 * d_ + col)] =
                    col < d_ ? -lt.lqv(col, row) : -lt.lvv(row, col - d_);
    }
    detail::over_steps(n_, evaluation_threads(),
                       [&](int first, int last) { step_jacobians(x, h, first, last, values); });
    add_constraint_jacobian(x, nullptr, &values);
    add_target_jacobian(x, nullptr, &values);
    add_path_jacobian(x, nullptr, &values);
    add_node_jacobian(x, nullptr, &values);
}

/// Steps first … last − 1 of jacobian(): each its own block of values, and with a free final
/// time (one thread only) the time's column.
void dmoc_transcription::step_jacobians(cvector x, double h, int first, int last,
                                        std::vector<double>& values) const {
    assert(!p_.free_time || (first == 0 && last == n_)); // the column sums across steps
    const int w = (s_ + 1) * d_;
    const std::size_t blocks = step_jacobian_size();
    std::size_t at = static_cast<std::size_t>(first) *
                     (static_cast<std::size_t>(w * w) + control_jacobian_.size());
    lagrangian_terms<dynamic> lt;
    matrix bq(w, w), bu(w, r_ * m_), qq, qv, vq, vv;
    input_terms ft;
    vector q, v, u(m_);
    for (int k = first; k < last; ++k) {
        bq.setZero();
        bu.setZero();
        for (int j = 0; j < r_; ++j) {
            point(x, k, j, q, v);
            const double t = point_time(k, j, h);
            sys_->derivatives(q, v, t, lt);
            u = x.segment(control_index(k * r_ + j), m_);
            sys_->force(q, v, t, u, ft, true);
            const double hw = h * weight(j);
            qq = hw * (lt.lqq + ft.fq);
            qv = weight(j) * (lt.lqv + ft.fv);
            vq = weight(j) * lt.lqv.transpose();
            vv = weight(j) / h * lt.lvv;
            if (p_.free_time) {
                // dE_i/dh = w_j [ℓ_i (L_q + f) − ℓ_i (L_qv + f_v) v − ℓ_i'/h L_vv v], v = V/h
                // (an autonomous system: t = (k + c_j) h is not differentiated); dT = N dh.
                const vector along = weight(j) * (lt.lq + ft.f - (lt.lqv + ft.fv) * v),
                             across = -weight(j) / h * (lt.lvv * v);
                for (int i = 0; i <= s_; ++i)
                    for (int a = 0; a < d_; ++a)
                        values[blocks + static_cast<std::size_t>(row_of(k, i) + a)] +=
                            (tab_.phi(i, j) * along(a) + tab_.dphi(i, j) * across(a)) / n_;
            }
            for (int i = 0; i <= s_; ++i) {
                const double pi = tab_.phi(i, j), di = tab_.dphi(i, j);
                for (int l = 0; l <= s_; ++l) {
                    const double pl = tab_.phi(l, j), dl = tab_.dphi(l, j);
                    bq.block(i * d_, l * d_, d_, d_) +=
                        pi * pl * qq + pi * dl * qv + di * pl * vq + di * dl * vv;
                }
                bu.block(i * d_, j * m_, d_, m_) += hw * pi * ft.fu;
            }
        }
        for (int row = 0; row < w; ++row)
            for (int col = 0; col < w; ++col)
                values[at++] = bq(row, col);
        for (const auto& [row, col] : control_jacobian_)
            values[at++] = bu(row, col);
    }
}

/// Each step's block over its control values and its controls, its lower triangle's
/// structural non-zeros (step_hessian_, transcription_structure.cpp); with a free final state,
/// the lower triangle of the block over (Q_{Ns}, v_N).
sparsity dmoc_transcription::hessian_pattern() const {
    sparsity s;
    for (int k = 0; k < n_; ++k)
        for (const auto& [row, col] : step_hessian_)
            s.add(step_index(k, row), step_index(k, col));
    for (int row = 0; free_end_ && row < 2 * d_; ++row)
        for (int col = 0; col <= row; ++col)
            s.add(end_index(row), end_index(col));
    add_constraint_hessian(vector(), vector(), &s, nullptr);
    add_node_hessian(vector(), vector(), &s, nullptr);
    add_time_hessian(vector(), vector(), nullptr, &s, nullptr);
    return s;
}

/// σ ∇²J + Σ_g λ_gᵀ ∇²E_g: each quadrature point's h w_j ψ with ψ = aᵀ(∂L/∂q + f) +
/// (b/h)ᵀ ∂L/∂q̇, a = Σ_i ℓ_i(c_j) λ_{ks+i}, b = Σ_i ℓ_i'(c_j) λ_{ks+i}, pulled back to
/// (Q_{ks} … Q_{ks+s}, u_kj) through z = (q, v, u) = G (Q, u).
void dmoc_transcription::hessian(cvector x, double sigma, cvector lambda,
                                 std::vector<double>& values) const {
    const double h = h_of(x);
    values.assign(static_cast<std::size_t>(n_) * step_hessian_.size(), 0.0);
    vector time_row; // a free final time's row (one thread: it sums over the steps)
    if (p_.free_time) time_row.setZero(variables());
    detail::over_steps(n_, evaluation_threads(), [&](int first, int last) {
        step_hessians(x, sigma, lambda, h, first, last, values, p_.free_time ? &time_row : nullptr);
    });
    if (free_end_) {
        // −λ_Nᵀ ∂L/∂q̇(Q_{Ns}, v_N) and σ times the terminal cost, over (Q_{Ns}, v_N).
        const vector lambda_end = lambda.segment((points_ - 1) * d_, d_);
        matrix he;
        sys_->third(x.segment((points_ - 1) * d_, d_), x.segment(end_velocity_index(), d_), n_ * h,
                    vector::Zero(d_), -lambda_end, he);
        vector diag(2 * d_);
        diag << p_.cost.terminal_position, p_.cost.terminal_velocity;
        he.diagonal() += sigma * diag;
        add_target_hessian(x, sigma, lambda, he);
        for (int row = 0; row < 2 * d_; ++row)
            for (int col = 0; col <= row; ++col)
                values.push_back(he(row, col));
    }
    add_constraint_hessian(x, lambda, nullptr, &values);
    add_node_hessian(x, lambda, nullptr, &values);
    add_time_hessian(x, lambda, &time_row, nullptr, &values);
}

/// Steps first … last − 1 of hessian(): each its own block of values, and with a free final
/// time (one thread only) their terms of its row.
void dmoc_transcription::step_hessians(cvector x, double sigma, cvector lambda, double h, int first,
                                       int last, std::vector<double>& values,
                                       vector* time_row) const {
    assert(!time_row || (first == 0 && last == n_));
    const int w = (s_ + 1) * d_ + r_ * m_, wq = (s_ + 1) * d_;
    matrix hk(w, w), hz, hc, third;
    vector q, v, a, b, u(m_), gc;
    std::size_t at = static_cast<std::size_t>(first) * step_hessian_.size();
    for (int k = first; k < last; ++k) {
        hk.setZero();
        for (int j = 0; j < r_; ++j) {
            point(x, k, j, q, v);
            a.setZero(d_);
            b.setZero(d_);
            for (int i = 0; i <= s_; ++i) {
                a += tab_.phi(i, j) * lambda.segment(row_of(k, i), d_);
                b += tab_.dphi(i, j) / h * lambda.segment(row_of(k, i), d_);
            }
            const double t = point_time(k, j, h);
            u = x.segment(control_index(k * r_ + j), m_);
            (void)running_cost_at(*sys_, p_.cost, p_.effort, q, v, t, u, time_row ? &gc : nullptr,
                                  &hc);
            sys_->force_hessian(q, v, t, u, a, hz);
            hz += sigma * hc;
            sys_->third(q, v, t, a, b, third);
            hz.topLeftCorner(2 * d_, 2 * d_) += third;
            hz *= h * weight(j);
            if (time_row) add_time_point({q, v, u, gc, a, b, t}, sigma, k, j, h, hz, *time_row);
            // Gᵀ hz G block by block: z = (q, v, u) = (Σ ℓ_l Q_l, Σ ℓ_l'/h Q_l, u_kj), so the
            // (l, m) block over (Q_l, Q_m) is Σ of the four (q, v) blocks of hz weighted by
            // ℓ_l or ℓ_l'/h and ℓ_m or ℓ_m'/h; (Q_l, u_kj) likewise; (u_kj, u_kj) is hz's.
            const int wu = wq + j * m_;
            for (int l = 0; l <= s_; ++l) {
                const double pl = tab_.phi(l, j), dl = tab_.dphi(l, j) / h;
                for (int mm = 0; mm <= l; ++mm) {
                    const double pm = tab_.phi(mm, j), dm = tab_.dphi(mm, j) / h;
                    hk.block(l * d_, mm * d_, d_, d_) +=
                        pl * pm * hz.topLeftCorner(d_, d_) + pl * dm * hz.block(0, d_, d_, d_) +
                        dl * pm * hz.block(d_, 0, d_, d_) + dl * dm * hz.block(d_, d_, d_, d_);
                }
                hk.block(wu, l * d_, m_, d_) +=
                    pl * hz.block(2 * d_, 0, m_, d_) + dl * hz.block(2 * d_, d_, m_, d_);
            }
            hk.block(wu, wu, m_, m_) += hz.bottomRightCorner(m_, m_);
        }
        for (const auto& [row, col] : step_hessian_)
            values[at++] = hk(row, col);
    }
}

namespace {

/// q̇ with ∂L/∂q̇(q, q̇, t) = p, by Newton's iteration from q̇ = M(q, 0)⁻¹ p (exact in one step for
/// L quadratic in q̇).
vector velocity_of(const controlled_system& s, const vector& q, const vector& p, double t) {
    vector v = vector::Zero(q.size());
    lagrangian_terms<dynamic> lt;
    for (int it = 0; it < 50; ++it) {
        s.derivatives(q, v, t, lt);
        const vector r = lt.lv - p;
        if (it > 0 &&
            r.lpNorm<Eigen::Infinity>() <= 1e-14 * std::max(1.0, p.lpNorm<Eigen::Infinity>()))
            break;
        v -= lt.lvv.partialPivLu().solve(r);
    }
    return v;
}

} // namespace

trajectory dmoc_transcription::unpack(const nlp_result& result) const {
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
    out.points.resize(d_, points_);
    for (int g = 0; g < points_; ++g)
        out.points.col(g) = x.segment(g * d_, d_);
    out.node_times.resize(n_ + 1);
    out.q.resize(d_, n_ + 1);
    out.p.resize(d_, n_ + 1);
    out.v.resize(d_, n_ + 1);
    out.costate.resize(d_, n_ + 1);
    // p_{k+1} = D₂L_d + f⁺: step k's contribution to its end node's equation.
    vector e_end = vector::Zero(constraints());
    add_step_equations(x, e_end, true);
    for (int n = 0; n <= n_; ++n) {
        out.node_times(n) = n * h;
        const vector q = x.segment(n * s_ * d_, d_);
        vector p = n == 0 ? p_start_ : vector(e_end.segment(n * s_ * d_, d_));
        vector v = velocity_of(*sys_, q, p, n * h);
        if (k_ > 0 && n > 0) sys_->tangent(q, p, v, n * h);
        out.q.col(n) = q;
        out.p.col(n) = p;
        out.v.col(n) = v;
        if (result.lambda.size() == constraints())
            out.costate.col(n) = -result.lambda.segment(n * s_ * d_, d_);
        else
            out.costate.col(n).setConstant(std::nan(""));
    }
    out.control_times.resize(n_ * r_);
    out.u.resize(m_, n_ * r_);
    for (int k = 0; k < n_; ++k)
        for (int j = 0; j < r_; ++j) {
            out.control_times(k * r_ + j) = point_time(k, j, h);
            out.u.col(k * r_ + j) = control(x, k, j);
        }
    return out;
}

} // namespace varsym::optimal
