// cuda_compile.cpp — every kernel file compiles for all three targets from one text
// (ctest -L cuda-compile; issue 11 item 4).
//
//   cuda_compile <nvcc|""> <host c++ compiler> <kernels dir> <work dir>
//
// For every kernels/*.cl (globbed at run time, so a new stage file is covered at once) and
// every option set (the kernels' defaults, and the shipped shade configuration plus the
// debug switches the file reads: WP_STATS, WP_INJECT_NAN, WP_PLAIN_TRIANGLES; the appearance
// switches and the thin lens, WP_HAVE_LENS, where the file reads them):
//   1. OpenCL: ocl::assemble_source + a build on the test device (PoCL) gives the entry
//      points (CL_PROGRAM_KERNEL_NAMES);
//   2. CUDA: the same assembled text through nvcc -x cu --ptx --fmad=false -std=c++17 with
//      the same -D options; every OpenCL entry point must be a `.entry NAME(` of the PTX,
//      and the PTX must have no other entry;
//   3. host C++: the same text through <c++> -x c++ -std=c++17 -fsyntax-only (C++17, as for
//      nvcc: C++20 would take OpenCL's broadcast (float4)(x) for {x, 0, 0, 0}).
// Layout: a CUDA translation unit stores every WP_LAYOUT_FIELDS value (types.h) in a
// __device__ array; the numbers read back from the PTX initializer must equal the host's.
// (The OpenCL side of the same list is compared by tests/test_layout.cpp.)
//
// Exit: 0 all passed; 1 a failure (each printed as file:line where the compiler named
// one); 77 nvcc not found (ctest reports the test as skipped).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <mutex>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "cl/device.h"
#include "cl/program.h"
#include "render/kernel_config.h"
#include "shared/types.h"

namespace fs = std::filesystem;
using namespace wp;

