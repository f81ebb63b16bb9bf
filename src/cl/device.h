// device.h — OpenCL platforms and devices: listing, selection, context and queue.
#pragma once

#include <CL/opencl.hpp>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "cl/memory.h"

namespace wp::ocl {

struct DeviceInfo {
    int index = 0;           // position in list_devices(), across all platforms
    std::string platform;    // platform name
    std::string platform_version;
    std::string name;        // device name
    std::string vendor;
    std::string version;     // OpenCL version string of the device
    std::string driver;      // driver version
    std::string type;        // "GPU", "CPU", "accelerator", "other"
    unsigned compute_units = 0;
    std::uint64_t global_mem = 0;     // bytes
    std::uint64_t max_alloc = 0;      // bytes, largest single buffer
    std::uint64_t cache_bytes = 0;    // CL_DEVICE_GLOBAL_MEM_CACHE_SIZE (0: none reported)
    bool host_unified = false;        // CL_DEVICE_HOST_UNIFIED_MEMORY
    bool is_gpu = false;
    ::cl::Device device;
};

// Every device of every platform, in platform order. Platforms that report no devices
// are skipped; an ICD loader with no platforms gives an empty list.
std::vector<DeviceInfo> list_devices();

// Picks a device: "" = the first GPU, else the first device; digits = index into
// list_devices(); anything else = the first device whose "platform: name" contains the
// text (case-insensitive). Throws wp::Error listing the devices when nothing matches.
DeviceInfo select_device(const std::string& selector);

// The testing aid of cl/memory.h: these make a device look smaller (bytes; K, M, G suffixes).
inline constexpr const char* kMemoryLimitEnv = "WP_DEVICE_MEMORY_LIMIT";
inline constexpr const char* kMaxAllocEnv = "WP_DEVICE_MAX_ALLOC";
// Set to 0 or "off", makes a CPU device's large buffers come from the driver like the rest
// (Device::huge_pages: for measuring what the huge pages give).
inline constexpr const char* kHugePagesEnv = "WP_HUGE_PAGES";

// Buffers of at least this many bytes on a huge-page device are host memory of the
// process's own, in transparent huge pages (Device::create_buffer). Each such buffer takes
// whole 2 MiB pages, so one of 256 KiB wastes up to 1.75 MiB; below it the driver's
// allocation is kept. The BVH's nodes and triangles and the shading data of the built-in box
// (256-769 KiB each) are above it: measured, they gain as much again as the pool
// (docs/performance.md, "Seventeenth round").
inline constexpr std::uint64_t kHugePageBufferMin = std::uint64_t(256) << 10;

// A context and an in-order, profiling-enabled queue on one device, and the ledger of its
// buffers (cl/memory.h).
struct Device {
    DeviceInfo info;
    ::cl::Context context;
    ::cl::CommandQueue queue;
    std::shared_ptr<MemoryLedger> memory;
    // A CPU device that shares the host's memory (PoCL): its buffers of at least
    // kHugePageBufferMin bytes are mapped by the process, 2 MiB-aligned, advised into
    // transparent huge pages (madvise MADV_HUGEPAGE) and handed to the driver with
    // CL_MEM_USE_HOST_PTR, which a CPU driver uses in place. The path pool, the film and
    // the BVH are read at random: in 4 KiB pages nearly every such read also misses the
    // TLB (measured: docs/performance.md, "Seventeenth round"). Off on GPUs and with
    // WP_HUGE_PAGES=0.
    bool huge_pages = false;

    // Opens the device; WP_DEVICE_MEMORY_LIMIT / WP_DEVICE_MAX_ALLOC, when set, lower
    // info.global_mem / info.max_alloc and the ledger's limits (a testing aid).
    static Device open(const std::string& selector);
    // Throws wp::Error naming `what` and the sizes when one buffer of `bytes` does not fit
    // the device: larger than its largest allocation, or more than its free memory.
    void check_alloc(std::uint64_t bytes, const std::string& what) const;
    // A buffer of `bytes`, checked (check_alloc) and counted in the ledger under `what`
    // until OpenCL releases it; an allocation the driver refuses is a wp::Error too.
    ::cl::Buffer create_buffer(cl_mem_flags flags, std::uint64_t bytes, const std::string& what) const;
};

// A read-only device buffer holding a copy of `v` (one zeroed element when `v` is empty:
// OpenCL has no empty buffers). Throws wp::Error naming `what` when the device lacks room.
template <typename T>
::cl::Buffer upload_buffer(const Device& dev, const std::vector<T>& v, const char* what) {
    std::size_t bytes = std::max<std::size_t>(v.size(), 1) * sizeof(T);
    ::cl::Buffer b = dev.create_buffer(CL_MEM_READ_ONLY, bytes, what);
    if (v.empty()) {
        T zero{};
        dev.queue.enqueueWriteBuffer(b, CL_TRUE, 0, sizeof(T), &zero);
    } else {
        dev.queue.enqueueWriteBuffer(b, CL_TRUE, 0, bytes, v.data());
    }
    return b;
}

// "1.5 GiB"-style rendering of a byte count.
std::string format_bytes(std::uint64_t bytes);

}  // namespace wp::ocl
