// varsym/systems/forcing.hpp: generalized forces f(q, q̇, t) (non-conservative forces, joint
// torques, controls), which the general engine adds by the discrete Lagrange–d'Alembert
// principle (schemes/variational.hpp; docs/mechanisms.md). Like a Lagrangian, a force is written
// once, templated on the scalar type, and differentiated automatically, or gives its derivatives
// by hand. Built in: Rayleigh damping, a PD controller tracking a reference trajectory (with
// optional gravity compensation), a prescribed force schedule u(t), and sums of these.
#pragma once

#include <algorithm>
#include <concepts>
#include <functional>
#include <stdexcept>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

#include "varsym/autodiff/second_order.hpp"
#include "varsym/systems/lagrangian.hpp"
#include "varsym/types.hpp"

namespace varsym {

/// A force's value and Jacobians at one point: fq(i, j) = ∂f_i/∂q_j, fv(i, j) = ∂f_i/∂q̇_j.
template <int D>
struct force_terms {
    vec<D> f;
    mat<D> fq, fv;
};

/// What a generalized force must provide: `static constexpr int dim` (as its Lagrangian's) and
/// `template <class T> tvec<T, D> operator()(const tvec<T, D>& q, const tvec<T, D>& v, double t)
/// const` returning the force conjugate to q (units of ∂L/∂q: N, N·m for an angle), callable
/// with T = double and the automatic-differentiation scalars (return a tvec<T, D>, not an Eigen
/// expression of local variables).
template <class F>
concept generalized_force = requires {
    F::dim;
}
&&requires(const F& f, const vec<F::dim>& q, double t) {
    { f(q, q, t) } -> std::convertible_to<vec<F::dim>>;
};

/// A force that also gives its value and Jacobians by hand in derivatives(q, v, t, terms), then
/// used instead of differentiation (a force of run-time dimension must).
template <class F>
concept force_with_derivatives = generalized_force<F> &&
    requires(const F& f, const vec<F::dim>& q, double t, force_terms<F::dim>& r) {
    f.derivatives(q, q, t, r);
};

/// A force that also gives its value alone, `value(q, v, t, out)` (out sized by the caller, no
/// allocation once sized): the Newton iterates that keep their Jacobian (chord updates), the
/// predictor and the momentum then evaluate no Jacobian of the force. The value is
/// derivatives()'s f: the same operations in the built-in forces, except a compensation's
/// ∂L/∂q, which takes L's path for first derivatives (the same operations as its second ones
/// for the robots, the arm and automatic derivatives up to dimension 8; round-off apart above).
template <class F>
concept force_with_value = generalized_force<F> &&
    requires(const F& f, const vec<F::dim>& q, double t, vec<F::dim>& out) {
    f.value(q, q, t, out);
};

/// The default force of the general engine: none (the conservative scheme, unchanged).
struct unforced {};

/// Whether a force is continuous in time along a smooth motion, and so has a rate: F declares
/// `static constexpr bool continuous_in_time = true` (damping, the PD controller, an expression
/// force, sums of them). A force that does not (a control held over each step, which jumps
/// between steps; a schedule u(t) of any kind) is taken to jump. Only a robot's Newton start
/// reads it (schemes/variational_solve.hpp): the jerk it extrapolates with includes the force's
/// rate. It is never the answer: a force that jumps anyway costs that step's start, not its
/// accuracy.
template <class F>
constexpr bool force_continuous_in_time() {
    if constexpr (requires { F::continuous_in_time; })
        return F::continuous_in_time;
    else
        return false;
}

/// Whether F is `unforced` or a generalized force of dimension D.
template <class F, int D>
constexpr bool force_for() {
    if constexpr (std::is_same_v<F, unforced>)
        return true;
    else if constexpr (generalized_force<F>)
        return F::dim == D;
    else
        return false;
}

/// Fills r with f(q, v, t) and, if `jacobian`, its Jacobians (by hand when the force gives them,
/// else by forward-mode automatic differentiation in the 2D variables (q, v)). r's members are
/// sized by the caller. A force with derivatives by hand fills all three, unless `jacobian` is
/// false and it gives its value alone (force_with_value): then r.f only, r.fq and r.fv as they
/// were.
template <generalized_force F>
void evaluate_force(const F& f, const vec<F::dim>& q, const vec<F::dim>& v, double t,
                    force_terms<F::dim>& r, bool jacobian) {
    constexpr int D = F::dim;
    if constexpr (force_with_value<F>) {
        if (!jacobian) {
            f.value(q, v, t, r.f);
            return;
        }
    }
    if constexpr (force_with_derivatives<F>) {
        f.derivatives(q, v, t, r);
    } else if (!jacobian) {
        r.f = f(q, v, t);
    } else {
        static_assert(D != dynamic, "automatic derivatives need a compile-time dimension: give a "
                                    "force of run-time dimension derivatives(q, v, t, terms)");
        constexpr int N = 2 * D;
        using J = ad::first_order<N>;
        tvec<J, D> qj, vj;
        for (int i = 0; i < D; ++i) {
            qj(i) = J(q(i), N, i);
            vj(i) = J(v(i), N, D + i);
        }
        const tvec<J, D> out = f(qj, vj, t);
        for (int i = 0; i < D; ++i) {
            r.f(i) = out(i).value();
            r.fq.row(i) = out(i).derivatives().template head<D>().transpose();
            r.fv.row(i) = out(i).derivatives().template tail<D>().transpose();
        }
    }
}

/// Rayleigh damping f = −C q̇, C symmetric positive semi-definite [N·s/m, or N·m·s/rad for an
/// angle]. It dissipates: f·q̇ = −q̇ᵀCq̇ ≤ 0.
template <int D>
struct rayleigh_damping {
    static constexpr int dim = D;
    static constexpr bool continuous_in_time = true;
    mat<D> c;

