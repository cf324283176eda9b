// varsym/solvers/iteration_choice.hpp: the general engine's automatic choice, step by step,
// between Newton's iteration and the articulated one for a robot
// (schemes/variational_articulated.hpp). The articulated iteration's step costs about
// F + u C_u (u updates of C_u each), Newton's a fixed T_N; from a model of both,
// `break_even` is the u at which they cost the same. The choice takes the articulated iteration
// over windows of `window` steps; where a window's updates average above the break-even
// (a step it handed to Newton counts its updates and Newton's step, break_even + `handed`),
// the next `hold` steps take Newton, then another window tries the articulated iteration. The
// hold starts at first_hold and doubles each time a window fails in a row, up to max_hold, so a
// motion that keeps the articulated iteration slow spends at most 16/(16 + 4096) of its steps
// trying it. Everything counted is the steps' own (no clock): a run's steps are the same on any
// machine, and a checkpoint keeps the state (save, restore).
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

namespace varsym {

class iteration_choice {
  public:
    static constexpr int window = 16;
    static constexpr int first_hold = 64;
    static constexpr int max_hold = 4096;
    /// A step handed to Newton costs its articulated updates, then Newton's step: break_even +
    /// handed updates (the articulated step's own fixed part, about 2.5 updates, comes on top).
    static constexpr double handed = 2.5;
    /// The numbers save() writes.
    static constexpr int saved = 4;

    iteration_choice() = default;
    /// `break_even` ≤ 0: no choice (the stepper's own iteration every step).
    explicit iteration_choice(double break_even) : break_even_(break_even) {}

    [[nodiscard]] bool on() const { return break_even_ > 0.0; }
    [[nodiscard]] double break_even() const { return break_even_; }
    /// Whether the next step takes the articulated iteration.
    [[nodiscard]] bool articulated() const { return left_ == 0; }
    /// Settles on Newton for good (the contact step, which takes a step several times over).
    void off() { break_even_ = 0.0; }

    /// After a step taken as articulated() said: its articulated updates, and whether it was
    /// handed to Newton.
    void record(int updates, bool to_newton) {
        if (!on()) return;
        ++steps_;
        if (left_ > 0) { // a held Newton step
            --left_;
            return;
        }
        ++articulated_steps_;
        sum_ += updates + (to_newton ? break_even_ + handed : 0.0);
        if (++in_window_ < window) return;
        if (sum_ > break_even_ * window) {
            left_ = hold_;
            hold_ = std::min(2 * hold_, max_hold);
        } else {
            hold_ = first_hold;
        }
        in_window_ = 0;
        sum_ = 0.0;
    }

    /// Steps recorded, and those of them taken by the articulated iteration.
    [[nodiscard]] long steps() const { return steps_; }
    [[nodiscard]] long articulated_steps() const { return articulated_steps_; }

    /// The state a checkpoint keeps: the steps into the window, their updates, the Newton steps
    /// left in a hold and the next hold.
    void save(std::vector<double>& out) const {
        out.insert(out.end(), {static_cast<double>(in_window_), sum_, static_cast<double>(left_),
                               static_cast<double>(hold_)});
    }
    /// Puts back what save() wrote; false (the state unchanged) where the numbers are not a
    /// state save() could have written: steps into a window and their updates (none in a hold),
    /// the Newton steps left (at most the next hold, a power of two times first_hold).
    bool restore(const double* in) {
        const auto whole = [](double v, double lo, double hi) {
            return v == std::floor(v) && v >= lo && v <= hi;
        };
        if (!whole(in[0], 0, window - 1) || !(in[1] >= 0.0 && std::isfinite(in[1])) ||
            !whole(in[2], 0, max_hold) || !whole(in[3], first_hold, max_hold))
            return false;
        bool doubled = false; // hold = first_hold · 2^k
        for (int h = first_hold; h <= max_hold; h *= 2)
            doubled = doubled || in[3] == h;
        const bool holding = in[2] > 0.0;
        const double most_left = in[3] == max_hold ? max_hold : in[3] / 2; // the hold before
        if (!doubled || (in[0] == 0.0 && in[1] != 0.0) ||
            (holding && (in[0] != 0.0 || in[3] == first_hold || in[2] > most_left)))
            return false;
        in_window_ = static_cast<int>(in[0]);
        sum_ = in[1];
        left_ = static_cast<int>(in[2]);
        hold_ = static_cast<int>(in[3]);
        return true;
    }
    /// The state of a fresh run: the first window starts.
    void restart() {
        in_window_ = left_ = 0;
        sum_ = 0.0;
        hold_ = first_hold;
    }

  private:
    double break_even_ = 0.0;
    int in_window_ = 0; // steps of the current window taken
    double sum_ = 0.0;  // their cost in articulated updates
    int left_ = 0;      // Newton steps left in a hold
    int hold_ = first_hold;
    long steps_ = 0, articulated_steps_ = 0;
};

} // namespace varsym
