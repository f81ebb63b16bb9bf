// intersect.cl — the intersect stage: closest hit and any hit through the BVH.
//
// Batch entry points (rays in, hits out) for tests and the benchmark:
//   reads  rays[0..count), the BVH (nodes, links), leaf-ordered triangles, prim_ids
//   writes hits[0..count) (Hit, types.h); with -D WP_STATS also stats[0..count)
// Launched with a fixed local size; items past `count` return at once.
#include "shared/bvh_traverse.h"

__kernel void intersect_closest_batch(__global const Ray* rays, int count,
                                      __global const BvhNode* nodes,
                                      __global const BvhLinks* links,
                                      __global const Triangle* tris,
                                      __global const int* prim_ids, __global Hit* hits,
                                      __global TraceStats* stats) {
    int i = wp_global_id();
    if (i >= count) return;
    TraceStats st = {0, 0};
    hits[i] = wp_trace_closest(rays[i], nodes, links, tris, prim_ids, &st);
#if defined(WP_STATS)
    stats[i] = st;
#endif
}

__kernel void intersect_closest_stack_batch(__global const Ray* rays, int count,
                                            __global const BvhNode* nodes,
                                            __global const BvhLinks* links,
                                            __global const Triangle* tris,
                                            __global const int* prim_ids, __global Hit* hits,
                                            __global TraceStats* stats) {
    int i = wp_global_id();
    if (i >= count) return;
    TraceStats st = {0, 0};
    hits[i] = wp_trace_closest_stack(rays[i], nodes, links, tris, prim_ids, &st);
#if defined(WP_STATS)
    stats[i] = st;
#endif
}

__kernel void intersect_any_batch(__global const Ray* rays, int count,
                                  __global const BvhNode* nodes, __global const BvhLinks* links,
                                  __global const Triangle* tris, __global const int* prim_ids,
                                  __global Hit* hits, __global TraceStats* stats) {
    int i = wp_global_id();
    if (i >= count) return;
    TraceStats st = {0, 0};
    hits[i] = wp_trace_any(rays[i], nodes, links, tris, prim_ids, &st);
#if defined(WP_STATS)
    stats[i] = st;
#endif
}

// Wavefront entry points: the queue length is read from the device (queue_count[0]), so
// the host launches at capacity and never reads counts back (pbrt-v4's ForAllQueued).
__kernel void intersect_closest(__global const Ray* rays, __global const int* queue_count,
                                __global const BvhNode* nodes, __global const BvhLinks* links,
                                __global const Triangle* tris, __global const int* prim_ids,
                                __global Hit* hits) {
    int i = wp_global_id();
    if (i >= queue_count[0]) return;
    hits[i] = wp_trace_closest(rays[i], nodes, links, tris, prim_ids, 0);
}

__kernel void intersect_any(__global const Ray* rays, __global const int* queue_count,
                            __global const BvhNode* nodes, __global const BvhLinks* links,
                            __global const Triangle* tris, __global const int* prim_ids,
                            __global Hit* hits) {
    int i = wp_global_id();
    if (i >= queue_count[0]) return;
    hits[i] = wp_trace_any(rays[i], nodes, links, tris, prim_ids, 0);
}