    explicit rayleigh_damping(mat<D> coefficients) : c(std::move(coefficients)) {
        if (!c.allFinite() || !c.isApprox(c.transpose()))
            throw std::invalid_argument("the damping matrix must be finite and symmetric");
    }
    /// Diagonal damping (one coefficient per coordinate; each ≥ 0).
    static rayleigh_damping diagonal(const vec<D>& coefficients) {
        if ((coefficients.array() < 0.0).any())
            throw std::invalid_argument("damping coefficients must be >= 0");
        return rayleigh_damping(mat<D>(coefficients.asDiagonal()));
    }
    [[nodiscard]] int dimension() const { return static_cast<int>(c.rows()); }
    vec<D> operator()(const vec<D>&, const vec<D>& v, double) const { return -(c * v); }
    void value(const vec<D>&, const vec<D>& v, double, vec<D>& out) const {
        out.noalias() = c * v; // then negated: −(C q̇) without a temporary for the product
        out = -out;
    }
    void derivatives(const vec<D>& q, const vec<D>& v, double t, force_terms<D>& r) const {
        value(q, v, t, r.f);
        r.fq.setZero(q.size(), q.size());
        r.fv = -c;
    }
};

/// A prescribed force u(t) that depends on time only (a torque schedule, an external load):
/// f = u(t). Its Jacobians are zero.
template <int D>
struct prescribed_force {
    static constexpr int dim = D;
    std::function<vec<D>(double)> u;
    int size = D == dynamic ? 0 : D;

    [[nodiscard]] int dimension() const { return size; }
    vec<D> operator()(const vec<D>&, const vec<D>&, double t) const { return u(t); }
    void derivatives(const vec<D>& q, const vec<D>&, double t, force_terms<D>& r) const {
        r.f = u(t);
        if (r.f.size() != q.size())
            throw std::invalid_argument("the prescribed force has " + std::to_string(r.f.size()) +
                                        " components for " + std::to_string(q.size()) +
                                        " coordinates");
        r.fq.setZero(q.size(), q.size());
        r.fv.setZero(q.size(), q.size());
    }

