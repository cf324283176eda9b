// apps/varsym/output/signals.cpp: the handlers of SIGINT and SIGTERM (signals.hpp). Only
// async-signal-safe calls in the handler: clock_gettime, unlink, signal, raise.
#include "signals.hpp"

#include <array>
#include <atomic>
#include <csignal>
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
    struct sigaction sa {};
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
}

void set_signal_polling(bool on) {
    polling = on ? 1 : 0;
}

int pending_signal() {
    return received;
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
