// host_trace.h — host work for the trace (issue 12, item 7): named spans of the steady clock.
//
// The renderer marks its host stages (scene load, device start-up, BVH build, program
// builds, upload, film resolve, image write) with HostSpan; the Chrome trace (render/profile.h) shows them on
// their own track beside the device queue, shifted onto the device's profiling clock. One
// recorder per process (host_trace()), thread-safe, keeping at most kMaxEvents spans (a
// process that renders many times, such as the tests, does not grow without bound).
#pragma once

#include <cstdint>
#include <mutex>
#include <utility>
#include <string>
#include <vector>

namespace wp {

struct HostEvent {
    std::string name;
    std::uint64_t start_ns = 0, end_ns = 0;  // steady clock
};

// Now on the steady clock, in nanoseconds.
std::uint64_t steady_ns();

class HostTrace {
  public:
    static constexpr std::size_t kMaxEvents = 4096;
    void add(std::string name, std::uint64_t start_ns, std::uint64_t end_ns);
    std::vector<HostEvent> events() const;
    void clear();

  private:
    mutable std::mutex mutex_;
    std::vector<HostEvent> events_;
};

// The process's recorder.
HostTrace& host_trace();

// Records [construction, destruction) as `name` in host_trace().
class HostSpan {
  public:
    explicit HostSpan(std::string name) : name_(std::move(name)), start_(steady_ns()) {}
    ~HostSpan() { host_trace().add(std::move(name_), start_, steady_ns()); }
    HostSpan(const HostSpan&) = delete;
    HostSpan& operator=(const HostSpan&) = delete;

  private:
    std::string name_;
    std::uint64_t start_;
};

}  // namespace wp
