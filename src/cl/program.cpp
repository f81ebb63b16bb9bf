#include "cl/program.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <regex>
#include <set>
#include <sstream>

#include <fmt/format.h>

#include "cl/embedded.h"
#include "util/atomic_file.h"
#include "util/error.h"
#include "util/timer.h"

namespace wp::ocl {

namespace fs = std::filesystem;

namespace {

// The text of kernels/<path>, from $WP_KERNEL_DIR when set, else the embedded copy.
std::string read_kernel_file(const std::string& path) {
    if (const char* dir = std::getenv("WP_KERNEL_DIR"); dir && *dir) {
        std::ifstream in(fs::path(dir) / path, std::ios::binary);
        if (!in) fail("kernel file '{}' not found in WP_KERNEL_DIR='{}'", path, dir);
        std::stringstream ss;
        ss << in.rdbuf();
        return ss.str();
    }
    for (const auto& f : embedded_kernel_files())
        if (path == f.path) return f.text;
    fail("kernel file '{}' is not among the embedded kernel sources", path);
}

void append_resolved(const std::string& path, std::string& out, std::set<std::string>& seen) {
    if (!seen.insert(path).second) return;  // every header has include guards; skip repeats
    static const std::regex include_re(R"re(^\s*#\s*include\s*"([^"]+)"\s*$)re");
    std::string dir = fs::path(path).parent_path().string();
    std::istringstream in(read_kernel_file(path));
    std::string line;
    int lineno = 0;
    out += fmt::format("#line 1 \"kernels/{}\"\n", path);
    while (std::getline(in, line)) {
        ++lineno;
        std::smatch m;
        if (std::regex_match(line, m, include_re)) {
            std::string inc = (fs::path(dir) / m[1].str()).lexically_normal().generic_string();
            append_resolved(inc, out, seen);
            out += fmt::format("#line {} \"kernels/{}\"\n", lineno + 1, path);
        } else {
            out += line;
            out += '\n';
        }
    }
}

std::uint64_t fnv1a(const std::string& s, std::uint64_t h = 1469598103934665603ull) {
    for (unsigned char c : s) {
        h ^= c;
        h *= 1099511628211ull;
    }
    return h;
}

std::optional<fs::path> cache_dir() {
    if (const char* d = std::getenv("WP_CACHE_DIR"); d && *d) {
        if (std::string(d) == "off") return std::nullopt;
        return fs::path(d);
    }
    if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return fs::path(x) / "wavepath";
    if (const char* h = std::getenv("HOME"); h && *h) return fs::path(h) / ".cache" / "wavepath";
    return std::nullopt;
}

std::string build_log(const ::cl::Program& p, const ::cl::Device& d) {
    try {
        return p.getBuildInfo<CL_PROGRAM_BUILD_LOG>(d);
    } catch (const ::cl::Error&) {
        return "(no build log)";
    }
}

// The binary of a built program into the cache file `path` (best effort: a read-only
// cache or a driver without binaries is not an error).
void store_binary(const ::cl::Program& program, const fs::path& path) {
    try {
        auto bins = program.getInfo<CL_PROGRAM_BINARIES>();
        if (bins.size() == 1 && !bins[0].empty()) {
            std::error_code ec;
            fs::create_directories(path.parent_path(), ec);
            write_text_atomically(path, std::string(bins[0].begin(), bins[0].end()));
        }
    } catch (const std::exception&) {
    }
}

struct DeferredStore {
    ::cl::Program program;
    fs::path path;
};
std::mutex g_deferred_mutex;
bool g_defer = false;
std::vector<DeferredStore> g_deferred;

}  // namespace

std::string assemble_source(const std::string& file) {
    std::string out;
    std::set<std::string> seen;
    append_resolved(file, out, seen);
    return out;
}

Program Program::build(const Device& dev, const std::string& file, const std::string& options) {
    Timer timer;
    Program prog;
    prog.file = file;
    prog.options = "-cl-std=CL1.2 -I. " + options;
    // Extra build options for profiling (e.g. WP_CL_OPTIONS=-g: line tables in PoCL's
    // kernel binaries for perf annotate and callgrind); part of the cache key.
    if (const char* extra = std::getenv("WP_CL_OPTIONS"); extra && *extra) prog.options += std::string(" ") + extra;
    std::string source = assemble_source(file);

    // Cache key: everything that can change the binary.
    std::uint64_t key = fnv1a(source);
    for (const std::string* s : std::initializer_list<const std::string*>{&prog.options, &dev.info.platform, &dev.info.platform_version,
                                 &dev.info.name, &dev.info.version, &dev.info.driver})
        key = fnv1a(*s, key ^ 0x9e3779b97f4a7c15ull);
    auto dir = cache_dir();
    fs::path cached = dir ? *dir / fmt::format("{}-{:016x}.bin", fs::path(file).stem().string(), key) : fs::path();

    // 1. A cached binary, when one exists and the driver accepts it.
    if (dir && fs::exists(cached)) {
        std::ifstream in(cached, std::ios::binary);
        std::vector<unsigned char> bin((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        try {
            ::cl::Program::Binaries bins{bin};
            prog.program = ::cl::Program(dev.context, {dev.info.device}, bins);
            prog.program.build({dev.info.device}, prog.options.c_str());
            prog.from_cache = true;
            prog.build_ms = timer.ms();
            return prog;
        } catch (const ::cl::Error&) {
            // A stale or foreign binary: fall through to a source build.
        }
    }

    // 2. A source build; on failure the log names kernels/<file>:<line>.
    prog.program = ::cl::Program(dev.context, source);
    try {
        prog.program.build({dev.info.device}, prog.options.c_str());
    } catch (const ::cl::Error& e) {
        fail("kernel build failed for kernels/{} on '{}' (options: {}):\n{}", file, dev.info.name,
             prog.options, build_log(prog.program, dev.info.device));
    }

    // 3. Store the binary for next time, now or deferred (store_deferred_programs).
    if (dir) {
        bool now = true;
        {
            std::lock_guard<std::mutex> lock(g_deferred_mutex);
            if (g_defer) {
                g_deferred.push_back({prog.program, cached});
                now = false;
            }
        }
        if (now) store_binary(prog.program, cached);
    }
    prog.build_ms = timer.ms();
    return prog;
}

void defer_cache_stores(bool defer) {
    std::lock_guard<std::mutex> lock(g_deferred_mutex);
    g_defer = defer;
}

double store_deferred_programs() {
    std::vector<DeferredStore> todo;
    {
        std::lock_guard<std::mutex> lock(g_deferred_mutex);
        todo.swap(g_deferred);
    }
    if (todo.empty()) return 0.0;
    Timer timer;
    for (const DeferredStore& d : todo) store_binary(d.program, d.path);
    return timer.ms();
}

::cl::Kernel Program::kernel(const std::string& name) const {
    try {
        return ::cl::Kernel(program, name.c_str());
    } catch (const ::cl::Error& e) {
        fail("kernel '{}' not found in kernels/{} (OpenCL error {})", name, file, e.err());
    }
}

}  // namespace wp::ocl