    /// u(t) interpolated linearly in a table: times increasing, values[k] the force at times[k];
    /// constant (the first or last row) outside the table.
    static prescribed_force piecewise_linear(std::vector<double> times,
                                             std::vector<vec<D>> values) {
        if (times.empty() || times.size() != values.size())
            throw std::invalid_argument("a force schedule needs as many rows of values as times "
                                        "(and at least one)");
        if (!std::is_sorted(times.begin(), times.end()) ||
            std::adjacent_find(times.begin(), times.end()) != times.end())
            throw std::invalid_argument("the times of a force schedule must increase");
        prescribed_force f;
        f.size = static_cast<int>(values.front().size());
        f.u = [times = std::move(times), values = std::move(values)](double t) -> vec<D> {
            if (t <= times.front()) return values.front();
            if (t >= times.back()) return values.back();
            const auto k = static_cast<std::size_t>(
                std::upper_bound(times.begin(), times.end(), t) - times.begin());
            const double a = (t - times[k - 1]) / (times[k] - times[k - 1]);
            return (1.0 - a) * values[k - 1] + a * values[k];
        };
        return f;
    }
};

/// Joint torques of a PD controller tracking a reference trajectory r(t):
///   f = K_p (r(t) − q) + K_d (ṙ(t) − q̇) + τ_g(q),
/// with gravity compensation τ_g(q) = −∂L/∂q(q, 0) (the torque that holds the system at rest at
/// q, for a kinetic energy quadratic in q̇) when built with compensate(). Gains K_p [N·m/rad],
/// K_d [N·m·s/rad]. The reference is taken to be continuous, with its rate
/// (force_continuous_in_time).
template <int D>
struct pd_controller {
    static constexpr int dim = D;
    static constexpr bool continuous_in_time = true;
    mat<D> kp, kd;
    /// The reference: fills r(t) and ṙ(t).
    std::function<void(double, vec<D>&, vec<D>&)> reference;
    /// Gravity compensation: fills τ_g(q), and ∂τ_g/∂q where the matrix is given (null: the
    /// value alone). Empty: none.
    std::function<void(const vec<D>&, vec<D>&, mat<D>*)> compensation;

    [[nodiscard]] int dimension() const { return static_cast<int>(kp.rows()); }

    /// Adds the compensation −∂L/∂q(q, 0) of the Lagrangian l (by hand or automatic derivatives).
    /// The value alone takes ∂L/∂q by evaluate_gradient: L's gradient() where it gives one (a
    /// robot's O(n) pass instead of its O(n²) second derivatives), first-order automatic
    /// derivatives where L gives none, and L's derivatives() where it gives only those.
    template <lagrangian L>
    pd_controller& compensate(L l) {
        compensation = [l = std::move(l)](const vec<D>& q, vec<D>& tau, mat<D>* dtau) {
            thread_local lagrangian_terms<D> t; // kept: no allocation once sized
            thread_local vec<D> rest;
            rest.setZero(q.size());
            if (dtau) {
                evaluate(l, q, rest, t);
                *dtau = -t.lqq;
            } else {
                evaluate_gradient(l, q, rest, t);
            }
            tau = -t.lq;
        };
        return *this;
    }

    vec<D> operator()(const vec<D>& q, const vec<D>& v, double t) const {
        vec<D> f;
        value(q, v, t, f);
        return f;
    }
    void value(const vec<D>& q, const vec<D>& v, double t, vec<D>& out) const {
        scratch local; // unused at D = dynamic
        fill(q, v, t, out, D == dynamic ? work() : local, false);
    }
    void derivatives(const vec<D>& q, const vec<D>& v, double t, force_terms<D>& r) const {
        scratch local; // unused at D = dynamic
        scratch& w = D == dynamic ? work() : local;
        fill(q, v, t, r.f, w, true);
        r.fq = -kp;
        r.fv = -kd;
        if (compensation) r.fq += w.dtau;
    }

  private:
    /// The vectors of one evaluation: at D = dynamic one set per thread (the controller stays
    /// const and shareable), so that an evaluation allocates nothing once they have the size.
    struct scratch {
        vec<D> ref, rate, error, tau;
        mat<D> dtau;
    };
    static scratch& work() {
        thread_local scratch w;
        return w;
    }
    /// f into out; the compensation's Jacobian into w.dtau where `jacobian`.
    void fill(const vec<D>& q, const vec<D>& v, double t, vec<D>& out, scratch& w,
              bool jacobian) const {
        w.ref.setZero(q.size());
        w.rate.setZero(q.size());
        if (reference) reference(t, w.ref, w.rate);
        w.error = w.ref - q;
        out.noalias() = kp * w.error;
        w.error = w.rate - v;
        out.noalias() += kd * w.error;
        if (compensation) {
            compensation(q, w.tau, jacobian ? &w.dtau : nullptr);
            out += w.tau;
        }
    }
};

/// A force with a control input u ∈ R^M held over each step (joint torques of a trajectory
/// optimizer, an LQR input): F gives `static constexpr int dim, controls` and
/// `template <class T> tvec<T, dim> operator()(q, v, double t, const tvec<T, controls>& u)`.
/// `controlled<F>` is the generalized force f(q, q̇, t) = F(q, q̇, t, u) with u its member (set it
/// before each step: stepper.force().u = …), and gives ∂f/∂u by automatic differentiation for
/// the step's control sensitivity (general::stepper::step_jacobian).
template <class F>
struct controlled {
    static constexpr int dim = F::dim, controls = F::controls;
    F f;
    vec<controls> u = vec<controls>::Zero();

