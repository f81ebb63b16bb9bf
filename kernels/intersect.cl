// intersect.cl — the intersect stage: closest hit and any hit through the BVH.
//
// Every entry point reads rays and the BVH (nodes, links, leaf-ordered triangles,
// prim_ids) and writes one Hit per ray (types.h). Launched with a fixed local size; items
// past the count return at once.
//   *_batch(rays, count, ...)      rays[0..count) in, hits out, for tests and the benchmark;
//                                  with -D WP_STATS also per-ray test counts in stats[]
//   intersect_*(rays, queue_count) wavefront entries: the queue length is read on the
//                                  device (queue_count[0]), so the host launches at capacity
//                                  and never reads counts back (pbrt-v4's ForAllQueued)
// Variants: closest (stackless, ordered: the default), closest_stack (the small-stack
// oracle and speed reference), any (stackless, first hit; shadow rays).
// -D WP_HAVE_ALPHA_MASK=1 adds the alpha test's arguments after each kernel's own
// (bvh_traverse.h WP_ALPHA_KERNEL_PARAMS) and skips cut-out hits (alpha.h).
// -D WP_PLAIN_TRIANGLES builds the benchmark-only baseline of `wavepath bench hard`
// (Möller-Trumbore triangles, plain box tests; not watertight): see triangle.h.
#include "shared/bvh_traverse.h"

#if defined(WP_STATS)
#define WP_STORE_STATS(i, st) stats[i] = st
#else
#define WP_STORE_STATS(i, st)
#endif

// One batch entry point and one wavefront entry point per traversal function.
#define WP_INTERSECT_ENTRIES(name, trace)                                                   \
    WP_KERNEL void name##_batch(WP_GLOBAL const Ray* rays, int count,                         \
                               WP_GLOBAL const BvhNode* nodes, WP_GLOBAL const BvhLinks* links, \
                               WP_GLOBAL const TriBlock* tris, WP_GLOBAL const int* prim_ids,   \
                               WP_GLOBAL Hit* hits, WP_GLOBAL TraceStats* stats WP_ALPHA_KERNEL_PARAMS) { \
        int i = wp_global_id();                                                             \
        if (i >= count) return;                                                             \
        WP_ALPHA_SETUP                                                                      \
        TraceStats st = {0, 0};                                                             \
        hits[i] = trace(rays[i], nodes, links, tris, prim_ids, &st WP_ALPHA_ARG);           \
        WP_STORE_STATS(i, st);                                                              \
    }                                                                                       \
    WP_KERNEL void name(WP_GLOBAL const Ray* rays, WP_GLOBAL const int* queue_count,           \
                       WP_GLOBAL const BvhNode* nodes, WP_GLOBAL const BvhLinks* links,       \
                       WP_GLOBAL const TriBlock* tris, WP_GLOBAL const int* prim_ids,         \
                       WP_GLOBAL Hit* hits WP_ALPHA_KERNEL_PARAMS) {                         \
        int i = wp_global_id();                                                             \
        if (i >= queue_count[0]) return;                                                    \
        WP_ALPHA_SETUP                                                                      \
        TraceStats st = {0, 0};                                                             \
        hits[i] = trace(rays[i], nodes, links, tris, prim_ids, &st WP_ALPHA_ARG);           \
    }

WP_INTERSECT_ENTRIES(intersect_closest, wp_trace_closest)
WP_INTERSECT_ENTRIES(intersect_closest_stack, wp_trace_closest_stack)
WP_INTERSECT_ENTRIES(intersect_any, wp_trace_any)

// The last bounce's rays (bounce == depth) in a scene whose escaped rays carry no radiance
// (black background, no environment that shines): such a ray adds light only where its
// closest hit is an emitter (at the last bounce shade only adds a hit's emission), so it is
// traced first through the BVH of the emitting triangles alone (e_*: DeviceScene::
// emitter_bvh, prim_ids in scene order), and through the whole scene only up to the emitter
// it meets (wp_trace_final, bvh_traverse.h): a miss where it meets none (which adds the same
// nothing a non-emitting hit would), else its unrestricted closest hit bit for bit.
// Wavefront::run_wave launches it for the last bounce (render --final-rays) where shade does
// not do it itself (shade.cl, shade_final); BatchTracer::trace_final for the tests.
WP_KERNEL void intersect_final(WP_GLOBAL const Ray* rays, WP_GLOBAL const int* queue_count,
                               WP_GLOBAL const BvhNode* nodes, WP_GLOBAL const BvhLinks* links,
                               WP_GLOBAL const TriBlock* tris, WP_GLOBAL const int* prim_ids,
                               WP_GLOBAL const BvhNode* e_nodes, WP_GLOBAL const BvhLinks* e_links,
                               WP_GLOBAL const TriBlock* e_tris, WP_GLOBAL const int* e_prim_ids,
                               WP_GLOBAL Hit* hits WP_ALPHA_KERNEL_PARAMS) {
    int i = wp_global_id();
    if (i >= queue_count[0]) return;
    WP_ALPHA_SETUP
    TraceStats st = {0, 0};
    Hit h;
    wp_trace_final(rays[i], nodes, links, tris, prim_ids, e_nodes, e_links, e_tris, e_prim_ids, &h,
                   &st WP_ALPHA_ARG);
    hits[i] = h;
}
