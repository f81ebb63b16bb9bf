// cmd_devices.cpp — `wavepath devices`: every OpenCL platform and device.
#include <fmt/format.h>

#include "app/subcommands.h"
#include "cl/device.h"

namespace wp::app {

Subcommand add_devices(CLI::App& app) {
    Subcommand s;
    s.app = app.add_subcommand("devices", "List every OpenCL platform and device with its index");
    s.run = [] {
        auto devices = ocl::list_devices();
        if (devices.empty()) {
            fmt::print(stderr, "no OpenCL devices found (is an OpenCL driver such as pocl-opencl-icd installed?)\n");
            return 1;
        }
        for (const auto& d : devices) {
            fmt::print("[{}] {}: {}\n    type {}, {} compute units, {} memory ({} per buffer)\n    {}, driver {}\n",
                       d.index, d.platform, d.name, d.type, d.compute_units, ocl::format_bytes(d.global_mem),
                       ocl::format_bytes(d.max_alloc), d.version, d.driver);
        }
        return 0;
    };
    return s;
}

}  // namespace wp::app