    template <class T>
    tvec<T, dim> operator()(const tvec<T, dim>& q, const tvec<T, dim>& v, double t) const {
        return f(q, v, t, tvec<T, controls>(u.template cast<T>()));
    }
    /// ∂f/∂u at (q, v, t, u) (dim × controls).
    void input_jacobian(const vec<dim>& q, const vec<dim>& v, double t,
                        Eigen::Matrix<double, dim, controls>& b) const {
        using J = ad::first_order<controls>;
        tvec<J, controls> uj;
        for (int i = 0; i < controls; ++i)
            uj(i) = J(u(i), controls, i);
        const tvec<J, dim> qj = q.template cast<J>(), vj = v.template cast<J>();
        const tvec<J, dim> out = f(qj, vj, t, uj);
        for (int i = 0; i < dim; ++i)
            b.row(i) = out(i).derivatives().transpose();
    }
};

/// Whether F gives ∂f/∂u (a controlled<…> force).
template <class F>
concept force_with_input = generalized_force<F> && requires(const F& f, const vec<F::dim>& q) {
    F::controls;
    f.input_jacobian(q, q, 0.0, std::declval<Eigen::Matrix<double, F::dim, F::controls>&>());
};

/// The sum of several forces of one dimension (e.g. damping and a controller).
template <generalized_force... F>
struct force_sum {
    static constexpr int dim = std::get<0>(std::tuple{F::dim...});
    static constexpr bool continuous_in_time = (force_continuous_in_time<F>() && ...);
    std::tuple<F...> parts;

    explicit force_sum(F... f) : parts(std::move(f)...) {}

    vec<dim> operator()(const vec<dim>& q, const vec<dim>& v, double t) const {
        vec<dim> f = vec<dim>::Zero(q.size());
        std::apply([&](const auto&... p) { ((f += vec<dim>(p(q, v, t))), ...); }, parts);
        return f;
    }
    /// The sum alone: each part's value alone where it gives it (evaluate_force), else its
    /// derivatives' f, summed in the order derivatives() sums them.
    void value(const vec<dim>& q, const vec<dim>& v, double t, vec<dim>& out) const {
        force_terms<dim> local;
        force_terms<dim>& part = sized_part(local, q.size());
        out.setZero(q.size());
        std::apply(
            [&](const auto&... p) {
                ((evaluate_force(p, q, v, t, part, false), out += part.f), ...);
            },
            parts);
    }
    void derivatives(const vec<dim>& q, const vec<dim>& v, double t, force_terms<dim>& r) const {
        force_terms<dim> local;
        force_terms<dim>& part = sized_part(local, q.size());
        r.f.setZero(q.size());
        r.fq.setZero(q.size(), q.size());
        r.fv.setZero(q.size(), q.size());
        std::apply(
            [&](const auto&... p) {
                ((evaluate_force(p, q, v, t, part, true), r.f += part.f, r.fq += part.fq,
                  r.fv += part.fv),
                 ...);
            },
            parts);
    }

  private:
    /// One part's terms, sized n: at a run-time dim kept per thread (no allocation once sized),
    /// else `local`.
    static force_terms<dim>& sized_part(force_terms<dim>& local, Eigen::Index n) {
        force_terms<dim>* part = &local;
        if constexpr (dim == dynamic) {
            thread_local force_terms<dim> kept;
            part = &kept;
        }
        part->f.resize(n);
        part->fq.resize(n, n);
        part->fv.resize(n, n);
        return *part;
    }
};

} // namespace varsym
