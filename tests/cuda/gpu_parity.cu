// gpu_parity.cu — runs the shared BSDF code (kernels/shared/bsdf.h, compiled as CUDA) on an
// NVIDIA GPU for every material kind and writes inputs and results to a file, which
// parity_check (the same code compiled as host C++) compares. Not part of CI: run by
// scripts/gpu_parity.sh on a machine with a GPU.
//   scripts/gpu_parity.sh run OUT.bin (builds it with nvcc --fmad=false)
#include "shared/bsdf.h"
#include "parity_cases.h"

#include <cstdio>
#include <cuda_runtime.h>

static float4 f4(float a, float b, float c, float d) { return make_float4(a, b, c, d); }

__global__ void run(const MaterialData* mats, const float* tables, const parity::Case* cases, parity::Result* out, int n) {
    int i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n * WP_MATERIAL_KIND_COUNT) return;
    MaterialData m = mats[i / n];
    parity::Case c = cases[i % n];
    float3 d = make_float3(c.d[0], c.d[1], c.d[2]), ns = make_float3(c.ns[0], c.ns[1], c.ns[2]);
    float3 wi = make_float3(c.wi[0], c.wi[1], c.wi[2]);
    float3 wo = make_float3(0, 0, 0), w = wo;
    float pdf = 0.0f, epdf = 0.0f;
    int spec = 0;
    parity::Result r{};
    r.ok = wp_bsdf_sample_pdf(m, tables, d, ns, c.front, make_float4(c.u[0], c.u[1], c.u[2], c.u[3]), &wo, &w, &pdf, &spec);
    r.specular = spec;
    r.wo[0] = wo.x, r.wo[1] = wo.y, r.wo[2] = wo.z;
    r.weight[0] = w.x, r.weight[1] = w.y, r.weight[2] = w.z;
    r.pdf = pdf;
    float3 f = wp_bsdf_eval(m, tables, d, ns, c.front, wi, &epdf);
    r.fcos[0] = f.x, r.fcos[1] = f.y, r.fcos[2] = f.z;
    r.eval_pdf = epdf;
    out[i] = r;
}

#define CHECK(x) do { cudaError_t e = (x); if (e != cudaSuccess) { std::fprintf(stderr, "%s: %s\n", #x, cudaGetErrorString(e)); return 1; } } while (0)

int main(int argc, char** argv) {
    if (argc != 2) { std::fprintf(stderr, "usage: gpu_parity OUT.bin\n"); return 2; }
    const int n = parity::kCasesPerKind, kinds = WP_MATERIAL_KIND_COUNT;
    std::vector<MaterialData> mats;
    for (int k = 0; k < kinds; ++k) mats.push_back(parity::material<MaterialData>(k, f4));
    std::vector<parity::Case> cases(n);
    for (int i = 0; i < n; ++i) cases[i] = parity::make_case(std::uint32_t(i));
    std::vector<float> table(parity::kTableSize);
    for (int i = 0; i < parity::kTableSize; ++i) table[i] = parity::table_value(i);
    float* dt;
    CHECK(cudaMalloc(&dt, sizeof(float) * table.size()));
    CHECK(cudaMemcpy(dt, table.data(), sizeof(float) * table.size(), cudaMemcpyHostToDevice));
    MaterialData* dm; parity::Case* dc; parity::Result* dr;
    CHECK(cudaMalloc(&dm, sizeof(MaterialData) * kinds));
    CHECK(cudaMalloc(&dc, sizeof(parity::Case) * n));
    CHECK(cudaMalloc(&dr, sizeof(parity::Result) * n * kinds));
    CHECK(cudaMemcpy(dm, mats.data(), sizeof(MaterialData) * kinds, cudaMemcpyHostToDevice));
    CHECK(cudaMemcpy(dc, cases.data(), sizeof(parity::Case) * n, cudaMemcpyHostToDevice));
    cudaDeviceProp prop;
    CHECK(cudaGetDeviceProperties(&prop, 0));
    run<<<(n * kinds + 127) / 128, 128>>>(dm, dt, dc, dr, n);
    CHECK(cudaGetLastError());
    CHECK(cudaDeviceSynchronize());
    std::vector<parity::Result> res(std::size_t(n) * kinds);
    CHECK(cudaMemcpy(res.data(), dr, sizeof(parity::Result) * res.size(), cudaMemcpyDeviceToHost));
    FILE* f = std::fopen(argv[1], "wb");
    if (!f) { std::perror(argv[1]); return 1; }
    int header[3] = {n, kinds, int(sizeof(parity::Result))};
    std::fwrite(header, sizeof header, 1, f);
    std::fwrite(res.data(), sizeof(parity::Result), res.size(), f);
    std::fclose(f);
    std::printf("gpu_parity: %s, %d kinds x %d cases written to %s\n", prop.name, kinds, n, argv[1]);
    return 0;
}
