// optimal/src/step_threads.hpp: the steps of a transcription's derivatives on several threads
// (dmoc_transcription::set_threads). Each step writes its own block of the values, so the result
// is the same to the bit with any number of threads.
#pragma once

#include <algorithm>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include <unistd.h>

#include "varsym/run/cpus.hpp"

namespace varsym::optimal::detail {

/// The CPUs this process may run on (varsym/run/cpus.hpp): its affinity mask, read at each
/// evaluation (a caller may pin itself between solves), at most its cgroup's CPU quota, read
/// once a process (from files: about 45 µs). At least 1.
inline int available_cpus() {
    static const unsigned quota = cgroup_cpu_limit();
    return static_cast<int>(std::min(least_limit(affinity_cpus(), quota), 1U << 20));
}

/// Worker threads kept for the life of the process: a thread started for every evaluation
/// would also build its per-thread workspaces (the robot's) anew each time. The pool is never
/// destroyed (its idle workers end with the process), so that exit() cannot pull it from under
/// a caller. One caller at a time; another caller meanwhile, or a child forked from this
/// process (it has none of the workers), runs all its parts itself. Workers keep the
/// floating-point environment of the thread that started them (the default one).
class step_pool {
  public:
    static step_pool& instance() {
        static step_pool& pool = *new step_pool; // NOLINT(cppcoreguidelines-owning-memory)
        return pool;
    }
    step_pool(const step_pool&) = delete;
    step_pool& operator=(const step_pool&) = delete;
    step_pool(step_pool&&) = delete;
    step_pool& operator=(step_pool&&) = delete;
    ~step_pool() = delete;

    /// part(0 … parts − 1), which must not throw and must not call run(): part 0 on this
    /// thread, the others on the workers where they can be started (else here). Returns when
    /// every part has ended.
    void run(int parts, const std::function<void(int)>& part) {
        std::unique_lock<std::mutex> caller(busy_, std::defer_lock);
        if (getpid() != pid_ || !caller.try_lock()) {
            for (int p = 0; p < parts; ++p)
                part(p);
            return;
        }
        int workers = 0;
        {
            const std::lock_guard<std::mutex> lock(m_);
            while (std::ssize(workers_) < parts - 1)
                try {
                    workers_.emplace_back(
                        [this, i = static_cast<int>(workers_.size())] { loop(i + 1); });
                } catch (...) { // no thread (system_error) or no room (bad_alloc): fewer
                    break;
                }
            workers = std::min(parts - 1, static_cast<int>(workers_.size()));
            job_ = &part;
            active_ = workers;
            pending_ = workers;
            ++generation_;
        }
        wake_.notify_all();
        part(0);
        for (int p = workers + 1; p < parts; ++p)
            part(p);
        std::unique_lock<std::mutex> lock(m_);
        done_.wait(lock, [this] { return pending_ == 0; });
        job_ = nullptr;
    }

  private:
    step_pool() = default;
    pid_t pid_ = getpid();
    void loop(int index) {
        std::uint64_t seen = 0;
        std::unique_lock<std::mutex> lock(m_);
        for (;;) {
            wake_.wait(lock, [&] { return generation_ != seen; });
            seen = generation_;
            if (index > active_) continue;
            const auto* job = job_;
            lock.unlock();
            (*job)(index);
            lock.lock();
            if (--pending_ == 0) done_.notify_all();
        }
    }
    std::mutex busy_, m_;
    std::condition_variable wake_, done_;
    std::vector<std::thread> workers_;
    const std::function<void(int)>* job_ = nullptr;
    std::uint64_t generation_ = 0;
    int active_ = 0, pending_ = 0;
};

/// body(first, last) over the steps [0, n) in `threads` contiguous parts. An exception in any
/// part is rethrown here after every part has ended.
template <class F>
void over_steps(int n, int threads, const F& body) {
    threads = std::clamp(threads, 1, std::max(n, 1));
    if (threads == 1) {
        body(0, n);
        return;
    }
    std::vector<std::exception_ptr> errors(static_cast<std::size_t>(threads));
    const std::function<void(int)> part = [&](int p) {
        try {
            body(static_cast<int>(1LL * p * n / threads),
                 static_cast<int>(1LL * (p + 1) * n / threads));
        } catch (...) {
            errors[static_cast<std::size_t>(p)] = std::current_exception();
        }
    };
    step_pool::instance().run(threads, part);
    for (const auto& e : errors)
        if (e) std::rethrow_exception(e);
}

} // namespace varsym::optimal::detail
