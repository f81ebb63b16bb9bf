// program.h — OpenCL programs from the embedded kernel sources.
//
// A program is one kernels/*.cl file with its #include "..." lines resolved from the
// embedded copies (or from the folder named by $WP_KERNEL_DIR, for editing kernels
// without rebuilding). Each included file is framed by #line markers, so a build error
// points at kernels/<file>:<line>. Build options always start with the standard set
// (-cl-std=CL1.2, no fast-relaxed-math) followed by the caller's -D options.
//
// Compiled programs are cached on disk by a hash of (source, options, device, driver):
// $WP_CACHE_DIR, else $XDG_CACHE_HOME/wavepath, else ~/.cache/wavepath. Set
// WP_CACHE_DIR=off to disable it. Storing a new binary is not free: on PoCL, reading
// CL_PROGRAM_BINARIES compiles every kernel of the program for any local size (1.8–2.3 s
// for the renderer's six programs, more than their builds); after defer_cache_stores(true)
// the stores wait for store_deferred_programs(), so that a cold `render` reaches its first
// frame without them.
#pragma once

#include <string>

#include "cl/device.h"

namespace wp::ocl {

// The full source of kernels/<file> with includes inlined and #line markers.
std::string assemble_source(const std::string& file);

struct Program {
    ::cl::Program program;
    std::string file;
    std::string options;     // the full option string passed to the compiler
    double build_ms = 0.0;   // wall time to create + build (or load from the cache), and
                             // to store a new binary unless the store is deferred
    bool from_cache = false;

    // Builds kernels/<file> for the device. Throws wp::Error with the build log.
    static Program build(const Device& dev, const std::string& file, const std::string& options = "");
    ::cl::Kernel kernel(const std::string& name) const;
};

// From now on (true) Program::build leaves the cache store of a program it built from source
// for store_deferred_programs(); false (the default) stores at once. Process-wide.
void defer_cache_stores(bool defer);
// Stores every deferred binary (best effort, as the immediate store); returns the wall time
// it took in ms (0 when nothing was deferred). Thread-safe.
double store_deferred_programs();

}  // namespace wp::ocl
