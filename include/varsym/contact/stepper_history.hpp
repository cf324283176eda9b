// varsym/contact/stepper_history.hpp: contact_stepper's history (stepper.hpp) in a checkpoint:
// the inner stepper's, then (where it reuses its matrix across steps) that matrix, its
// multipliers and its warm take's miss (none without warm pairs) and their count, the warm start's
// contacts and impulses, the contact's work and the last report. Included by stepper.hpp.
#pragma once

#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace varsym::contact {

template <class Inner>
void contact_stepper<Inner>::save_history(std::vector<double>& out) const {
    Inner::save_history(out);
    if constexpr (reuses) { // the inner stepper's kept matrix, for a warm step (warm())
        const std::size_t before = out.size();
        if (!warm_pairs_.empty()) Inner::save_kept(out);
        out.push_back(static_cast<double>(out.size() - before));
    }
    for (std::size_t i = 0; i < warm_pairs_.size(); ++i) {
        out.push_back(warm_pairs_[i]);
        for (int j = 0; j < 3; ++j)
            out.push_back(warm_lambda_(3 * static_cast<Eigen::Index>(i) + j));
    }
    out.insert(out.end(), {static_cast<double>(warm_pairs_.size()), history_tag, work_, carry_,
                           static_cast<double>(last_.active), last_.normal, last_.friction,
                           last_.penetration, last_.work, static_cast<double>(last_.iterations)});
}

template <class Inner>
void contact_stepper<Inner>::restore_history(const phase_state<dim>& x,
                                             const std::vector<double>& in) {
    last_ = {};
    impulses_.clear();
    work_ = carry_ = 0.0;
    warm_pairs_.clear();
    if (in.empty()) {
        Inner::restore_history(x, in);
        return;
    }
    const std::size_t tail = fixed_size + 2; // count, tag, the fixed part
    // Whole literals: GCC 12 -O1 sees a false -Warray-bounds in a string built of a conditional.
    const auto bad = [] {
        if constexpr (reuses)
            return std::invalid_argument(
                "the saved history is not a contact step's (its layout: the stepper's, its kept "
                "matrix and its count, 4 numbers a contact, their count, a tag, 8 numbers): was it "
                "saved by a run with contact?");
        else
            return std::invalid_argument(
                "the saved history is not a contact step's (its layout: the stepper's, 4 numbers "
                "a contact, their count, a tag, 8 numbers): was it saved by a run with contact?");
    };
    if (reuses && in.size() >= tail &&
        (in[in.size() - fixed_size - 1] == older_tag || in[in.size() - fixed_size - 1] == old_tag))
        throw std::invalid_argument("the saved history is in an older layout (before the contact "
                                    "step kept its matrix and its start's miss across steps): "
                                    "start the run afresh");
    if (in.size() < tail || in[in.size() - fixed_size - 1] != history_tag) throw bad();
    const double stored = in[in.size() - tail];
    if (!(stored >= 0.0 && stored == std::floor(stored) &&
          4.0 * stored <= static_cast<double>(in.size() - tail)))
        throw bad();
    const auto n = static_cast<std::size_t>(stored);
    const auto warm = in.end() - static_cast<std::ptrdiff_t>(tail + 4 * n);
    for (std::size_t i = 0; i < n; ++i) { // every check before anything is put back
        const double pair = warm[static_cast<std::ptrdiff_t>(4 * i)];
        if (!(pair >= 0.0 && pair < pairs() && pair == std::floor(pair))) throw bad();
    }
    auto inner = warm; // the inner stepper's history ends here
    if constexpr (reuses) {
        if (warm == in.begin()) throw bad();
        const double kept = *(warm - 1);
        if (kept != (n > 0 ? static_cast<double>(Inner::kept_size()) : 0.0) ||
            kept > static_cast<double>(warm - 1 - in.begin()))
            throw bad();
        inner = warm - 1 - static_cast<std::ptrdiff_t>(kept);
        Inner::restore_history(x, std::vector<double>(in.begin(), inner));
        if (kept > 0.0) Inner::restore_kept(&*inner);
    } else {
        Inner::restore_history(x, std::vector<double>(in.begin(), inner));
    }
    warm_lambda_.resize(3 * static_cast<Eigen::Index>(n));
    for (std::size_t i = 0; i < n; ++i) {
        warm_pairs_.push_back(static_cast<int>(warm[static_cast<std::ptrdiff_t>(4 * i)]));
        for (int j = 0; j < 3; ++j)
            warm_lambda_(3 * static_cast<Eigen::Index>(i) + j) =
                warm[static_cast<std::ptrdiff_t>(4 * i) + 1 + j];
    }
    const auto fixed = in.end() - fixed_size;
    work_ = fixed[0];
    carry_ = fixed[1];
    last_.active = static_cast<int>(fixed[2]);
    last_.normal = fixed[3];
    last_.friction = fixed[4];
    last_.penetration = fixed[5];
    last_.work = fixed[6];
    last_.iterations = static_cast<int>(fixed[7]);
}

} // namespace varsym::contact
