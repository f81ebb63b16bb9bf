// memory.h — every device buffer counted by name, group and size, and checked against the
// device before it is created.
//
// Each ocl::Device owns one MemoryLedger (Device::memory). Every buffer wavepath creates goes
// through Device::create_buffer (ocl::Array<T>, upload_buffer, the batch tracer's buffers):
// it checks the buffer against the largest allocation the device allows and the buffers
// already alive against the device's capacity, throws a wp::Error naming the buffer and both
// sizes when it does not fit, and records the buffer under the group in force (MemoryGroup:
// "scene", "bvh", "pool", "film"; "other" outside any). A buffer leaves the ledger when
// OpenCL releases it (clSetMemObjectDestructorCallback), so the ledger holds exactly the
// buffers alive.
//
// Capacity: CL_DEVICE_GLOBAL_MEM_SIZE; a CPU device that shares the host's memory
// (CL_DEVICE_HOST_UNIFIED_MEMORY) allocates from all of it (PoCL reports a fraction of the
// host's memory and allocates beyond it), so there the capacity is the larger of the two.
// Testing aid: WP_DEVICE_MEMORY_LIMIT and WP_DEVICE_MAX_ALLOC (bytes, or with a K, M or G
// suffix: binary units) make the device look smaller (Device::open), so the failure paths
// can be tested with small scenes.
#pragma once

#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

namespace wp::ocl {

struct Device;

struct BufferRecord {
    std::uint64_t id = 0;     // allocation order, from 1
    std::string group;        // MemoryGroup in force when it was created
    std::string name;         // what it holds: "the BVH nodes"
    std::uint64_t bytes = 0;  // bytes allocated (a zero-size Array still allocates one element)
};

class MemoryLedger {
  public:
    // capacity: bytes all live buffers together may take; max_alloc: bytes one buffer may
    // take; note: appended to failure messages (e.g. which environment variable lowered
    // a limit), "" for none.
    MemoryLedger(std::string device_name, std::uint64_t capacity, std::uint64_t max_alloc,
                 std::string note = "");

    std::uint64_t capacity() const { return capacity_; }
    std::uint64_t max_alloc() const { return max_alloc_; }
    std::uint64_t live_bytes() const;
    std::uint64_t available() const;              // capacity - live bytes (0 when over)
    std::vector<BufferRecord> live() const;       // in allocation order
    std::uint64_t next_id() const;                // the id the next buffer gets

    // Throws wp::Error naming `what` when one buffer of `bytes` exceeds max_alloc, or the live
    // buffers and it exceed the capacity.
    void check_buffer(std::uint64_t bytes, const std::string& what) const;
    // Only the capacity part: `bytes` more in any number of buffers.
    void check_room(std::uint64_t bytes, const std::string& what) const;

    // Records a buffer under the current group; returns its id.
    std::uint64_t add(const std::string& name, std::uint64_t bytes);
    void remove(std::uint64_t id);

    std::string group() const;
    void set_group(std::string group);

  private:
    std::string allocated_summary() const;  // "bvh 1.2 MiB, scene 3.0 MiB" (lock held)

    std::string device_;
    std::uint64_t capacity_ = 0, max_alloc_ = 0;
    std::string note_;
    mutable std::mutex mutex_;
    std::vector<BufferRecord> live_;
    std::uint64_t live_bytes_ = 0;
    std::uint64_t next_id_ = 1;
    std::string group_ = "other";
};

// Buffers created on `dev` while this is alive are counted under `group`; the previous
// group returns when it ends. Does nothing for a device without a ledger.
class MemoryGroup {
  public:
    MemoryGroup(const Device& dev, std::string group);
    ~MemoryGroup();
    MemoryGroup(const MemoryGroup&) = delete;
    MemoryGroup& operator=(const MemoryGroup&) = delete;

  private:
    MemoryLedger* ledger_ = nullptr;
    std::string previous_;
};

// "4194304", "512K", "64M", "2G" (binary units) -> bytes; throws wp::Error naming `what`
// for anything else, or for 0.
std::uint64_t parse_byte_count(const std::string& text, const std::string& what);

}  // namespace wp::ocl