namespace {

// The configuration `wavepath render` ships for the shade stage, every material kind on:
// the renderer's own option string (render/kernel_config.h), not a copy of it.
// (with the shadow segments' clearance, which a render turns on by default, and the last
// bounce's shade_final of a scene whose escaped rays carry no light).
const std::string kShipped = [] {
    render::KernelConfig c;
    c.light_clearance = true;
    c.stream_stores = true;
    c.final_rays = true;
    return c.shade_options();
}();
// The same with every appearance feature of issue 13 on (normals, textures, normal maps,
// the environment, alpha cut-outs) and light pairs, from the renderer's own option strings.
const std::string kAppearance = [] {
    render::KernelConfig c;
    c.normals = c.textures = c.normal_maps = c.env = c.alpha_mask = c.anisotropic = c.light_pairs = true;
    c.light_clearance = true;
    return c.shade_options() + " " + c.trace_options();
}();
// The generate stage with a thin-lens camera (WP_HAVE_LENS) and streamed queue stores, from
// the renderer's own string.
const std::string kLens = [] {
    render::KernelConfig c;
    c.lens = true;
    c.stream_stores = true;
    return c.generate_options();
}();

std::string read_text(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

void write_text(const fs::path& p, const std::string& s) {
    std::ofstream out(p, std::ios::binary);
    out << s;
}

std::string quote(const std::string& s) {
    std::string r = "'";
    for (char c : s) r += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return r + "'";
}

// nvcc reports "file(line): error: ..."; print it as "file:line: error: ..." like g++.
std::string as_file_line(const std::string& log) {
    static const std::regex re(R"re(^(.+)\((\d+)\): )re", std::regex::multiline);
    return std::regex_replace(log, re, "$1:$2: ");
}

std::vector<std::string> split(const std::string& s, char sep) {
    std::vector<std::string> out;
    std::string item;
    std::istringstream in(s);
    while (std::getline(in, item, sep))
        if (!item.empty()) out.push_back(item);
    return out;
}

// Runs shell commands on `threads` threads; each job's exit status lands in its slot.
struct Job {
    std::string command;
    int status = -1;
};
void run_all(std::vector<Job>& jobs, unsigned threads) {
    std::mutex m;
    std::size_t next = 0;
    auto worker = [&] {
        for (;;) {
            std::size_t i;
            {
                std::lock_guard<std::mutex> lock(m);
                if (next >= jobs.size()) return;
                i = next++;
            }
            jobs[i].status = std::system(jobs[i].command.c_str());
        }
    };
    std::vector<std::thread> pool;
    for (unsigned t = 0; t < threads; ++t) pool.emplace_back(worker);
    for (auto& t : pool) t.join();
}

// The first `max_lines` lines of a compiler log, and where the rest is.
std::string head(const std::string& log, const fs::path& where, int max_lines = 20) {
    std::istringstream in(log);
    std::string line, out;
    int n = 0;
    while (std::getline(in, line))
        if (++n <= max_lines) out += "  " + line + "\n";
    if (n > max_lines) out += "  ... " + std::to_string(n - max_lines) + " more lines in " + where.string() + "\n";
    return out;
}

struct Case {
    std::string file;     // e.g. "shade.cl"
    std::string label;    // "defaults", "shipped", ...
    std::string options;  // -D options
    fs::path stem;        // work/<file>.<n>: .cu, .ptx, .cpp, .nvcc.log, .cxx.log
    std::size_t nvcc_job = 0, cxx_job = 0;
};

}  // namespace

int main(int argc, char** argv) {
    auto t0 = std::chrono::steady_clock::now();
    if (argc != 5) {
        std::cerr << "usage: cuda_compile <nvcc> <c++ compiler> <kernels dir> <work dir>\n";
        return 2;
    }
    std::string nvcc = argv[1], cxx = argv[2];
    fs::path kernels = argv[3], work = argv[4];
    if (nvcc.empty() || nvcc.find("NOTFOUND") != std::string::npos || !fs::exists(nvcc)) {
        std::cout << "SKIP: nvcc not found (cmake searched PATH, $CUDA_PATH, $CUDA_HOME and "
                     "/usr/local/cuda/bin; install the CUDA toolkit or pass -DWP_NVCC=/path/to/nvcc): "
                     "the kernels were not compiled for CUDA\n";
        return 77;
    }
    // assemble_source and Program::build read the kernel files from here, not from the
    // embedded copies: the check sees the tree as it is now.
    setenv("WP_KERNEL_DIR", kernels.c_str(), 1);
    fs::create_directories(work);

    std::vector<std::string> files;
    for (const auto& e : fs::directory_iterator(kernels))
        if (e.is_regular_file() && e.path().extension() == ".cl") files.push_back(e.path().filename().string());
    std::sort(files.begin(), files.end());
    if (files.empty()) {
        std::cout << "FAIL: no kernels/*.cl in " << kernels << "\n";
        return 1;
    }

    // The cases and their compiler jobs.
    std::vector<Case> cases;
    std::vector<Job> jobs;
    for (const auto& file : files) {
        std::string source = ocl::assemble_source(file);
        std::vector<std::string> sets = {"", kShipped}, labels = {"defaults", "shipped"};
        auto reads = [&](const char* macro) { return source.find(macro) != std::string::npos; };
        if (reads("WP_STATS")) sets[1] += " -D WP_STATS", labels[1] += " + WP_STATS";
        if (reads("WP_INJECT_NAN")) sets[1] += " -D WP_INJECT_NAN=7", labels[1] += " + WP_INJECT_NAN=7";
        if (reads("WP_HAVE_NORMALS") || reads("WP_HAVE_ALPHA_MASK")) {
            sets.push_back(kAppearance);
            labels.push_back("shipped + appearance");
        }
        if (reads("WP_HAVE_LENS")) {
            sets.push_back(kLens);
            labels.push_back("thin lens");
        }
        if (reads("WP_PLAIN_TRIANGLES")) {
            sets.push_back(std::string(kShipped) + " -D WP_PLAIN_TRIANGLES");
            labels.push_back("shipped + WP_PLAIN_TRIANGLES");
        }
        for (std::size_t k = 0; k < sets.size(); ++k) {
            Case c;
            c.file = file;
            c.label = labels[k];
            c.options = sets[k];
            c.stem = work / (file + "." + std::to_string(k));
            write_text(c.stem.string() + ".cu", source);
            // The host sees the shared code in namespace wp; the stage files use it unqualified.
            write_text(c.stem.string() + ".cpp", "namespace wp {}\nusing namespace wp;\n" + source);
            c.nvcc_job = jobs.size();
            jobs.push_back({quote(nvcc) + " -x cu --ptx --fmad=false -std=c++17 " + c.options + " " +
                            quote(c.stem.string() + ".cu") + " -o " + quote(c.stem.string() + ".ptx") +
                            " > " + quote(c.stem.string() + ".nvcc.log") + " 2>&1"});
            c.cxx_job = jobs.size();
            // C++17 as for nvcc: C++20's parenthesised aggregate init would accept OpenCL's
            // broadcast (float4)(x) as {x, 0, 0, 0}, silently.
            jobs.push_back({quote(cxx) + " -x c++ -std=c++17 -fsyntax-only -ffp-contract=off " + c.options +
                            " " + quote(c.stem.string() + ".cpp") + " > " +
                            quote(c.stem.string() + ".cxx.log") + " 2>&1"});
            cases.push_back(c);
        }
    }
    // Layout probe: every WP_LAYOUT_FIELDS value as CUDA lays the structs out.
    fs::path layout_cu = work / "layout.cu", layout_ptx = work / "layout.ptx";
    write_text(layout_cu,
               "#include \"shared/types.h\"\n"
               "#define WP_LAYOUT_ENTRY(expr) (int)(expr),\n"
               "extern \"C\" __device__ int wp_cuda_layout[] = {WP_LAYOUT_FIELDS(WP_LAYOUT_ENTRY) -1};\n");
    std::size_t layout_job = jobs.size();
    jobs.push_back({quote(nvcc) + " -x cu --ptx --fmad=false -std=c++17 -I " + quote(kernels.string()) + " " +
                    quote(layout_cu.string()) + " -o " + quote(layout_ptx.string()) + " > " +
                    quote(layout_ptx.string() + ".log") + " 2>&1"});

    // Compilers run in the background while the OpenCL device builds the same cases.
    unsigned threads = std::max(2u, std::thread::hardware_concurrency());
    std::thread compilers([&] { run_all(jobs, threads); });

    int failures = 0;
    std::vector<std::vector<std::string>> entries(cases.size());
    try {
        const char* sel = std::getenv("WP_TEST_DEVICE");
        ocl::Device dev = ocl::Device::open(sel ? sel : "");
        std::cout << "OpenCL device: " << dev.info.platform << ": " << dev.info.name << "\n";
        for (std::size_t i = 0; i < cases.size(); ++i) {
            try {
                auto prog = ocl::Program::build(dev, cases[i].file, cases[i].options);
                entries[i] = split(prog.program.getInfo<CL_PROGRAM_KERNEL_NAMES>(), ';');
                if (entries[i].empty()) {
                    std::cout << "FAIL: kernels/" << cases[i].file << ": OpenCL reports no entry point\n";
                    ++failures;
                }
            } catch (const std::exception& e) {
                std::cout << "FAIL: OpenCL build of kernels/" << cases[i].file << " [" << cases[i].label
                          << "]:\n" << e.what() << "\n";
                ++failures;
            }
        }
    } catch (const std::exception& e) {
        std::cout << "FAIL: no OpenCL device: " << e.what() << "\n";
        ++failures;
    }
    compilers.join();

    // CUDA and host results per case.
    static const std::regex entry_re(R"re(\.entry\s+([A-Za-z_][A-Za-z0-9_]*)\s*\()re");
    for (std::size_t i = 0; i < cases.size(); ++i) {
        const Case& c = cases[i];
        std::string what = "kernels/" + c.file + " [" + c.label + "]";
        if (jobs[c.nvcc_job].status != 0) {
            fs::path log = c.stem.string() + ".nvcc.log";
            std::cout << "FAIL: nvcc rejected " << what << ":\n"
                      << head(as_file_line(read_text(log)), log) << "  command: " << jobs[c.nvcc_job].command
                      << "\n";
            ++failures;
        } else {
            std::string ptx = read_text(c.stem.string() + ".ptx");
            std::vector<std::string> cuda;
            for (std::sregex_iterator it(ptx.begin(), ptx.end(), entry_re), end; it != end; ++it)
                cuda.push_back((*it)[1].str());
            for (const auto& name : entries[i])
                if (std::find(cuda.begin(), cuda.end(), name) == cuda.end()) {
                    std::cout << "FAIL: " << what << ": entry point " << name
                              << " is missing from the PTX (is it declared WP_KERNEL?)\n";
                    ++failures;
                }
            for (const auto& name : cuda)
                if (!entries[i].empty() && std::find(entries[i].begin(), entries[i].end(), name) == entries[i].end()) {
                    std::cout << "FAIL: " << what << ": the PTX has an entry point " << name
                              << " that OpenCL does not\n";
                    ++failures;
                }
            if (!entries[i].empty() && cuda.size() >= entries[i].size())
                std::cout << "ok   cuda " << what << ": " << cuda.size() << " entry points\n";
            else if (entries[i].empty())
                std::cout << "??   cuda " << what << ": compiled, entry points not compared (no OpenCL build)\n";
        }
        if (jobs[c.cxx_job].status != 0) {
            fs::path log = c.stem.string() + ".cxx.log";
            std::cout << "FAIL: host C++ rejected " << what << ":\n"
                      << head(read_text(log), log) << "  command: " << jobs[c.cxx_job].command << "\n";
            ++failures;
        } else {
            std::cout << "ok   c++  " << what << "\n";
        }
    }

    // Layout: CUDA's numbers from the PTX initializer against the host's.
    std::vector<int> host;
#define WP_HOST_ENTRY(expr) host.push_back(static_cast<int>(expr));
    WP_LAYOUT_FIELDS(WP_HOST_ENTRY)
#undef WP_HOST_ENTRY
    host.push_back(-1);
    if (jobs[layout_job].status != 0) {
        std::cout << "FAIL: nvcc rejected the layout probe:\n"
                  << as_file_line(read_text(layout_ptx.string() + ".log")) << "\n";
        ++failures;
    } else {
        std::string ptx = read_text(layout_ptx);
        // .global .align 4 .b32 wp_cuda_layout[N] = {a, b, ...};  (or .b8 bytes, little-endian)
        static const std::regex init_re(R"re(\.(b8|b32|u32|s32)\s+wp_cuda_layout\[(\d+)\]\s*=\s*\{([^}]*)\})re");
        std::smatch m;
        std::vector<int> cuda;
        if (std::regex_search(ptx, m, init_re)) {
            std::vector<long long> raw;
            for (const auto& v : split(m[3].str(), ',')) raw.push_back(std::stoll(v));
            if (m[1].str() == "b8") {
                for (std::size_t k = 0; k + 3 < raw.size(); k += 4)
                    cuda.push_back(static_cast<int>(static_cast<std::uint32_t>(raw[k] | raw[k + 1] << 8 |
                                                                             raw[k + 2] << 16 | raw[k + 3] << 24)));
            } else {
                for (long long v : raw) cuda.push_back(static_cast<int>(v));
            }
        }
        if (cuda != host) {
            std::cout << "FAIL: struct layouts differ between CUDA and the host (types.h WP_LAYOUT_FIELDS)\n"
                      << "  entry  host  cuda\n";
            for (std::size_t k = 0; k < std::max(host.size(), cuda.size()); ++k)
                std::cout << "  " << k << "  " << (k < host.size() ? std::to_string(host[k]) : "-") << "  "
                          << (k < cuda.size() ? std::to_string(cuda[k]) : "-") << "\n";
            ++failures;
        } else {
            std::cout << "ok   layout: " << host.size() - 1 << " sizes and offsets agree (host C++, CUDA)\n";
        }
    }

    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::cout << "shipped = " << kShipped << "\n";
    std::cout << files.size() << " kernel files, " << cases.size() << " option sets, " << jobs.size()
              << " compiler runs on " << threads << " threads: " << s << " s\n";
    if (failures) {
        std::cout << "FAIL: " << failures << " failure(s)\n";
        return 1;
    }
    std::cout << "PASS\n";
    return 0;
}
