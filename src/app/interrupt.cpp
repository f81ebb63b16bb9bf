#include "app/interrupt.h"

#include <atomic>
#include <csignal>

#include <signal.h>

namespace wp::app {

namespace {

std::atomic<int> g_signal{0};
static_assert(std::atomic<int>::is_always_lock_free, "the flag must be async-signal-safe");

extern "C" void on_interrupt(int sig) {
    int expected = 0;
    if (g_signal.compare_exchange_strong(expected, sig)) return;  // first: keep the work
    // Second: the default action (terminate), delivered when this handler returns.
    std::signal(sig, SIG_DFL);
    std::raise(sig);
}

}  // namespace

void install_interrupt_handler() {
    struct sigaction sa {};
    sa.sa_handler = on_interrupt;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
}

int interrupt_signal() { return g_signal.load(); }

}  // namespace wp::app
