// shadow.cl — the shadow stage: the light samples of next-event estimation.
//
// shadow_trace (after shade, with NEE)
// reads   shadow_rays[i], shadow_items[i], shadow_contrib[i] for i < shadow_count[0] (the
//         shadow queue shade filled: a segment from the shading point towards the light
//         point, hits need 0 < t < dir.w <= 1: offset.h's wp_shadow_tmax); the BVH
//         (nodes, links, leaf-ordered tris, prim_ids);
//         with WP_HAVE_ALPHA_MASK the alpha test's arguments (bvh_traverse.h), so cut-out
//         surfaces let light through
// writes  radiance[item] += shadow_contrib[i] when the segment is unoccluded (any hit,
//         stackless traversal: bvh_traverse.h); the rays are counted by the next
//         queue_reset (queue.cl)
// A sample has at most one shadow ray per bounce, so the radiance update needs no atomics
// and does not depend on the order of the queue.
#include "shared/bvh_traverse.h"

WP_KERNEL void shadow_trace(WP_GLOBAL const Ray* shadow_rays, WP_GLOBAL const int* shadow_items,
                            WP_GLOBAL const float4* shadow_contrib,
                            WP_GLOBAL const int* shadow_count, WP_GLOBAL const BvhNode* nodes,
                            WP_GLOBAL const BvhLinks* links, WP_GLOBAL const TriBlock* tris,
                            WP_GLOBAL const int* prim_ids,
                            WP_GLOBAL float4* radiance WP_ALPHA_KERNEL_PARAMS) {
    int i = wp_global_id();
    if (i >= shadow_count[0]) return;
    WP_ALPHA_SETUP
    TraceStats st = {0, 0};
    Hit h = wp_trace_any(shadow_rays[i], nodes, links, tris, prim_ids, &st WP_ALPHA_ARG);
    if (h.prim >= 0) return;  // occluded
    int item = shadow_items[i];
    radiance[item] += shadow_contrib[i];
}
