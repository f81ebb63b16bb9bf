#include "cl/device.h"

#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>

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
            info.cache_bytes = d.getInfo<CL_DEVICE_GLOBAL_MEM_CACHE_SIZE>();
            info.host_unified = d.getInfo<CL_DEVICE_HOST_UNIFIED_MEMORY>() == CL_TRUE;
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

namespace {

// The host's physical memory in bytes (0 when unknown).
std::uint64_t host_memory() {
    const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
    return pages > 0 && page > 0 ? std::uint64_t(pages) * std::uint64_t(page) : 0;
}

// The value of a byte-count environment variable, or 0 when it is unset or empty.
std::uint64_t env_bytes(const char* name) {
    const char* v = std::getenv(name);
    if (!v || !*v) return 0;
    return parse_byte_count(v, name);
}

// Receives OpenCL's release of a counted buffer (clSetMemObjectDestructorCallback).
struct ReleaseToken {
    std::weak_ptr<MemoryLedger> ledger;
    std::uint64_t id = 0;
};

void CL_CALLBACK on_release(cl_mem, void* user) {
    auto* t = static_cast<ReleaseToken*>(user);
    if (auto l = t->ledger.lock()) l->remove(t->id);
    delete t;
}

// Host memory for a buffer of `bytes` in transparent huge pages: an anonymous mapping
// rounded up to whole 2 MiB pages and aligned to one, advised MADV_HUGEPAGE before anything
// touches it, so the first touch of each 2 MiB faults in one huge page (when the kernel's
// THP setting is "madvise" or "always"; with "never" the advice is a no-op and the pages
// stay small). Null when the mapping fails (the caller falls back to the driver's memory).
constexpr std::size_t kHugePage = std::size_t(2) << 20;

struct HugeMapping {
    void* base = nullptr;  // what munmap takes
    std::size_t length = 0;
    void* data = nullptr;  // the 2 MiB-aligned start handed to the driver
};

HugeMapping map_huge(std::uint64_t bytes) {
    HugeMapping m;
    const std::size_t rounded = (static_cast<std::size_t>(bytes) + kHugePage - 1) & ~(kHugePage - 1);
    m.length = rounded + kHugePage;  // room to align the start
    void* p = ::mmap(nullptr, m.length, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) return {};
    m.base = p;
    const auto addr = reinterpret_cast<std::uintptr_t>(p);
    m.data = reinterpret_cast<void*>((addr + kHugePage - 1) & ~std::uintptr_t(kHugePage - 1));
#ifdef MADV_HUGEPAGE
    ::madvise(m.data, rounded, MADV_HUGEPAGE);  // advice only: its failure changes nothing
#endif
    return m;
}

// Unmaps a HugeMapping once OpenCL has released the buffer that used it.
void CL_CALLBACK on_release_mapping(cl_mem, void* user) {
    auto* m = static_cast<HugeMapping*>(user);
    ::munmap(m->base, m->length);
    delete m;
}

bool env_off(const char* name) {
    const char* v = std::getenv(name);
    return v && (std::string(v) == "0" || lower(v) == "off");
}

}  // namespace

Device Device::open(const std::string& selector) {
    Device d;
    d.info = select_device(selector);
    // A CPU device sharing the host's memory allocates from all of it (cl/memory.h).
    std::uint64_t capacity = d.info.global_mem;
    if (!d.info.is_gpu && d.info.host_unified) capacity = std::max(capacity, host_memory());
    std::string note;
    if (const std::uint64_t limit = env_bytes(kMemoryLimitEnv)) {
        d.info.global_mem = std::min<std::uint64_t>(d.info.global_mem, limit);
        capacity = std::min(capacity, limit);
        note += fmt::format(", {}={}", kMemoryLimitEnv, limit);
    }
    if (const std::uint64_t limit = env_bytes(kMaxAllocEnv)) {
        d.info.max_alloc = std::min<std::uint64_t>(d.info.max_alloc, limit);
        note += fmt::format(", {}={}", kMaxAllocEnv, limit);
    }
    if (!note.empty()) note = " (limited by" + note.substr(1) + ")";
    d.memory = std::make_shared<MemoryLedger>(d.info.name, capacity, d.info.max_alloc, note);
    d.context = ::cl::Context(d.info.device);
    d.queue = ::cl::CommandQueue(d.context, d.info.device, CL_QUEUE_PROFILING_ENABLE);
    d.huge_pages = !d.info.is_gpu && d.info.host_unified && !env_off(kHugePagesEnv);
    return d;
}

void Device::check_alloc(std::uint64_t bytes, const std::string& what) const {
    if (memory) return memory->check_buffer(bytes, what);
    // A Device not made by open(): its limits only.
    MemoryLedger(info.name, info.global_mem, info.max_alloc).check_buffer(bytes, what);
}

::cl::Buffer Device::create_buffer(cl_mem_flags flags, std::uint64_t bytes, const std::string& what) const {
    check_alloc(bytes, what);
    ::cl::Buffer b;
    HugeMapping* mapping = nullptr;
    if (huge_pages && bytes >= kHugePageBufferMin &&
        !(flags & (CL_MEM_USE_HOST_PTR | CL_MEM_ALLOC_HOST_PTR | CL_MEM_COPY_HOST_PTR))) {
        if (HugeMapping m = map_huge(bytes); m.base) mapping = new HugeMapping(m);
    }
    try {
        b = mapping ? ::cl::Buffer(context, flags | CL_MEM_USE_HOST_PTR, bytes, mapping->data)
                    : ::cl::Buffer(context, flags, bytes);
    } catch (const ::cl::Error& e) {
        if (mapping) {
            ::munmap(mapping->base, mapping->length);
            delete mapping;
        }
        fail("device '{}' refused a buffer of {} for {} (OpenCL error {} in {})", info.name,
             format_bytes(bytes), what, e.err(), e.what());
    }
    if (mapping) {
        try {
            b.setDestructorCallback(&on_release_mapping, mapping);  // called after the ledger's
        } catch (const ::cl::Error&) {
            // A driver that cannot say when it lets go of the memory: keep it mapped.
        }
    }
    if (memory) {
        auto* token = new ReleaseToken{memory, memory->add(what, bytes)};
        try {
            b.setDestructorCallback(&on_release, token);
        } catch (const ::cl::Error&) {
            memory->remove(token->id);  // not counted: the device cannot tell us when it goes
            delete token;
        }
    }
    return b;
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
