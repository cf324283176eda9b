// apps/varsym/ensemble/ensemble_writer.cpp: rows put in member order on their way to a file.
#include "ensemble/ensemble_writer.hpp"

namespace varsym::cli {

void ordered_writer::partial(std::size_t k, std::string rows) {
    const std::lock_guard lock(mutex_);
    if (k == next_)
        buffer_ += rows;
    else
        started_[k] += rows;
    if (buffer_.size() > (std::size_t{1} << 16)) write();
}

void ordered_writer::done(std::size_t k, std::string row) {
    const std::lock_guard lock(mutex_);
    if (const auto s = started_.find(k); s != started_.end()) { // its rows before these
        row = std::move(s->second) + row;
        started_.erase(s);
    }
    waiting_.emplace(k, std::move(row));
    for (;;) { // every row from next_ on that is done goes out, in order
        if (!waiting_.empty() && waiting_.begin()->first == next_) {
            buffer_ += waiting_.begin()->second;
            waiting_.erase(waiting_.begin());
        } else if (ahead_.erase(next_) == 0) {
            break;
        }
        ++next_;
        // The new head's rows so far go out now; the rest follow through partial().
        if (const auto s = started_.find(next_); s != started_.end()) {
            buffer_ += s->second;
            started_.erase(s);
        }
    }
    // A member far slower than the rest: the rows behind it do not wait (where allowed).
    if (max_waiting_ > 0 && waiting_.size() > max_waiting_) {
        for (auto& [j, r] : waiting_) {
            buffer_ += r;
            ahead_.insert(j);
        }
        waiting_.clear();
    }
    if (buffer_.size() > (std::size_t{1} << 16) ||
        std::chrono::steady_clock::now() - last_ > std::chrono::milliseconds(250))
        write();
}

void ordered_writer::flush_all() {
    const std::lock_guard lock(mutex_);
    for (auto& [j, r] : waiting_)
        buffer_ += r;
    waiting_.clear();
    for (auto& [j, r] : started_) // members stopped part-way (an error ends the work)
        buffer_ += r;
    started_.clear();
    write();
}

void ordered_writer::write() {
    if (!buffer_.empty()) sink_(buffer_);
    buffer_.clear();
    last_ = std::chrono::steady_clock::now();
}

} // namespace varsym::cli
