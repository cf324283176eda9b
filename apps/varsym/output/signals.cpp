// apps/varsym/output/signals.cpp: the handlers of SIGINT and SIGTERM (signals.hpp). Only
// async-signal-safe calls in the handler: clock_gettime, unlink, signal, raise, write.
#include "output/signals.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <ctime>

#include <unistd.h>

namespace varsym::cli {

namespace {

constexpr std::size_t slots = 16, path_max = 4096;
std::array<std::array<char, path_max>, slots> temporary{}; // "" = free
std::array<std::atomic<bool>, slots> in_use{};
volatile std::sig_atomic_t polling = 0;
volatile std::sig_atomic_t received = 0;
std::atomic<long long> received_at{0}; // CLOCK_MONOTONIC ns of the first signal
std::atomic<bool> stop{false};         // set with `received` (lock-free: safe in a handler)
std::atomic<bool> embedded{false};
std::array<char, 512> first_sigint{}; // the line a first SIGINT prints while polling
std::atomic<std::size_t> first_sigint_length{0};

long long monotonic_ns() {
    timespec ts{};
    ::clock_gettime(CLOCK_MONOTONIC, &ts); // async-signal-safe
    return static_cast<long long>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

extern "C" void on_signal(int sig) {
    const long long now = monotonic_ns();
    if (polling != 0 && received == 0) {
        received_at.store(now);
        received = sig;
        stop.store(true);
        if (sig == SIGINT) // write(2) is async-signal-safe; the line was made beforehand
            (void)!::write(STDERR_FILENO, first_sigint.data(), first_sigint_length.load());
        return;
    }
    // The same signal again within a second is the same request delivered twice: timeout(1)
    // signals the process and then its process group, a terminal's Ctrl-C the whole group.
    if (received == sig && now - received_at.load() < 1'000'000'000) return;
    for (std::size_t i = 0; i < slots; ++i)
        if (in_use[i].load()) ::unlink(temporary[i].data());
    std::signal(sig, SIG_DFL);
    std::raise(sig);
}

} // namespace

void install_signal_handlers() {
    if (embedded.load()) return;
    struct sigaction sa {};
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
}

void set_signal_polling(bool on, const char* finishing) {
    if (on) {
        first_sigint_length.store(0);
        const int n = std::snprintf(first_sigint.data(), first_sigint.size(),
                                    "varsym: SIGINT: stopping once %s, keeping what is done; "
                                    "Ctrl-C again stops at once\n",
                                    finishing != nullptr ? finishing : "the current step finishes");
        first_sigint_length.store(
            std::min(static_cast<std::size_t>(std::max(n, 0)), first_sigint.size() - 1));
    }
    polling = on ? 1 : 0;
}

int pending_signal() {
    return received;
}

const std::atomic<bool>& stop_flag() {
    return stop;
}

void set_embedded(bool on) {
    embedded.store(on);
}

void request_stop(int sig) {
    if (received == 0) {
        received_at.store(monotonic_ns());
        received = sig;
    }
    stop.store(true);
}

void clear_pending_signal() {
    received = 0;
    stop.store(false);
}

void remove_at_signal(const std::string& path) {
    if (path.size() >= path_max) return;
    for (std::size_t i = 0; i < slots; ++i) {
        if (in_use[i].load()) continue;
        std::memcpy(temporary[i].data(), path.c_str(), path.size() + 1);
        in_use[i].store(true);
        return;
    }
}

void forget_at_signal(const std::string& path) {
    for (std::size_t i = 0; i < slots; ++i)
        if (in_use[i].load() && path == temporary[i].data()) {
            in_use[i].store(false);
            return;
        }
}

} // namespace varsym::cli
