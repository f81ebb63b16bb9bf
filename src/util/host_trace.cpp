#include "util/host_trace.h"

#include <chrono>

namespace wp {

std::uint64_t steady_ns() {
    return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                          std::chrono::steady_clock::now().time_since_epoch())
                                          .count());
}

void HostTrace::add(std::string name, std::uint64_t start_ns, std::uint64_t end_ns) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (events_.size() >= kMaxEvents) return;
    events_.push_back({std::move(name), start_ns, end_ns});
}

std::vector<HostEvent> HostTrace::events() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return events_;
}

void HostTrace::clear() {
    std::lock_guard<std::mutex> lock(mutex_);
    events_.clear();
}

HostTrace& host_trace() {
    static HostTrace trace;
    return trace;
}

}  // namespace wp
