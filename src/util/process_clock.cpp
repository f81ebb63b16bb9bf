#include "util/process_clock.h"

#include <time.h>
#include <unistd.h>

#include <atomic>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include "util/host_trace.h"

namespace wp {

namespace {

std::atomic<std::uint64_t> g_main_start{0};

// Seconds since boot at which this process started (field 22 of /proc/self/stat, after the
// command name in parentheses, which may itself hold spaces); < 0 where unreadable.
double process_start_since_boot_s() {
    std::ifstream in("/proc/self/stat");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::size_t close = text.rfind(')');
    if (close == std::string::npos) return -1.0;
    std::istringstream fields(text.substr(close + 2));
    std::string f;
    // Fields 3..21 precede starttime (field 22).
    for (int i = 3; i <= 22; ++i)
        if (!(fields >> f)) return -1.0;
    const long hz = sysconf(_SC_CLK_TCK);
    if (hz <= 0) return -1.0;
    try {
        return double(std::stoull(f)) / double(hz);
    } catch (const std::exception&) {
        return -1.0;
    }
}

}  // namespace

void mark_main_start() {
    std::uint64_t expected = 0;
    g_main_start.compare_exchange_strong(expected, steady_ns());
}

std::uint64_t main_start_ns() {
    mark_main_start();  // keeps an earlier mark
    return g_main_start.load();
}

double exec_to_main_ms() {
    const double start_s = process_start_since_boot_s();
    timespec boot{};
    if (start_s < 0.0 || clock_gettime(CLOCK_BOOTTIME, &boot) != 0) return -1.0;
    // Now on both clocks, then back from now to main's mark.
    const double now_since_boot_s = double(boot.tv_sec) + 1e-9 * double(boot.tv_nsec);
    const double since_main_ms = double(steady_ns() - main_start_ns()) * 1e-6;
    const double ms = (now_since_boot_s - start_s) * 1e3 - since_main_ms;
    return ms >= 0.0 ? ms : -1.0;
}

}  // namespace wp
