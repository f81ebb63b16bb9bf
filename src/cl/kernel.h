// kernel.h — typed device arrays and named kernels launched with their arguments in order.
//
// Array<T> is a device buffer of `size` elements of one shared type (kernels/shared/types.h),
// so a stage's enqueue(...) says what each buffer holds. Kernel binds all of a kernel's
// arguments in one call, in the kernel's own order, and checks their number against the
// compiled kernel (CL_KERNEL_NUM_ARGS): a launcher whose parameter list drifts from the
// .cl signature fails at its first launch with both names, instead of reading garbage.
// No code outside this file sets a kernel argument by its index.
#pragma once

#include <CL/opencl.hpp>

#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include "cl/device.h"
#include "cl/profiler.h"
#include "cl/program.h"

namespace wp::ocl {

// A device buffer of `size` elements of T. A zero-size array still owns one element
// (OpenCL has no empty buffers), so placeholders of features a scene does not use cost
// 16 bytes at most.
template <typename T>
struct Array {
    ::cl::Buffer buffer;
    std::size_t size = 0;

    std::size_t bytes() const { return size * sizeof(T); }

    // Uninitialised storage for n elements, counted in the device's ledger as `what`
    // (cl/memory.h); throws wp::Error naming `what` when the device cannot hold it.
    static Array allocate(const Device& dev, std::size_t n, const char* what) {
        Array a;
        a.size = n;
        std::size_t bytes = std::max<std::size_t>(n, 1) * sizeof(T);
        a.buffer = dev.create_buffer(CL_MEM_READ_WRITE, bytes, what);
        return a;
    }
    // n zeroed elements.
    static Array zeros(const Device& dev, std::size_t n, const char* what) {
        Array a = allocate(dev, n, what);
        a.fill_zero(dev);
        return a;
    }
    // A copy of v.
    static Array upload(const Device& dev, const std::vector<T>& v, const char* what) {
        Array a;
        a.buffer = upload_buffer(dev, v, what);
        a.size = v.size();
        return a;
    }
    // Enqueues a fill with zero bytes (not blocking; the queue is in order).
    void fill_zero(const Device& dev) const {
        std::size_t n = std::max<std::size_t>(size, 1) * sizeof(T);
        if (n % 4 == 0)
            dev.queue.enqueueFillBuffer(buffer, std::uint32_t(0), 0, n);
        else
            dev.queue.enqueueFillBuffer(buffer, std::uint8_t(0), 0, n);
    }
    // Blocking read of elements [first, first + n).
    std::vector<T> read(const Device& dev, std::size_t first = 0, std::size_t n = SIZE_MAX) const {
        if (n == SIZE_MAX) n = size - first;
        std::vector<T> v(n);
        if (n > 0) dev.queue.enqueueReadBuffer(buffer, CL_TRUE, first * sizeof(T), n * sizeof(T), v.data());
        return v;
    }
    // Blocking write of v at element 0.
    void write(const Device& dev, const std::vector<T>& v) const {
        if (!v.empty()) dev.queue.enqueueWriteBuffer(buffer, CL_TRUE, 0, v.size() * sizeof(T), v.data());
    }
};

// Where launches go: the queue, and the profiler that records them (may be null).
struct LaunchTarget {
    const ::cl::CommandQueue* queue = nullptr;
    Profiler* profiler = nullptr;
};

// One entry point of a program, with the name it is profiled under.
class Kernel {
  public:
    Kernel() = default;
    // `entry` is the kernel function in the program; `label` its profiling name
    // ("intersect.closest"), by default the entry name; `local` its local size (kLocalSize,
    // WP_GROUP_SIZE, unless the kernel shares nothing within a group and wants another).
    Kernel(const Program& program, const std::string& entry, std::string label = "",
           std::size_t local = kLocalSize);

    const std::string& entry() const { return entry_; }
    const std::string& label() const { return label_; }
    explicit operator bool() const { return arg_count_ > 0 || !entry_.empty(); }

    // Binds args to arguments 0, 1, ... in order and enqueues `items` work-items (padded to
    // the fixed local size). Throws wp::Error when the number of args differs from the
    // kernel's.
    template <typename... A>
    ::cl::Event launch(const LaunchTarget& target, std::size_t items, const A&... args) {
        check_arg_count(sizeof...(A));
        cl_uint i = 0;
        (set(i++, args), ...);
        return ocl::launch(*target.queue, kernel_, label_, items, target.profiler, local_);
    }

  private:
    template <typename T>
    void set(cl_uint index, const Array<T>& a) { kernel_.setArg(index, a.buffer); }
    void set(cl_uint index, const ::cl::Buffer& b) { kernel_.setArg(index, b); }
    template <typename T>
    void set(cl_uint index, const T& v) {
        static_assert(std::is_trivially_copyable_v<T>, "kernel arguments are plain data or arrays");
        kernel_.setArg(index, v);
    }
    void check_arg_count(std::size_t given) const;

    ::cl::Kernel kernel_;
    std::string entry_, label_, file_;
    cl_uint arg_count_ = 0;
    std::size_t local_ = kLocalSize;
};

}  // namespace wp::ocl
