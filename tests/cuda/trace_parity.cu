// trace_parity.cu — runs the shared traversals (kernels/shared/bvh_traverse.h compiled as
// CUDA: the stackless closest hit with its ancestor ring, the small-stack oracle, the
// any-hit walk) on an NVIDIA GPU over a BVH and rays made on the host, writes the hits, and
// prints each traversal's throughput (median of 7 timed launches). Not part of CI:
//   scripts/gpu_parity.sh trace-run IN.bin OUT.bin   (built with nvcc --fmad=false)
#include "shared/bvh_traverse.h"
#include "trace_parity.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <vector>
#include <cuda_runtime.h>

#define CHECK(x) do { cudaError_t e = (x); if (e != cudaSuccess) { std::fprintf(stderr, "%s: %s\n", #x, cudaGetErrorString(e)); return 1; } } while (0)

__global__ void trace(int variant, const Ray* rays, int n, const BvhNode* nodes, const BvhLinks* links,
                      const TriBlock* tris, const int* prim_ids, Hit* out) {
    int i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    TraceStats st{0, 0};
    out[i] = variant == 0 ? wp_trace_closest(rays[i], nodes, links, tris, prim_ids, &st)
           : variant == 1 ? wp_trace_closest_stack(rays[i], nodes, links, tris, prim_ids, &st)
                          : wp_trace_any(rays[i], nodes, links, tris, prim_ids, &st);
}

template <typename T>
static bool read_array(FILE* f, std::vector<T>& v, int n) {
    v.resize(n);
    return std::fread(v.data(), sizeof(T), n, f) == std::size_t(n);
}

template <typename T>
static int upload(T** d, const std::vector<T>& v) {
    CHECK(cudaMalloc(d, sizeof(T) * std::max<std::size_t>(v.size(), 1)));
    if (!v.empty()) CHECK(cudaMemcpy(*d, v.data(), sizeof(T) * v.size(), cudaMemcpyHostToDevice));
    return 0;
}

int main(int argc, char** argv) {
    if (argc != 3) { std::fprintf(stderr, "usage: trace_parity IN.bin OUT.bin\n"); return 2; }
    FILE* f = std::fopen(argv[1], "rb");
    if (!f) { std::perror(argv[1]); return 1; }
    trace_parity::Header h;
    if (std::fread(&h, sizeof h, 1, f) != 1 || std::strcmp(h.magic, "WPTRACE") != 0 ||
        h.node_size != int(sizeof(BvhNode)) || h.link_size != int(sizeof(BvhLinks)) ||
        h.tri_size != int(sizeof(TriBlock)) || h.ray_size != int(sizeof(Ray)) || h.hit_size != int(sizeof(Hit))) {
        std::fprintf(stderr, "%s: not a trace_parity input of these layouts\n", argv[1]);
        return 1;
    }
    std::vector<BvhNode> nodes; std::vector<BvhLinks> links; std::vector<TriBlock> tris;
    std::vector<int> prim_ids; std::vector<Ray> rays;
    if (!read_array(f, nodes, h.nodes) || !read_array(f, links, h.nodes) || !read_array(f, tris, h.tris) ||
        !read_array(f, prim_ids, h.tris * WP_TRI_BLOCK) || !read_array(f, rays, h.rays)) {
        std::fprintf(stderr, "%s: truncated\n", argv[1]);
        return 1;
    }
    std::fclose(f);
    BvhNode* dn; BvhLinks* dl; TriBlock* dt; int* dp; Ray* dr; Hit* dh;
    if (upload(&dn, nodes) || upload(&dl, links) || upload(&dt, tris) || upload(&dp, prim_ids) || upload(&dr, rays)) return 1;
    CHECK(cudaMalloc(&dh, sizeof(Hit) * rays.size() * trace_parity::kVariants));
    cudaDeviceProp prop;
    CHECK(cudaGetDeviceProperties(&prop, 0));
    cudaEvent_t t0, t1;
    CHECK(cudaEventCreate(&t0));
    CHECK(cudaEventCreate(&t1));
    const char* names[] = {"stackless closest (ring)", "stack closest", "any hit"};
    const int n = h.rays, block = 128, grid = (n + block - 1) / block;
    for (int v = 0; v < trace_parity::kVariants; ++v) {
        Hit* out = dh + std::size_t(v) * n;
        trace<<<grid, block>>>(v, dr, n, dn, dl, dt, dp, out);  // warm-up, and the result
        CHECK(cudaGetLastError());
        CHECK(cudaDeviceSynchronize());
        std::vector<float> ms;
        for (int r = 0; r < 7; ++r) {
            CHECK(cudaEventRecord(t0));
            trace<<<grid, block>>>(v, dr, n, dn, dl, dt, dp, out);
            CHECK(cudaEventRecord(t1));
            CHECK(cudaEventSynchronize(t1));
            float m = 0.0f;
            CHECK(cudaEventElapsedTime(&m, t0, t1));
            ms.push_back(m);
        }
        std::sort(ms.begin(), ms.end());
        std::printf("trace_parity: %s: %d rays, median %.3f ms (%.0f Mrays/s)\n", names[v], n, ms[3],
                    n / (ms[3] * 1e3));
    }
    std::vector<Hit> hits(std::size_t(n) * trace_parity::kVariants);
    CHECK(cudaMemcpy(hits.data(), dh, sizeof(Hit) * hits.size(), cudaMemcpyDeviceToHost));
    FILE* o = std::fopen(argv[2], "wb");
    if (!o) { std::perror(argv[2]); return 1; }
    trace_parity::Header oh = h;
    std::memset(oh.magic, 0, sizeof oh.magic);
    std::strcpy(oh.magic, "WPHITS");
    std::fwrite(&oh, sizeof oh, 1, o);
    std::fwrite(hits.data(), sizeof(Hit), hits.size(), o);
    std::fclose(o);
    int runtime = 0, driver = 0;
    cudaRuntimeGetVersion(&runtime);
    cudaDriverGetVersion(&driver);
    std::printf("trace_parity: %s (CUDA runtime %d, driver API %d), %d nodes, %d triangles; hits written to %s\n",
                prop.name, runtime, driver, h.nodes, h.tris, argv[2]);
    return 0;
}
