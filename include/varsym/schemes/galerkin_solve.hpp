// varsym/schemes/galerkin_solve.hpp: how the family stepper (galerkin.hpp) solves a step's
// equations: its residual and Jacobian, and the Newton, simplified-Newton and fixed-point
// iterations on them (docs/design.md, "Solving the step"). Included by galerkin.hpp.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "varsym/schemes/galerkin.hpp"

namespace varsym::galerkin {

namespace detail {
/// out = ∇V(q), written through `scratch` where the potential writes in place
/// (in_place_gradient): at a run-time d no vector is then allocated.
template <class P, int D, class Out>
void gradient_to(const P& v, const vec<D>& q, vec<D>& scratch, Out&& out) {
    if constexpr (in_place_gradient<P, D>) {
        v.gradient(q, scratch);
        out = scratch;
    } else {
        out = v.gradient(q);
    }
}
} // namespace detail

template <separable System>
newton_report stepper<System>::solve(const phase_state<dim>& x, iteration_kind kind,
                                     bool continues) {
    const bool simplified = kind == iteration_kind::simplified;
    bool fresh = false;
    if (simplified && !jac_kept_) {
        factor(x.q);
        fresh = true;
    }
    newton_report rep = iterate(x, kind, continues);
    if (simplified && !fresh && !rep.converged) {
        const int spent = rep.iterations;
        factor(x.q);
        rep = iterate(x, kind, continues);
        rep.iterations += spent;
    }
    if (simplified) jac_kept_ = rep.converged && rate_ <= opt_.contraction_limit;
    return rep;
}

template <separable System>
newton_report stepper<System>::iterate(const phase_state<dim>& x, iteration_kind kind,
                                       bool continues) {
    const int s = s_, d = sys_.dimension();
    predict(x, continues);
    newton_options opt = opt_;
    opt.typical = xm_.template lpNorm<Eigen::Infinity>();
    opt.reference = x.q.template lpNorm<Eigen::Infinity>();
    const bool newton = kind == iteration_kind::newton;
    newton_monitor monitor(opt, !newton);
    newton_report rep;
    rate_ = 0.0;
    // The fixed point sweeps in closed form (tableau::sweep: one s × r product) until the updates'
    // contraction predicts the rest below round-off, then closes with one sweep whose tables
    // carry their low parts, so that it lands on the exact equations' root (docs/design.md,
    // "Solving the step").
    const bool fixed = kind == iteration_kind::fixed_point;
    bool closing = false;
    double last = std::numeric_limits<double>::infinity();
    // A fixed point that gives up reports the residual where it stopped.
    const auto unsolved = [&] {
        if (fixed) {
            residual(x, false);
            rep.residual = res_.template lpNorm<Eigen::Infinity>();
        }
        return rep;
    };
    while (true) {
        Eigen::Map<stage_matrix> dm(delta_.data(), d, s);
        if (monitor.exhausted()) return unsolved();
        double step = 0.0, size = 0.0;
        bool swept = false;
        if constexpr (dim == 1) {
            if (fixed && !closing) {
                step = scalar_sweep(x, size);
                swept = true;
            }
        }
        if (!swept) {
            if (fixed) {
                gradients(x, false);
                closed_form(mx_, closing);
                dm = xm_ - mx_;
            } else {
                residual(x, newton);
                rep.residual = res_.template lpNorm<Eigen::Infinity>();
                if (!newton) {
                    delta_.noalias() = jinv_ * res_;
                } else {
                    jacobian();
                    linear_solve();
                }
            }
            step = delta_.template lpNorm<Eigen::Infinity>();
        }
        rep.iterations = monitor.iterations() + 1;
        if (!std::isfinite(step) || !std::isfinite(rep.residual)) return rep;
        if (!swept) {
            if (fixed)
                xm_ = mx_;
            else
                xm_ -= dm;
            size = xm_.template lpNorm<Eigen::Infinity>();
        }
        const bool done = monitor.converged(step, size);
        if (fixed) {
            // Linear convergence at rate ρ = step/last leaves ρ/(1 − ρ) step to go. The closing
            // sweep is taken when that, contracted once more, is below round-off, and accepted
            // when its own update bears that out (else the exact sweeps go on). After one sweep
            // from the forces predictor, the last step's rate (doubled) stands in for ρ.
            const bool carried = monitor.iterations() == 1 && continues && carried_rate_ > 0.0 &&
                                 opt_.predictor == predictor_kind::forces;
            const double rho = carried ? 2.0 * carried_rate_ : step / last;
            const double floor = opt.tolerance * std::max(size, opt.typical);
            const bool measured = carried || monitor.iterations() > 1;
            if (monitor.iterations() > 1 && monitor.rate() > 0.0) carried_rate_ = monitor.rate();
            if (closing && (done || (rho < 0.5 && step * rho <= (1.0 - rho) * floor))) break;
            closing = closing || done ||
                      (measured && rho < 0.5 && step * rho * rho <= (1.0 - rho) * floor);
            last = step;
        } else if (done) {
            break;
        }
        if (!newton && monitor.iterations() > 1) {
            rate_ = std::max(rate_, monitor.rate());
            // Diverging, or so slow that Newton is cheaper: Newton takes over.
            if (monitor.rate() > 0.5) return unsolved();
        }
    }
    rep.converged = true;
    return rep;
}

template <separable System>
void stepper<System>::linear_solve() {
    [[maybe_unused]] const bool small = varsym::detail::solve_small(
        n_, jac_.data(), jac_.outerStride(), res_.data(), delta_.data());
    if constexpr (needs_lu) {
        if (!small) {
            lu_.compute(jac_);
            delta_.noalias() = lu_.solve(res_);
        }
    }
}

template <separable System>
void stepper<System>::factor(const vec<dim>& q_bar) {
    q_bar_ = q_bar;
    const mat<dim> hbar = sys_.potential().hessian(q_bar_);
    for (int a = 0; a < n_active_; ++a)
        hess_[active_[a]] = hbar;
    jacobian();
    if (n_ <= varsym::detail::small_solve_limit) {
        for (int c = 0; c < n_; ++c) {
            res_.setZero();
            res_(c) = 1.0;
            varsym::detail::solve_small(n_, jac_.data(), jac_.outerStride(), res_.data(),
                                        jinv_.col(c).data());
        }
    } else if constexpr (needs_lu) {
        lu_.compute(jac_);
        jinv_ = lu_.inverse();
    }
    jac_kept_ = true;
}

template <separable System>
void stepper<System>::gradients(const phase_state<dim>& x, bool hessians) {
    const auto& v = sys_.potential();
    for (int k = 0; k < r_; ++k) {
        if (at_start_[k])
            grads_.col(k) = grad_j_;
        else
            grads_.col(k).setZero();
    }
    if constexpr (batched) {
        if (!hessians) { // the points first, then ∇V at all of them in one call
            for (int a = 0; a < n_active_; ++a)
                detail::add_combination(points_.col(a), x.q, xm_, v_.col(active_[a]));
            active_gradients();
            return;
        }
    }
    for (int a = 0; a < n_active_; ++a) {
        const int k = active_[a];
        detail::add_combination(qk_, x.q, xm_, v_.col(k));
        detail::gradient_to(v, qk_, gk_, grads_.col(k));
        if (hessians) hess_[k] = v.hessian(qk_);
    }
}

template <separable System>
void stepper<System>::active_gradients() {
    sys_.potential().gradients(points_.data(), n_active_, batch_.data());
    for (int a = 0; a < n_active_; ++a)
        grads_.col(active_[a]) = batch_.col(a);
}

template <separable System>
bool stepper<System>::converged_gradients(const phase_state<dim>& x) {
    const auto& v = sys_.potential();
    bool has_end = false;
    int n = 0; // points evaluated by a batch_potential, in points_'s first columns
    for (int k = 0; k < r_; ++k) {
        auto g = previous_grads_.col(k);
        if (at_end_[k]) {
            qk_ = x.q; // ∇V(q_{j+1}), the next step's ∇V(q_j)
            has_end = true;
        } else if (at_start_[k]) {
            g = grad_j_;
            continue;
        } else {
            detail::add_combination(qk_, q_j_, xm_, v_.col(k));
        }
        if constexpr (batched)
            points_.col(n++) = qk_;
        else
            detail::gradient_to(v, qk_, gk_, g);
    }
    if constexpr (batched) {
        v.gradients(points_.data(), n, batch_.data());
        for (int k = 0, a = 0; k < r_; ++k)
            if (!at_start_[k]) previous_grads_.col(k) = batch_.col(a++);
    }
    return has_end;
}

template <separable System>
double stepper<System>::scalar_sweep(const phase_state<dim>& x, double& size) {
    // gradients(x, false), closed_form(mx_, false) and xm_ = mx_ for d = 1 on raw entries, in
    // the same order of operations (so the same roundings), with the sizes, the step and the
    // tables' strides in locals: the writes through raw pointers would otherwise make the
    // compiler reload every member at every entry.
    const auto& v = sys_.potential();
    const int s = s_, r = r_;
    const double h = h_, q = x.q(0);
    const double* basis = v_.data();
    const Eigen::Index basis_stride = v_.outerStride();
    const double* sweep = sweep_t_.data();
    const Eigen::Index sweep_stride = sweep_t_.outerStride();
    double* g = grads_.data();
    double* xs = xm_.data();
    for (int k = 0; k < r; ++k)
        g[k] = at_start_[k] ? grad_j_(0) : 0.0;
    for (int a = 0; a < n_active_; ++a) {
        const int k = active_[a];
        const double* column = basis + k * basis_stride;
        double point = q;
        for (int l = 0; l < s; ++l)
            point += column[l] * xs[l];
        if constexpr (batched) {
            points_(0, a) = point;
        } else {
            qk_(0) = point;
            if constexpr (in_place_gradient<std::remove_cvref_t<decltype(v)>, dim>) {
                v.gradient(qk_, gk_);
                g[k] = gk_(0);
            } else {
                g[k] = v.gradient(qk_)(0);
            }
        }
    }
    if constexpr (batched) active_gradients(); // into grads_, whose entries g points at
    double minv = 0.0;
    if constexpr (scalar_mass<System>)
        minv = sys_.inverse_mass();
    else
        minv = diagonal_mass_ ? inverse_mass_diagonal_(0) : sys_.inverse_mass()(0, 0);
    const double flight = h * vel_(0);
    double step = 0.0, largest = 0.0;
    bool finite = true;
    for (int l = 0; l < s; ++l) {
        double sum = sweep[l] * g[0];
        for (int k = 1; k < r; ++k)
            sum += sweep[l + k * sweep_stride] * g[k];
        const double out = minv * (h * (h * sum)) + flight_[l] * flight;
        finite = finite && std::isfinite(out);
        step = std::max(step, std::abs(xs[l] - out));
        largest = std::max(largest, std::abs(out));
        xs[l] = out;
    }
    size = largest;
    return finite ? step : std::numeric_limits<double>::quiet_NaN();
}

template <separable System>
void stepper<System>::residual(const phase_state<dim>& x, bool hessians) {
    const int s = s_, d = sys_.dimension();
    gradients(x, hessians);
    Eigen::Map<stage_matrix> rm(res_.data(), d, s);
    apply_mass<false>(mx_, xm_);
    // The tables' products summed with compensation, their low parts' products added once
    // (detail::times_transpose_compensated): A's and U's rows cancel against increments and
    // gradients that change little across a step, and a plain sum's rounding tilted the energy.
    detail::times_transpose_compensated(rm, mx_, a_, a_lo_);
    rm *= hinv_;
    detail::times_transpose_compensated(gu_, grads_, u_, u_lo_);
    rm.noalias() -= h_ * gu_;
    rm.col(0) += x.p;
}

template <separable System>
void stepper<System>::jacobian() {
    const int s = s_, d = sys_.dimension();
    if (d == 1) {
        curvature_.setZero();
        for (int a = 0; a < n_active_; ++a)
            curvature_(active_[a]) = hess_[active_[a]](0, 0);
        for (int i = 0; i < s; ++i)
            for (int l = 0; l < s; ++l) {
                double c = 0.0;
                for (int a = 0; a < n_active_; ++a)
                    c += u_(i, active_[a]) * curvature_(active_[a]) * v_(l, active_[a]);
                jac_(i, l) = hinv_ * mass_entry() * a_(i, l) - h_ * c;
            }
        return;
    }
    for (int i = 0; i < s; ++i)
        for (int l = 0; l < s; ++l) {
            auto block = block_of<dim>(jac_, i, l, d);
            if constexpr (scalar_mass<System>) {
                block.setZero();
                block.diagonal().setConstant(hinv_ * a_(i, l) * sys_.mass());
            } else {
                block = (hinv_ * a_(i, l)) * sys_.mass();
            }
            for (int a = 0; a < n_active_; ++a) {
                const int k = active_[a];
                const double c = h_ * u_(i, k) * v_(l, k);
                if (c != 0.0) block -= c * hess_[k];
            }
        }
}

} // namespace varsym::galerkin
