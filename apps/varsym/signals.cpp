// apps/varsym/signals.cpp: the handlers of SIGINT and SIGTERM (signals.hpp). Only
// async-signal-safe calls in the handler: unlink, signal, raise.
#include "signals.hpp"

#include <array>
#include <atomic>
#include <csignal>
#include <cstring>

#include <unistd.h>

namespace varsym::cli {

namespace {

constexpr std::size_t slots = 16, path_max = 4096;
std::array<std::array<char, path_max>, slots> temporary{}; // "" = free
std::array<std::atomic<bool>, slots> in_use{};
volatile std::sig_atomic_t polling = 0;
volatile std::sig_atomic_t received = 0;

extern "C" void on_signal(int sig) {
    if (polling != 0 && received == 0) {
        received = sig;
        return;
    }
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
