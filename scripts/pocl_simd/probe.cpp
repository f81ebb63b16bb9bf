// probe.cpp — how PoCL runs one diffuse-bounce "shade" written four ways (issue 15).
//
// The same work per path: two random numbers from a hash of the path id, a cosine-weighted
// direction around the hit normal (branchless orthonormal basis, Duff et al. 2017), the
// throughput times the albedo. Kernels (probe.cl):
//   aos_float3  one path per work-item, float3 state (the renderer's shade.cl style)
//   soa_scalar  one path per work-item, every value a scalar float in its own array
//   soa_branchy soa_scalar plus a material kind read through an index and a branch on it
//   soa_lanes8  eight paths per work-item, every value a float8 (SIMD spelled out)
// Prints ns per path, wall and CPU time of the process (all of PoCL's threads; steadier
// than wall time on a busy machine), medians of the launches, and the largest difference between the
// outputs (the same arithmetic: they must agree).
// Build and run: scripts/pocl_simd/run.sh
#include <CL/opencl.hpp>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

int main(int argc, char** argv) {
    const std::size_t n = argc > 2 ? std::stoul(argv[2]) : (1u << 20);
    const int runs = argc > 3 ? std::stoi(argv[3]) : 15;
    std::ifstream f(argc > 1 ? argv[1] : "probe.cl");
    if (!f) { std::fprintf(stderr, "probe: cannot read the kernel file\n"); return 2; }
    std::stringstream src;
    src << f.rdbuf();

    cl::Context ctx(CL_DEVICE_TYPE_ALL);
    cl::Device dev = ctx.getInfo<CL_CONTEXT_DEVICES>()[0];
    cl::CommandQueue q(ctx, dev);
    cl::Program prog(ctx, src.str());
    try {
        prog.build("-cl-std=CL1.2");
    } catch (...) {
        std::fprintf(stderr, "%s\n", prog.getBuildInfo<CL_PROGRAM_BUILD_LOG>(dev).c_str());
        return 1;
    }
    // Inputs: unit normals (random directions) and albedos, as SoA floats.
    std::vector<float> in(6 * n);
    unsigned s = 12345u;
    auto u01 = [&] { s = s * 1664525u + 1013904223u; return (s >> 8) * (1.0f / 16777216.0f); };
    for (std::size_t i = 0; i < n; ++i) {
        float z = 2 * u01() - 1, a = 6.2831853f * u01(), r = std::sqrt(std::max(0.0f, 1 - z * z));
        in[i] = r * std::cos(a); in[n + i] = r * std::sin(a); in[2 * n + i] = z;
        in[3 * n + i] = u01(); in[4 * n + i] = u01(); in[5 * n + i] = u01();
    }
    cl::Buffer bin(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, in.size() * 4, in.data());
    std::vector<int> kinds(256, 0);  // every path diffuse; the kernel cannot know it
    cl::Buffer bkind(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, kinds.size() * 4, kinds.data());
    const char* names[] = {"aos_float3", "soa_scalar", "soa_branchy", "soa_lanes8"};
    std::vector<std::vector<float>> outs;
    for (const char* name : names) {
        cl::Buffer bout(ctx, CL_MEM_WRITE_ONLY, 6 * n * 4);
        cl::Kernel k(prog, name);
        k.setArg(0, bin); k.setArg(1, bout); k.setArg(2, (cl_uint)n);
        if (std::string(name) == "soa_branchy") k.setArg(3, bkind);
        std::size_t items = std::string(name) == "soa_lanes8" ? n / 8 : n;
        std::vector<double> ns, cpu;
        auto cpu_now = [] {
            timespec t{};
            clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
            return t.tv_sec * 1e9 + t.tv_nsec;
        };
        for (int r = 0; r < runs + 1; ++r) {
            auto t0 = std::chrono::steady_clock::now();
            double c0 = cpu_now();
            q.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(items), cl::NDRange(64));
            q.finish();
            double dt = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count();
            double dc = cpu_now() - c0;
            if (r > 0) {  // the first launch compiles the work-group function
                ns.push_back(dt / n);
                cpu.push_back(dc / n);
            }
        }
        std::sort(ns.begin(), ns.end());
        std::sort(cpu.begin(), cpu.end());
        std::vector<float> out(6 * n);
        q.enqueueReadBuffer(bout, CL_TRUE, 0, out.size() * 4, out.data());
        outs.push_back(out);
        std::printf("%-11s wall %7.2f ns/path (median of %d; min %.2f, max %.2f)   cpu %7.2f ns/path (min %.2f)\n",
                    name, ns[ns.size() / 2], runs, ns.front(), ns.back(), cpu[cpu.size() / 2],
                    cpu.front());
    }
    double worst = 0;
    for (std::size_t v = 1; v < outs.size(); ++v)
        for (std::size_t i = 0; i < outs[0].size(); ++i)
            worst = std::max(worst, (double)std::fabs(outs[v][i] - outs[0][i]));
    std::printf("largest |difference| between the outputs: %.3g\n", worst);
    return worst < 1e-5 ? 0 : 1;
}
