// startup.h — cold start: where the time to the first frame goes (issue 15, target 5).
//
// The first frame is the render's first sample per pixel, finished on the device. Every
// step is wall time on the steady clock, in milliseconds; `to_first_frame_ms` counts from
// the start of main() (util/process_clock.h), and `exec_to_main_ms` (process start to main:
// the dynamic loader relocating every shared library and their static constructors; 10 ms
// resolution) comes on top of it. Steps, in order:
//   load         the scene file read and parsed (or the built-in scene made)
//   device       OpenCL platform, device, context and queue (PoCL's start-up), on its own
//                thread from the start of the load; device_wait_ms is what the main thread
//                still waited for it after the load and the settings
//   scene        BVH build, flatten and upload
//   programs     every stage's program: a build from source, or the binary from the program
//                cache (cl/program.h), listed per program
//   first frame  the first sample per pixel, from its first launch to its end; of it,
//                first_frame_device_ms is the device time of its launches and
//                first_launch_ms = first_frame_ms − first_frame_device_ms the time the
//                device waited: PoCL compiles each kernel's work-group function at its first
//                launch at a new local size (its kernel cache, $POCL_CACHE_DIR, keeps them),
//                plus the enqueue latencies.
// to_first_frame_ms also holds what lies between the steps (argument parsing, settings,
// the path pool and film allocation). After the render and the image writes, a cold start
// stores the binaries of the programs it built in the program cache: cache_store_ms (not
// part of the time to the first frame; cl/program.h says why it waits).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace wp::render {

struct StartupProgram {
    std::string file;  // kernels/<file>
    double ms = 0.0;   // create + build, or load from the cache
    bool from_cache = false;
};

struct Startup {
    double exec_to_main_ms = -1.0;  // < 0: unknown
    double load_ms = 0.0;
    double device_ms = 0.0;
    double device_wait_ms = 0.0;
    double scene_ms = 0.0;
    double programs_ms = 0.0;
    std::vector<StartupProgram> programs;
    double first_frame_ms = 0.0;
    double first_frame_device_ms = 0.0;
    double first_launch_ms = 0.0;
    double to_first_frame_ms = 0.0;  // main() to the first frame done
    double cache_store_ms = 0.0;     // after the render: new binaries into the program cache
};

// {"clock": ..., "exec_to_main_ms", "load_ms", ..., "programs": [{"file", "ms",
// "from_cache"}], ..., "to_first_frame_ms", "to_first_frame_from_exec_ms"} (the last one
// absent where exec_to_main_ms is unknown).
nlohmann::json startup_json(const Startup& s);

// Two lines for `render -v`, each ending in a newline:
// "startup: 412 ms from main to the first frame (+150 ms exec to main): load 1, device 44, ..."
// "programs: generate.cl 2 ms (cache), ..."
std::string format_startup(const Startup& s);

}  // namespace wp::render
