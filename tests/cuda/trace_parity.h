// trace_parity.h — the files that carry a BVH and rays to the GPU and its hits back
// (tests/cuda/trace_parity.cu on an NVIDIA GPU; tests/cuda/trace_parity_host.cpp makes the
// input and checks the output here). Raw arrays of the shared layouts (types.h), after a
// header that names their counts and sizes, so that a mismatch is reported, not misread.
#pragma once

#include <cstdint>

namespace trace_parity {

struct Header {
    char magic[8];         // "WPTRACE" + NUL (input) or "WPHITS" + NULs (output)
    std::int32_t nodes;    // BvhNode count (the links array has as many entries)
    std::int32_t tris;     // leaf TriBlock count (prim_ids has WP_TRI_BLOCK entries for each)
    std::int32_t rays;     // Ray count
    std::int32_t node_size, link_size, tri_size, ray_size, hit_size;  // sizeof each
};

// Output: Header (magic "WPHITS"), then closest, stack and any-hit results, rays each.
constexpr int kVariants = 3;

}  // namespace trace_parity
