#include "cl/device.h"

#include <algorithm>
#include <cctype>

#include <fmt/format.h>

#include "util/error.h"

namespace wp::ocl {

namespace {

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

std::string type_name(cl_device_type t) {
    if (t & CL_DEVICE_TYPE_GPU) return "GPU";
    if (t & CL_DEVICE_TYPE_CPU) return "CPU";
    if (t & CL_DEVICE_TYPE_ACCELERATOR) return "accelerator";
    return "other";
}

std::string device_list_text(const std::vector<DeviceInfo>& devices) {
    std::string s;
    for (const auto& d : devices) s += fmt::format("\n  [{}] {}: {} ({})", d.index, d.platform, d.name, d.type);
    return s.empty() ? "\n  (none: is an OpenCL driver such as pocl-opencl-icd installed?)" : s;
}

}  // namespace

std::vector<DeviceInfo> list_devices() {
    std::vector<::cl::Platform> platforms;
    try {
        ::cl::Platform::get(&platforms);
    } catch (const ::cl::Error& e) {
        if (e.err() == CL_PLATFORM_NOT_FOUND_KHR) return {};
        throw;
    }
    std::vector<DeviceInfo> out;
    for (auto& p : platforms) {
        std::vector<::cl::Device> devices;
        try {
            p.getDevices(CL_DEVICE_TYPE_ALL, &devices);
        } catch (const ::cl::Error&) {
            continue;  // CL_DEVICE_NOT_FOUND: a platform without devices
        }
        for (auto& d : devices) {
            DeviceInfo info;
            info.index = static_cast<int>(out.size());
            info.platform = p.getInfo<CL_PLATFORM_NAME>();
            info.platform_version = p.getInfo<CL_PLATFORM_VERSION>();
            info.name = d.getInfo<CL_DEVICE_NAME>();
            info.vendor = d.getInfo<CL_DEVICE_VENDOR>();
            info.version = d.getInfo<CL_DEVICE_VERSION>();
            info.driver = d.getInfo<CL_DRIVER_VERSION>();
            auto t = d.getInfo<CL_DEVICE_TYPE>();
            info.type = type_name(t);
            info.is_gpu = (t & CL_DEVICE_TYPE_GPU) != 0;
            info.compute_units = d.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>();
            info.global_mem = d.getInfo<CL_DEVICE_GLOBAL_MEM_SIZE>();
            info.max_alloc = d.getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>();
            info.device = d;
            out.push_back(std::move(info));
        }
    }
    return out;
}

DeviceInfo select_device(const std::string& selector) {
    auto devices = list_devices();
    if (devices.empty()) fail("no OpenCL device found{}", device_list_text(devices));
    if (selector.empty()) {
        for (auto& d : devices)
            if (d.is_gpu) return d;
        return devices.front();
    }
    if (std::all_of(selector.begin(), selector.end(), [](unsigned char c) { return std::isdigit(c); })) {
        std::size_t i = std::stoul(selector);
        if (i < devices.size()) return devices[i];
        fail("device index {} out of range; devices:{}", i, device_list_text(devices));
    }
    std::string needle = lower(selector);
    for (auto& d : devices)
        if (lower(d.platform + ": " + d.name).find(needle) != std::string::npos) return d;
    fail("no OpenCL device matches '{}'; devices:{}", selector, device_list_text(devices));
}

Device Device::open(const std::string& selector) {
    Device d;
    d.info = select_device(selector);
    d.context = ::cl::Context(d.info.device);
    d.queue = ::cl::CommandQueue(d.context, d.info.device, CL_QUEUE_PROFILING_ENABLE);
    return d;
}

void Device::check_alloc(std::uint64_t bytes, const std::string& what) const {
    if (bytes > info.max_alloc)
        fail("{} needs a buffer of {}, but device '{}' allows at most {} per buffer", what,
             format_bytes(bytes), info.name, format_bytes(info.max_alloc));
    if (bytes > info.global_mem)
        fail("{} needs {}, but device '{}' has {} of memory", what, format_bytes(bytes), info.name,
             format_bytes(info.global_mem));
}

std::string format_bytes(std::uint64_t bytes) {
    const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
    double v = static_cast<double>(bytes);
    int u = 0;
    while (v >= 1024.0 && u < 4) {
        v /= 1024.0;
        ++u;
    }
    return u == 0 ? fmt::format("{} B", bytes) : fmt::format("{:.1f} {}", v, units[u]);
}

}  // namespace wp::ocl
