// device.h — OpenCL platforms and devices: listing, selection, context and queue.
#pragma once

#include <CL/opencl.hpp>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

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

// A context and an in-order, profiling-enabled queue on one device.
struct Device {
    DeviceInfo info;
    ::cl::Context context;
    ::cl::CommandQueue queue;

    static Device open(const std::string& selector);
    // Throws wp::Error when `bytes` exceed what the device can hold, naming `what`.
    void check_alloc(std::uint64_t bytes, const std::string& what) const;
};

// A read-only device buffer holding a copy of `v` (one zeroed element when `v` is empty:
// OpenCL has no empty buffers). Throws wp::Error naming `what` when the device lacks room.
template <typename T>
::cl::Buffer upload_buffer(const Device& dev, const std::vector<T>& v, const char* what) {
    std::size_t bytes = std::max<std::size_t>(v.size(), 1) * sizeof(T);
    dev.check_alloc(bytes, what);
    ::cl::Buffer b(dev.context, CL_MEM_READ_ONLY, bytes);
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
