// test_compat.cpp — compat.h's own test: kernels/test_compat.cl runs on the OpenCL device
// and, compiled as host C++ from the same text (included below), on the host; every result
// must agree bit for bit. (tests/cuda/cuda_compile.cpp compiles the same file for CUDA.)
#include <catch2/catch.hpp>

#include <cstring>
#include <vector>

#include "cl/kernel.h"
#include "cl/program.h"
#include "support.h"

// The probe kernel as host C++: its names resolve in namespace wp, as the stage files' do.
namespace wp {}
using namespace wp;
#include "test_compat.cl"

namespace {

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof(float)) == 0; }

}  // namespace

TEST_CASE("compat.h: OpenCL builtins and their C++ definitions agree bit for bit", "[kernel][compat]") {
    auto& dev = test::device();
    // Inputs: signed zeros, equal lanes, negative values, large and tiny magnitudes (no NaN:
    // min/max are unspecified for NaN in OpenCL), every lane permutation class.
    test::Rng rng(11);
    const float specials[] = {0.0f, -0.0f, 1.0f, -1.0f, 0.5f, 3.0e38f, -1.0e-38f, 2.0f, 1.0e-3f, -7.25f};
    std::vector<float4> a, b;
    std::vector<uint4> idx;
    std::vector<ulong> bits;
    for (int i = 0; i < 256; ++i) {
        auto pick = [&](int k) {
            return (i + k) % 3 == 0 ? specials[(i * 7 + k) % 10] : rng.uniform(-4.0f, 4.0f);
        };
        float4 x = make_float4(pick(0), pick(1), pick(2), pick(3));
        float4 y = i % 5 == 0 ? x : make_float4(pick(4), pick(5), pick(6), pick(7));
        if (i % 4 == 1) y.y = x.y;  // a partly equal pair
        a.push_back(x);
        b.push_back(y);
        idx.push_back(make_uint4(i & 3u, (i >> 2) & 3u, (i >> 4) & 3u, (i * 5 >> 1) & 3u));
        bits.push_back(ulong(1) << (i % 64) | (i % 3 == 0 ? ulong(1) << 63 : 0));
    }
    const int n = static_cast<int>(a.size());

    // OpenCL.
    auto prog = ocl::Program::build(dev, "test_compat.cl");
    auto upload = [&](auto& v) {
        return cl::Buffer(dev.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, v.size() * sizeof(v[0]), v.data());
    };
    cl::Buffer ba = upload(a), bb = upload(b), bi = upload(idx), bm = upload(bits);
    cl::Buffer bf(dev.context, CL_MEM_WRITE_ONLY, sizeof(float4) * WP_COMPAT_F * n);
    cl::Buffer bn(dev.context, CL_MEM_WRITE_ONLY, sizeof(int) * WP_COMPAT_N * n);
    ocl::Kernel(prog, "probe_compat").launch({&dev.queue}, n, ba, bb, bi, bm, n, bf, bn);
    std::vector<float4> dev_f(WP_COMPAT_F * n);
    std::vector<int> dev_n(WP_COMPAT_N * n);
    dev.queue.enqueueReadBuffer(bf, CL_TRUE, 0, sizeof(float4) * dev_f.size(), dev_f.data());
    dev.queue.enqueueReadBuffer(bn, CL_TRUE, 0, sizeof(int) * dev_n.size(), dev_n.data());

    // Host C++, the same kernel text, one work-item at a time.
    std::vector<float4> host_f(WP_COMPAT_F * n);
    std::vector<int> host_n(WP_COMPAT_N * n);
    for (int i = 0; i < n; ++i) {
        wp::host_item.global_id = i;
        probe_compat(a.data(), b.data(), idx.data(), bits.data(), n, host_f.data(), host_n.data());
    }
    wp::host_item.global_id = 0;

    // Known difference (documented in compat.h): OpenCL's length/normalize rescale when
    // |v|^2 overflows, the C++/CUDA ones do not; those items' result 7 is not compared.
    int mismatches = 0, overflowing = 0;
    for (int i = 0; i < n; ++i) {
        bool overflow = !std::isfinite(dot(wp_xyz(a[i]), wp_xyz(a[i])));
        overflowing += overflow;
        for (int r = 0; r < WP_COMPAT_F; ++r) {
            if (r == 7 && overflow) continue;
            const float4& d = dev_f[WP_COMPAT_F * i + r];
            const float4& h = host_f[WP_COMPAT_F * i + r];
            const float dl[4] = {d.x, d.y, d.z, d.w}, hl[4] = {h.x, h.y, h.z, h.w};
            for (int l = 0; l < 4; ++l)
                if (!same_bits(dl[l], hl[l]) && mismatches++ < 20)
                    FAIL_CHECK("item " << i << " float4 result " << r << " lane " << l << ": device " << dl[l]
                                       << ", host " << hl[l]);
        }
        for (int r = 0; r < WP_COMPAT_N; ++r)
            if (dev_n[WP_COMPAT_N * i + r] != host_n[WP_COMPAT_N * i + r] && mismatches++ < 20)
                FAIL_CHECK("item " << i << " int result " << r << ": device " << dev_n[WP_COMPAT_N * i + r]
                                   << ", host " << host_n[WP_COMPAT_N * i + r]);
    }
    CHECK(mismatches == 0);
    CHECK(overflowing < n / 8);  // the rest of the inputs do exercise normalize
}
