#include "cl/memory.h"

#include <algorithm>
#include <cctype>
#include <map>

#include "cl/device.h"
#include "util/error.h"

namespace wp::ocl {

MemoryLedger::MemoryLedger(std::string device_name, std::uint64_t capacity, std::uint64_t max_alloc,
                           std::string note)
    : device_(std::move(device_name)), capacity_(capacity), max_alloc_(max_alloc), note_(std::move(note)) {}

std::uint64_t MemoryLedger::live_bytes() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return live_bytes_;
}

std::uint64_t MemoryLedger::available() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return live_bytes_ >= capacity_ ? 0 : capacity_ - live_bytes_;
}

std::vector<BufferRecord> MemoryLedger::live() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return live_;
}

std::uint64_t MemoryLedger::next_id() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return next_id_;
}

std::string MemoryLedger::allocated_summary() const {
    std::map<std::string, std::uint64_t> by_group;
    for (const auto& r : live_) by_group[r.group] += r.bytes;
    std::string s;
    for (const auto& [g, b] : by_group) s += (s.empty() ? "" : ", ") + g + " " + format_bytes(b);
    return s.empty() ? "nothing" : s;
}

void MemoryLedger::check_buffer(std::uint64_t bytes, const std::string& what) const {
    if (bytes > max_alloc_)
        fail("buffer too large for {}: {} needed, but device '{}' allows at most {} per buffer{}",
             what, format_bytes(bytes), device_, format_bytes(max_alloc_), note_);
    check_room(bytes, what);
}

void MemoryLedger::check_room(std::uint64_t bytes, const std::string& what) const {
    std::lock_guard<std::mutex> lock(mutex_);
    const std::uint64_t free = live_bytes_ >= capacity_ ? 0 : capacity_ - live_bytes_;
    if (bytes > free)
        fail("not enough device memory for {}: {} needed, but device '{}' has only {} of its {} "
             "free (already allocated: {}){}",
             what, format_bytes(bytes), device_, format_bytes(free), format_bytes(capacity_),
             allocated_summary(), note_);
}

std::uint64_t MemoryLedger::add(const std::string& name, std::uint64_t bytes) {
    std::lock_guard<std::mutex> lock(mutex_);
    BufferRecord r{next_id_++, group_, name, bytes};
    live_.push_back(r);
    live_bytes_ += bytes;
    return r.id;
}

void MemoryLedger::remove(std::uint64_t id) {
    std::lock_guard<std::mutex> lock(mutex_);
    // Ids are increasing, so live_ is sorted by id.
    auto it = std::lower_bound(live_.begin(), live_.end(), id,
                               [](const BufferRecord& r, std::uint64_t i) { return r.id < i; });
    if (it == live_.end() || it->id != id) return;
    live_bytes_ -= it->bytes;
    live_.erase(it);
}

std::string MemoryLedger::group() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return group_;
}

void MemoryLedger::set_group(std::string group) {
    std::lock_guard<std::mutex> lock(mutex_);
    group_ = std::move(group);
}

MemoryGroup::MemoryGroup(const Device& dev, std::string group) : ledger_(dev.memory.get()) {
    if (!ledger_) return;
    previous_ = ledger_->group();
    ledger_->set_group(std::move(group));
}

MemoryGroup::~MemoryGroup() {
    if (ledger_) ledger_->set_group(previous_);
}

std::uint64_t parse_byte_count(const std::string& text, const std::string& what) {
    std::size_t i = 0;
    std::uint64_t v = 0;
    while (i < text.size() && std::isdigit(static_cast<unsigned char>(text[i]))) {
        const std::uint64_t d = static_cast<std::uint64_t>(text[i] - '0');
        if (v > (UINT64_MAX - d) / 10) fail("{}: '{}' is too large", what, text);
        v = v * 10 + d;
        ++i;
    }
    int shift = 0;
    if (i + 1 == text.size()) {
        switch (std::toupper(static_cast<unsigned char>(text[i]))) {
        case 'K': shift = 10; break;
        case 'M': shift = 20; break;
        case 'G': shift = 30; break;
        default: shift = -1;
        }
        ++i;
    }
    if (i == 0 || i != text.size() || shift < 0 || v == 0)
        fail("{}: '{}' is not a byte count > 0 (digits, optionally followed by K, M or G)", what, text);
    if (v > (UINT64_MAX >> shift)) fail("{}: '{}' is too large", what, text);
    return v << shift;
}

}  // namespace wp::ocl
