// varsym/schemes/variational_history.hpp: what the general engine (variational.hpp) keeps
// from one step to the next, saved into and restored from a checkpoint: the linear iterations'
// kept point, the time-dependent work's carries and the robot predictor's jerk and last miss.
#pragma once

#include <algorithm>
#include <cmath>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "varsym/schemes/variational.hpp"

namespace varsym::general {

/// q_{j+1} = q_j + X_s and p_{j+1} = p_j + dp_ (compensated); the clock and work advance, and a
/// robot's predictor keeps where the step ended (its jerk's history) and the step's miss.
template <lagrangian L, class F>
void stepper<L, F>::commit(phase_state<dim>& x) {
    dq_ = x_.col(s_ - 1);
    sum_.add_q(x, dq_);
    sum_.add_p(x, dp_);
    if constexpr (jerk_history) {
        continues_ = a0_taken_; // the robot predictor took a_next_ at this step's start
        a0_taken_ = false;
        miss_valid_ = continues_ && jerk_taken_;
        if (miss_valid_) x_miss_ = x_ - x_taylor_;
        if (continues_) {
            a0_ = a_next_;
            q_end_ = x.q;
            p_end_ = x.p;
        }
    }
    work_ *= h_;
    t_step_ = t_;
    t_ += h_;
    // total_work_ += work_, compensated (Neumaier): long runs add many small works.
    const double sum = total_work_ + work_;
    work_carry_ += std::abs(total_work_) >= std::abs(work_) ? (total_work_ - sum) + work_
                                                            : (work_ - sum) + total_work_;
    total_work_ = sum;
}

template <lagrangian L, class F>
void stepper<L, F>::save_history(std::vector<double>& out) const {
    out.clear();
    if (linear()) {
        out.push_back(kept_ ? 1.0 : 0.0);
        out.insert(out.end(), q_bar_.data(), q_bar_.data() + d_);
        out.insert(out.end(), v_bar_.data(), v_bar_.data() + d_);
    }
    if constexpr (timed) out.insert(out.end(), {t_bar_, total_work_, work_carry_});
    if constexpr (jerk_history) {
        out.push_back(continues_ ? 1.0 : 0.0);
        if (continues_) {
            for (const vec<dim>* v : {&a0_, &q_end_, &p_end_})
                out.insert(out.end(), v->data(), v->data() + d_);
            out.push_back(miss_valid_ ? 1.0 : 0.0);
            if (miss_valid_) out.insert(out.end(), x_miss_.data(), x_miss_.data() + x_miss_.size());
        }
    }
    if (choice_.on()) choice_.save(out); // last: a history written without it is read too
}

/// restore_steps, with an automatic choice's state taken from the last numbers where they are
/// one: a history written without it starts the choice afresh, and a stepper without the choice
/// (Newton, or the articulated iteration, named) reads an automatic run's history and ignores it.
template <lagrangian L, class F>
void stepper<L, F>::restore_history(const phase_state<dim>& x, const std::vector<double>& in) {
    const std::span<const double> all(in);
    constexpr auto n = static_cast<std::size_t>(iteration_choice::saved);
    iteration_choice saved(choice_.on() ? choice_.break_even() : 1.0);
    choice_.restart();
    if (in.size() >= n && saved.restore(in.data() + in.size() - n)) {
        try {
            restore_steps(x, all.first(in.size() - n));
            if (choice_.on()) choice_ = saved;
            return;
        } catch (const std::invalid_argument&) { // not a choice's state: the whole history
        }
    }
    restore_steps(x, all);
}

template <lagrangian L, class F>
void stepper<L, F>::restore_steps(const phase_state<dim>&, std::span<const double> in) {
    kept_ = false;
    total_work_ = work_carry_ = 0.0;
    continues_ = a0_taken_ = miss_valid_ = false;
    if (in.empty()) return;
    const auto want = static_cast<std::size_t>((linear() ? 1 + 2 * d_ : 0) + (timed ? 3 : 0));
    // Then the predictor's jerk: a flag, and if it is set a₀, q and p where the last step ended,
    // and a flag and the last step's miss (its increments less their Taylor prediction). A
    // history in a layout without either part is read too; what it lacks then starts afresh.
    bool fits = in.size() == want;
    std::string sizes = std::to_string(want);
    if constexpr (jerk_history) {
        const auto d = static_cast<std::size_t>(d_), jerk = want + 1 + 3 * d;
        const auto missed = jerk + 1 + static_cast<std::size_t>(x_miss_.size());
        sizes += ", " + std::to_string(want + 1) + ", " + std::to_string(jerk) + ", " +
                 std::to_string(jerk + 1) + " or " + std::to_string(missed);
        const bool miss = in.size() == missed && in[jerk] == 1.0;
        if ((in.size() == jerk || (in.size() == jerk + 1 && in[jerk] == 0.0) || miss) &&
            in[want] == 1.0) {
            const double* at = in.data() + want + 1;
            for (vec<dim>* v : {&a0_, &q_end_, &p_end_}) { // sized by the constructor
                std::copy(at, at + d_, v->data());
                at += d_;
            }
            if (miss) std::copy(at + 1, at + 1 + x_miss_.size(), x_miss_.data());
            continues_ = fits = true;
            miss_valid_ = miss;
        }
        fits = fits || (in.size() == want + 1 && in[want] == 0.0);
    }
    if (!fits)
        throw std::invalid_argument("the saved history has " + std::to_string(in.size()) +
                                    " numbers where this stepper's options keep " + sizes +
                                    " (or " + std::to_string(iteration_choice::saved) +
                                    " more: an automatic choice of iteration)");
    if constexpr (timed) {
        t_bar_ = in[want - 3];
        total_work_ = in[want - 2];
        work_carry_ = in[want - 1];
    }
    if (!linear()) return;
    std::copy(in.begin() + 1, in.begin() + 1 + d_, q_bar_.data());
    std::copy(in.begin() + 1 + d_, in.begin() + 1 + 2 * d_, v_bar_.data());
    if (in[0] != 0.0) {
        evaluate(sys_.lagrangian(), q_bar_, v_bar_, t_bar_, terms_[0]);
        if constexpr (forced) add_force(0, q_bar_, v_bar_, t_bar_, true);
        refresh(terms_[0]);
    }
}

} // namespace varsym::general
