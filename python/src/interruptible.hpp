// python/src/interruptible.hpp: long work without the GIL that Ctrl-C stops within a fraction of
// a second, for varsym._core and varsym._tool. The work runs on a thread of its own; the calling
// thread, which holds the GIL, waits for it 20 ms at a time and runs Python's signal handlers
// in between (PyErr_CheckSignals: only the main thread sees Ctrl-C, and only while it runs
// Python code or calls this).
#pragma once

#include <pybind11/pybind11.h>

#include <chrono>
#include <exception>
#include <functional>
#include <future>
#include <optional>
#include <thread>

namespace varsym_python {

/// Runs work() on another thread. On KeyboardInterrupt (Ctrl-C) calls stop() once, which must
/// make work() return soon (a flag its loops watch), waits for it, clears the error and returns
/// true. Another exception raised by a Python signal handler stops it the same way and is
/// rethrown after the wait; an exception from work() is rethrown. Call with the GIL held.
inline bool run_interruptible(const std::function<void()>& work,
                              const std::function<void()>& stop) {
    std::promise<void> finished;
    std::future<void> done = finished.get_future();
    std::exception_ptr failure;
    std::thread worker([&] {
        try {
            work();
        } catch (...) {
            failure = std::current_exception();
        }
        finished.set_value();
    });
    bool interrupted = false;
    std::optional<pybind11::error_already_set> raised;
    for (;;) {
        bool ready = false;
        {
            pybind11::gil_scoped_release unlocked;
            ready = done.wait_for(std::chrono::milliseconds(20)) == std::future_status::ready;
        }
        if (ready) break;
        if (interrupted || raised || PyErr_CheckSignals() == 0) continue;
        if (PyErr_ExceptionMatches(PyExc_KeyboardInterrupt)) {
            PyErr_Clear();
            interrupted = true;
        } else {
            raised.emplace(); // takes the error
        }
        stop();
    }
    worker.join();
    if (failure) std::rethrow_exception(failure);
    if (raised) throw *raised;
    return interrupted;
}

} // namespace varsym_python
