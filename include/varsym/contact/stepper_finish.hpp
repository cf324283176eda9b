// varsym/contact/stepper_finish.hpp: the end of contact_stepper's converged step (stepper.hpp):
// its report, the contact's work and the warm start's pairs for the next step. Included by
// stepper.hpp.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace varsym::contact {

/// E(q_j, p_j + Jᵀλ) − E(q_j, p_j). For L = ½ q̇ᵀM(q)q̇ − V(q) (lagrangian_with_mass_matrix), E =
/// ½ pᵀM⁻¹p + V and the change is exactly q̇(q_j, p_j + Jᵀλ/2)·Jᵀλ: one velocity, no energy
/// differenced (nor its round-off, ε E), by M(q_j)'s LDLᵀ (small_ldlt at a run-time size) and
/// one step of iterative refinement; by velocity() where M is not positive definite (which then
/// says why). kick_ is Jᵀλ: every converged iteration ends on a take with the step's J and λ.
template <class Inner>
double contact_stepper<Inner>::kick_work() {
    const auto& sys = this->system();
    phase_state<dim> kicked = from_;
    if constexpr (lagrangian_with_mass_matrix<typename Inner::system_type::lagrangian_type>) {
        kicked.p.noalias() += 0.5 * kick_;
        work_mass_.resize(kicked.q.size(), kicked.q.size());
        sys.lagrangian().mass_matrix(kicked.q, work_mass_);
        if (work_mass_.allFinite() &&
            solve_positive_definite<dim>(work_factor_, work_mass_, kicked.p, work_v_)) {
            work_r_ = kicked.p;
            work_r_.noalias() -= work_mass_ * work_v_;
            solve_symmetric_again<dim>(work_factor_, work_mass_, work_r_, work_dv_);
            work_v_ += work_dv_;
            return work_v_.dot(kick_);
        }
        return sys.velocity(kicked.q, kicked.p, this->t_step_).dot(kick_);
    } else {
        kicked.p += kick_;
        return sys.energy(kicked) - sys.energy(from_);
    }
}

/// The converged step: its report, the contact's work (the kick's change of the energy at q_j,
/// E(q_j, p_j + Jᵀλ) − E(q_j, p_j): the inner step from the kicked state accounts for the
/// rest, its forces' work and its own error), the warm start's pairs (those that pressed).
template <class Inner>
void contact_stepper<Inner>::finish(phase_state<dim>& x) {
    kin_.at(y_.q);
    double low = std::numeric_limits<double>::infinity();
    for (int c = 0; c < pairs(); ++c)
        low = std::min(low, gap(c));
    last_.penetration = std::max(0.0, -low);
    const int k = static_cast<int>(active_.size());
    double gamma_max = 0.0;
    for (int i = 0; i < k; ++i)
        gamma_max = std::max(gamma_max, lambda_(3 * i));
    warm_pairs_.clear();
    impulses_.clear();
    std::vector<Eigen::Index> pressing;
    for (int i = 0; i < k; ++i) {
        last_.normal += lambda_(3 * i);
        last_.friction += lambda_.segment<2>(3 * i + 1).norm();
        if (!(lambda_(3 * i) > 1e-9 * gamma_max)) continue;
        ++last_.active;
        warm_pairs_.push_back(active_[static_cast<std::size_t>(i)].pair);
        pressing.push_back(i);
    }
    warm_lambda_.resize(3 * static_cast<Eigen::Index>(pressing.size()));
    for (std::size_t j = 0; j < pressing.size(); ++j) {
        const Eigen::Index i = pressing[j];
        warm_lambda_.segment<3>(3 * static_cast<Eigen::Index>(j)) = lambda_.segment<3>(3 * i);
        const pair_state& a = active_[static_cast<std::size_t>(i)]; // n = t₁ × t₂ (tangents())
        const vec3 l = lambda_(3 * i) * a.t1.cross(a.t2) + lambda_(3 * i + 1) * a.t1 +
                       lambda_(3 * i + 2) * a.t2;
        impulses_.insert(impulses_.end(),
                         {a.start.x(), a.start.y(), a.start.z(), l.x(), l.y(), l.z()});
    }
    last_.work = kick_work();
    const double sum = work_ + last_.work; // Neumaier's compensated sum
    carry_ += std::abs(work_) >= std::abs(last_.work) ? (work_ - sum) + last_.work
                                                      : (last_.work - sum) + work_;
    work_ = sum;
    x = y_;
}

} // namespace varsym::contact
