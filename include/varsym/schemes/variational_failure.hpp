// varsym/schemes/variational_failure.hpp: why a step of the general engine failed. After a step
// that did not converge, diagnose() looks at the step's start, at the predicted motion over the
// step and at Newton's last iterate, and names what it finds: a Lagrangian or force that returned
// NaN or infinity, or a mass matrix ∂²L/∂q̇² that is singular, not positive definite or
// ill-conditioned. The drivers of integrate.hpp put it in their step_failure's message.
#pragma once

#include <cmath>
#include <cstdio>
#include <string>

#include <Eigen/Eigenvalues>

#include "varsym/schemes/variational.hpp"
#include "varsym/solvers/eigenvalues.hpp"

namespace varsym {
namespace detail {

template <int D>
bool finite_terms(const lagrangian_terms<D>& t) {
    return std::isfinite(t.value) && t.lq.allFinite() && t.lv.allFinite() && t.lqq.allFinite() &&
           t.lqv.allFinite() && t.lvv.allFinite();
}

template <int D>
bool finite_force(const force_terms<D>& f) {
    return f.f.allFinite() && f.fq.allFinite() && f.fv.allFinite();
}

/// " <where> (t = <t>)".
inline std::string where_when(const char* where, double t) {
    char buf[32];
    std::snprintf(buf, sizeof buf, " (t = %.9g)", t);
    return std::string(" ") + where + buf;
}

} // namespace detail

namespace general {

template <lagrangian L, class F>
std::string stepper<L, F>::diagnose(const phase_state<dim>& x) {
    using namespace detail;
    if (!x.q.allFinite() || !x.p.allFinite())
        return "the state the step started from is NaN or infinite";
    // predict() moves the kept Jacobian's point; a diagnosis must not change the next step.
    const vec<dim> q_bar = q_bar_, v_bar = v_bar_;
    const double t_bar = t_bar_;
    // Newton's last iterate first: predict() replaces it.
    const std::string iterate =
        x_.allFinite() ? diagnose_points(x, "at Newton's last iterate") : std::string();
    // The step's start: L at (q_j, q̇_j) as the predictor finds q̇_j (from q̇ = 0, or from p
    // where ∂²L/∂q̇² is singular at 0), then the force there.
    std::string cause;
    predict(x);
    const lagrangian_terms<dim>& t = terms_[0];
    if (!finite_terms(t))
        cause = "the Lagrangian or its derivatives are NaN or infinite" +
                where_when("at the step's start", t_);
    else if (std::string m = mass_matrix_problem<dim>(t.lvv); !m.empty())
        cause = m + where_when("at the step's start", t_);
    if (cause.empty()) {
        if constexpr (forced)
            if (!finite_force(fterms_[0]))
                cause = "the force or its Jacobians are NaN or infinite" +
                        where_when("at the step's start", t_);
    }
    if (cause.empty()) cause = diagnose_points(x, "on the step's predicted motion");
    if (cause.empty()) cause = iterate;
    q_bar_ = q_bar;
    v_bar_ = v_bar;
    t_bar_ = t_bar;
    return cause;
}

/// At the quadrature points of the current increments: the force, then L, then ∂²L/∂q̇².
template <lagrangian L, class F>
std::string stepper<L, F>::diagnose_points(const phase_state<dim>& x, const char* where) {
    using namespace detail;
    evaluate_points(x.q, true);
    for (int k = 0; k < r_; ++k) {
        const auto ks = static_cast<std::size_t>(k);
        const double tk = t_ + tab_.quad.nodes[ks] * h_;
        if constexpr (forced)
            if (!finite_force(fterms_[ks]))
                return "the force or its Jacobians are NaN or infinite" + where_when(where, tk);
        if (!finite_terms(terms_[ks]))
            return "the Lagrangian or its derivatives are NaN or infinite" + where_when(where, tk);
        if (std::string m = mass_matrix_problem<dim>(terms_[ks].lvv); !m.empty())
            return m + where_when(where, tk);
    }
    return {};
}

} // namespace general
} // namespace varsym
