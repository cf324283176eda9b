// varsym/schemes/constrained_failure.hpp: why a step of the constrained engine failed. Beside
// the general engine's causes (variational_failure.hpp), a constraint that returned NaN or
// infinity, and a constraint Jacobian G that is singular, or nearly so against its value at the
// initial state (a singular configuration of the mechanism: a cusp, a toggle, a change point).
#pragma once

#include <cstdio>
#include <string>

#include <Eigen/SVD>

#include "varsym/schemes/constrained.hpp"
#include "varsym/schemes/variational_failure.hpp"

namespace varsym::general {

/// Empty if g and G are finite at q and G is far from singular (its smallest singular value
/// above 1e-10 of its largest and above 1e-2 of the smallest at the initial state), else what it
/// is. Asked only after a step failed: near a singular configuration Newton's iteration on the
/// saddle-point system stalls or diverges, so "nearly" is generous.
template <lagrangian L, holonomic_constraint C, class F>
std::string constrained_stepper<L, C, F>::constraint_problem(const vec<dim>& q, const char* where,
                                                             double t) const {
    vec<count> g;
    jacobian_type jac(m_, q.size());
    evaluate_constraint(c_, q, g, jac);
    if (!g.allFinite() || !jac.allFinite())
        return "the constraint or its Jacobian is NaN or infinite" + detail::where_when(where, t);
    const Eigen::VectorXd sv = singular_values(jac);
    const double lo = sv(sv.size() - 1), hi = sv(0);
    if (lo > 1e-10 * hi && lo > 1e-2 * sigma_ref_) return {};
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  "the constraint Jacobian is singular or nearly so (singular values from %.3g to "
                  "%.3g; the smallest was %.3g at the initial state): the mechanism is at or near "
                  "a singular configuration",
                  lo, hi, sigma_ref_);
    return buf + detail::where_when(where, t);
}

template <lagrangian L, holonomic_constraint C, class F>
std::string constrained_stepper<L, C, F>::diagnose(const phase_state<dim>& x) {
    const int s = this->s_;
    auto points = [&](const char* where) {
        for (int l = 1; l <= s; ++l) {
            const double tl = this->t_ + this->tab_.control[l] * this->h_;
            std::string c = constraint_problem(x.q + this->x_.col(l - 1), where, tl);
            if (!c.empty()) return c;
        }
        return std::string();
    };
    // Newton's last iterate first: the general engine's diagnosis replaces it by the predictor.
    const std::string iterate =
        this->x_.allFinite() ? points("at Newton's last iterate") : std::string();
    if (std::string c = constraint_problem(x.q, "at the step's start", this->t_); !c.empty())
        return c;
    if (std::string c = base::diagnose(x); !c.empty()) return c;
    if (this->x_.allFinite()) {
        if (std::string c = points("on the step's predicted motion"); !c.empty()) return c;
    }
    return iterate;
}

} // namespace varsym::general
