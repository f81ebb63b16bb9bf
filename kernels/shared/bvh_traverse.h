// bvh_traverse.h — closest-hit and any-hit traversal of the wide BVH (types.h).
//
// Three traversals over the same nodes; each node visit tests all WP_BVH_WIDTH (8) child
// boxes at once with float8 arithmetic: PoCL does not vectorise traversal loops across
// work-items, so the SIMD width has to be used inside one (NOTES-pocl.md trap 3).
//   * wp_trace_closest: stackless and ordered (nearest child first). The state is the
//     current node, a 64-bit bitstack with one bit per ancestor level ("children may be
//     left there") and parent links with the node's slot in its parent. Climbing back to
//     an ancestor re-tests its boxes against the current closest hit and continues with
//     the nearest child that comes after the one it came from in (entry t, slot) order,
//     so near-first order is kept without storing it. After Áfra & Szirmay-Kalos,
//     "Stackless Multi-BVH Traversal for CPU, MIC and GPU Ray Tracing", CGF 33(1), 2014.
//     A ring of the WP_BVH_SHORT_STACK (4) most recent pending ancestors spares most climbs
//     and re-tests; the order and the hits do not depend on it. The generic walk
//     (wp_trace_stackless, closest or any hit by a flag) is the host tests' oracle for
//     wp_trace_closest and wp_trace_any, its two specialised forms that the kernels run.
//   * wp_trace_closest_stack: the same order with a private stack of (child, entry t);
//     the oracle and the speed reference for the stackless one.
//   * wp_trace_any: stackless like wp_trace_closest, but children in slot order, and it
//     stops at the first hit; specialised for its constant cull distance (see there).
// Leaf children are intersected as the order reaches them, without descending.
//
// Box tests are conservative (Ize, "Robust BVH Ray Traversal", JCGT 2(2), 2013): the far
// distance is scaled by 1 + 2*gamma(3), and zero direction components get a reciprocal of
// 1/FLT_MIN (finite) instead of infinity, so no 0*inf NaN arises. A box whose entry
// distance equals the current closest t is still visited, so ties are found and broken by
// the rule in triangle.h.
//
// Why wide and why this state (measured with perf on PoCL, see the report in issue 2):
// the BVH2 stackless kernel was memory-latency bound. Its samples sat on the node loads
// that follow a backtrack, and a backtrack serialised its cache misses: ctz, then k
// dependent parent-link loads, then the far child's link load, then the node load, with
// a data-dependent climb loop (a mispredicted exit) and the bitstack spilled to the stack
// frame. The stack kernel pops the next node index from an L1-resident array, so its
// next miss starts at once. The eight-wide layout halves the levels (fewer climbs and
// fewer serial misses per ray), keeps the child references in the node (no dependent
// link load on the way down) and the up-links in a dense 8-byte array (cheap climbs).
#ifndef WP_BVH_TRAVERSE_H
#define WP_BVH_TRAVERSE_H

#include "triangle.h"

// Alpha cut-outs (alpha.h): with WP_HAVE_ALPHA_MASK every traversal takes an AlphaScene
// and skips candidate hits whose material is not there. Without it nothing changes.
#ifndef WP_HAVE_ALPHA_MASK
#define WP_HAVE_ALPHA_MASK 0
#endif
#if WP_HAVE_ALPHA_MASK
#include "alpha.h"
#define WP_ALPHA_PARAM , const AlphaScene* alpha
#define WP_ALPHA_ARG , alpha
// The kernel arguments that feed it (after a kernel's own, in this order) and the
// AlphaScene `alpha` built from them at the top of the kernel.
#define WP_ALPHA_KERNEL_PARAMS                                                              \
    , WP_GLOBAL const int *material_ids, WP_GLOBAL const MaterialTextures *material_textures, \
        WP_GLOBAL const TriUVs *tri_uvs, WP_GLOBAL const TextureData *textures,              \
        WP_GLOBAL const TextureView *texture_views, WP_GLOBAL const uint *texels8,           \
        WP_GLOBAL const float4 *texelsf
#define WP_ALPHA_SETUP                                     \
    AlphaScene alpha_scene;                                \
    alpha_scene.material_ids = material_ids;               \
    alpha_scene.material_textures = material_textures;     \
    alpha_scene.uvs = tri_uvs;                             \
    alpha_scene.pool.textures = textures;                  \
    alpha_scene.pool.views = texture_views;                \
    alpha_scene.pool.texels8 = texels8;                    \
    alpha_scene.pool.texelsf = texelsf;                    \
    const AlphaScene* alpha = &alpha_scene;
#else
#define WP_ALPHA_PARAM
#define WP_ALPHA_ARG
#define WP_ALPHA_KERNEL_PARAMS
#define WP_ALPHA_SETUP
#endif

WP_NAMESPACE_BEGIN

#if defined(WP_PLAIN_TRIANGLES)
// Benchmark-only baseline (see triangle.h): plain, non-conservative box tests.
#define WP_BOX_FAR_SCALE 1.0f
#else
#define WP_BOX_FAR_SCALE 1.00000036f  // 1 + 2 * gamma(3), rounded up (Ize 2013)
#endif
// Boxes are culled against the closest hit so far only when they start clearly behind it:
// the triangle test's own rounding (a few ulps, more at grazing angles) must not decide
// which of two nearly coincident hits (overlapping coplanar triangles) is visited, or the
// winner would depend on the traversal order. 1 + 2^-14.
#if defined(WP_PLAIN_TRIANGLES)
#define WP_HIT_CULL_SCALE 1.0f
#else
#define WP_HIT_CULL_SCALE 1.00006104f
#endif

// Width-generic vector helpers over WpLanes (types.h).
#if WP_BVH_WIDTH == 8
#define wp_wsplat wp_splat8
#define wp_wmask_le wp_mask8_le
#define wp_wmask_lt wp_mask8_lt
#define wp_wmask_eq wp_mask8_eq
#define wp_wlane wp_lane8
#else
#define wp_wsplat wp_splat4
#define wp_wmask_le wp_mask4_le
#define wp_wmask_lt wp_mask4_lt
#define wp_wmask_eq wp_mask4_eq
#define wp_wlane wp_lane4
#endif
#define WP_SLOTS_ALL ((1 << WP_BVH_WIDTH) - 1)
// Slots after slot s (a mask).
#define WP_SLOTS_AFTER(s) ((WP_SLOTS_ALL << ((s) + 1)) & WP_SLOTS_ALL)

// Per-ray constants of the four-wide box test.
typedef struct BoxRay {
    WpLanes ox, oy, oz;  // origin, broadcast
    WpLanes ix, iy, iz;  // safe reciprocal direction, broadcast
    WpLanes tmin;        // broadcast
    int nx, ny, nz;     // row of the near plane per axis in BvhNode (2 * axis + (dir < 0))
} BoxRay;

// 1/d with |d| clamped to [FLT_MIN, 2^126], so the result is finite and never denormal.
// The upper clamp matters on PoCL: LLVM packs the three divides into one four-lane divide
// whose spare lane holds dir.w (tmax, often FLT_MAX), and 1/FLT_MAX is denormal: a
// microcode assist on every ray (13% of the four-wide closest-hit kernel's samples).
WP_FN float wp_safe_rcp(float d) { return 1.0f / copysign(min(max(fabs(d), FLT_MIN), 0x1p126f), d); }

WP_FN BoxRay wp_box_ray(Ray ray) {
    BoxRay b;
#if defined(WP_OPENCL)
    // The three reciprocals as one four-lane divide, each lane correctly rounded, so the
    // same bits as wp_safe_rcp per component; the spare lane divides 1 by 1 (no denormal).
    // LLVM 15 packed only one of this and wp_tri_ray's three divides itself, and left the
    // other three scalar (callgrind: -3.4 % of the closest-hit kernel's instructions).
    float4 d = (float4)(ray.dir.x, ray.dir.y, ray.dir.z, 1.0f);
    float4 rc = 1.0f / copysign(min(max(fabs(d), FLT_MIN), 0x1p126f), d);
    float ix = rc.x, iy = rc.y, iz = rc.z;
#else
    float ix = wp_safe_rcp(ray.dir.x), iy = wp_safe_rcp(ray.dir.y), iz = wp_safe_rcp(ray.dir.z);
#endif
    b.ox = wp_wsplat(ray.org.x);
    b.oy = wp_wsplat(ray.org.y);
    b.oz = wp_wsplat(ray.org.z);
    b.ix = wp_wsplat(ix);
    b.iy = wp_wsplat(iy);
    b.iz = wp_wsplat(iz);
    b.tmin = wp_wsplat(ray.org.w);
    b.nx = ix < 0.0f ? 1 : 0;
    b.ny = iy < 0.0f ? 3 : 2;
    b.nz = iz < 0.0f ? 5 : 4;
    return b;
}

// Tests the child boxes of a node against [tmin, tcull]. Returns a bit mask (bit i: child
// i hit) and the entry distances (lane i: child i; max(entry, tmin)).
WP_FN int wp_intersect_node(const BoxRay* r, WP_GLOBAL const BvhNode* node, float tcull, WpLanes* tnear) {
    WP_GLOBAL const WpLanes* rows = (WP_GLOBAL const WpLanes*)node;
    WpLanes nx = (rows[r->nx] - r->ox) * r->ix;
    WpLanes ny = (rows[r->ny] - r->oy) * r->iy;
    WpLanes nz = (rows[r->nz] - r->oz) * r->iz;
    WpLanes fx = (rows[r->nx ^ 1] - r->ox) * r->ix;
    WpLanes fy = (rows[r->ny ^ 1] - r->oy) * r->iy;
    WpLanes fz = (rows[r->nz ^ 1] - r->oz) * r->iz;
    WpLanes tn = max(max(nx, ny), max(nz, r->tmin));
    // The far bound (box exit or current closest t) is widened, so rounding in either
    // never culls a box whose true entry lies before it.
    WpLanes tf = min(min(min(fx, fy), fz) * WP_BOX_FAR_SCALE, wp_wsplat(tcull));
    *tnear = tn;
    return wp_wmask_le(tn, tf);
}

// The child reference in slot s of node `cur`.
WP_FN int wp_child(WP_GLOBAL const BvhNode* nodes, int cur, int s) {
    return (&nodes[cur].child0)[s];
}

// The candidate with the smallest (entry t, slot), and the one with the largest.
WP_FN int wp_nearest(WpLanes t, int cand) {
    int best = wp_ctz32((uint)cand);
    int rest = cand & (cand - 1);
    if (rest == 0) return best;  // one candidate (the common case)
    float bt = wp_wlane(t, best);
    for (; rest != 0; rest &= rest - 1) {
        int i = wp_ctz32((uint)rest);
        float ti = wp_wlane(t, i);
        if (ti < bt) {
            bt = ti;
            best = i;
        }
    }
    return best;
}

WP_FN int wp_farthest(WpLanes t, int cand) {
    int best = wp_ctz32((uint)cand);
    float bt = wp_wlane(t, best);
    for (int rest = cand & (cand - 1); rest != 0; rest &= rest - 1) {
        int i = wp_ctz32((uint)rest);
        float ti = wp_wlane(t, i);
        if (ti >= bt) {  // ties: the larger slot is the farther
            bt = ti;
            best = i;
        }
    }
    return best;
}

// Slots whose (entry t, slot) comes after slot sc's.
WP_FN int wp_after(WpLanes t, int sc) {
    WpLanes tc = wp_wsplat(wp_wlane(t, sc));
    return wp_wmask_lt(tc, t) | (wp_wmask_eq(t, tc) & WP_SLOTS_AFTER(sc));
}

WP_FN int wp_leaf_first(int ref) { return (~ref) >> WP_LEAF_COUNT_BITS; }
WP_FN int wp_leaf_count(int ref) { return (~ref) & WP_LEAF_MAX_COUNT; }

// Intersects the triangles of one leaf, a block of four at a time (wp_intersect_block),
// keeping the closest hit (ties: smallest prim): each block's hit lanes in leaf order, so the
// updates are those of a loop over the triangles. Returns 1 when any triangle was hit
// (and kept by the alpha test).
WP_FN int wp_intersect_leaf(const TriRay* tr, int ref, WP_GLOBAL const TriBlock* tris,
                            WP_GLOBAL const int* prim_ids, Hit* hit, TraceStats* stats WP_ALPHA_PARAM) {
    (void)stats;  // used only with WP_STATS
    const int first = wp_leaf_first(ref), count = wp_leaf_count(ref);
#if defined(WP_STATS)
    stats->tri_tests += count;
#endif
    int any = 0;
    for (int b = 0; b * WP_TRI_BLOCK < count; ++b) {
        float4 t4, u4, v4;
        int m = wp_intersect_block(tr, tris + first + b, min(count - b * WP_TRI_BLOCK, WP_TRI_BLOCK), &t4, &u4, &v4);
        for (; m != 0; m &= m - 1) {
            const int i = wp_ctz32((uint)m);
            const float t = wp_lane4(t4, i);
            const int prim = prim_ids[(first + b) * WP_TRI_BLOCK + i];
            const float u = wp_lane4(u4, i), v = wp_lane4(v4, i);
            if ((t < hit->t || (t == hit->t && prim < hit->prim))
#if WP_HAVE_ALPHA_MASK
                && wp_alpha_pass(alpha, prim, u, v)
#endif
            ) {
                hit->t = t;
                hit->prim = prim;
                hit->u = u;
                hit->v = v;
                any = 1;
            }
        }
    }
    return any;
}

// The any-hit form: stops at the leaf's first triangle hit in (tmin, tmax) (and kept by
// the alpha test), so it returns 1 exactly when wp_intersect_leaf would (whose first update
// needs t < tmax, as hit->prim is still -1), without testing the blocks after it; the hit it
// reports is that triangle, not the leaf's closest.
WP_FN int wp_intersect_leaf_any(const TriRay* tr, int ref, WP_GLOBAL const TriBlock* tris,
                                WP_GLOBAL const int* prim_ids, Hit* hit, TraceStats* stats WP_ALPHA_PARAM) {
    (void)stats;  // used only with WP_STATS
    const int first = wp_leaf_first(ref), count = wp_leaf_count(ref);
    for (int b = 0; b * WP_TRI_BLOCK < count; ++b) {
        const int lanes = min(count - b * WP_TRI_BLOCK, WP_TRI_BLOCK);
#if defined(WP_STATS)
        stats->tri_tests += lanes;
#endif
        float4 t4, u4, v4;
        int m = wp_intersect_block(tr, tris + first + b, lanes, &t4, &u4, &v4) &
                wp_mask4_lt(t4, wp_splat4(hit->t));
        for (; m != 0; m &= m - 1) {
            const int i = wp_ctz32((uint)m);
            const int prim = prim_ids[(first + b) * WP_TRI_BLOCK + i];
            const float u = wp_lane4(u4, i), v = wp_lane4(v4, i);
#if WP_HAVE_ALPHA_MASK
            if (!wp_alpha_pass(alpha, prim, u, v)) continue;
#endif
            hit->t = wp_lane4(t4, i);
            hit->prim = prim;
            hit->u = u;
            hit->v = v;
            return 1;
        }
    }
    return 0;
}

WP_FN Hit wp_miss(Ray ray) {
    Hit h;
    h.t = ray.dir.w;
    h.prim = -1;
    h.u = 0.0f;
    h.v = 0.0f;
    return h;
}

// Stackless traversal: closest hit (ordered; wp_trace_closest) or any hit (slot order,
// early out). The kernels run wp_trace_closest and wp_trace_any below, specialised forms of
// this walk; the generic one stays as their oracle in the host tests.
//
// A climb normally re-tests the ancestor's boxes to find the children it has left. A short
// ring of the WP_BVH_SHORT_STACK most recent such ancestors (node, candidates left, entry
// distances) saves that: the deepest pending ancestor is always the newest entry, and its
// candidates are the stored ones still entered before the current closest hit — the very
// set the re-test gives (same entry distances, the cull only tighter), so the visiting
// order and the hits are unchanged. When the ring has been overrun (deeper than its size)
// the climb falls back to the up-links and the re-test. The state stays bounded (the
// 64-bit word, the ring, no stack that grows with depth).
WP_FN Hit wp_trace_stackless(Ray ray, WP_GLOBAL const BvhNode* nodes,
                             WP_GLOBAL const BvhLinks* links, WP_GLOBAL const TriBlock* tris,
                             WP_GLOBAL const int* prim_ids, int any_hit, TraceStats* stats WP_ALPHA_PARAM) {
    Hit hit = wp_miss(ray);
    BoxRay br = wp_box_ray(ray);
    TriRay tr = wp_tri_ray(ray);
    ulong bits = 0;  // bit k: the ancestor k + 1 levels above `cur` may have children left
    int cur = 0;
    int sc = -1;     // slot of the child we climbed back from; -1 on a first visit
    int ring_node[WP_BVH_SHORT_STACK];
    int ring_cand[WP_BVH_SHORT_STACK];
    WpLanes ring_tn[WP_BVH_SHORT_STACK];
    int ring_top = 0, ring_count = 0;  // the newest entry; how many entries are valid
    WpLanes tn = wp_wsplat(0.0f);
    int cand = 0;
    int resume = 0;  // cand and tn of `cur` came from the ring: no box test
    for (;;) {
        if (!resume) {
            cand = wp_intersect_node(&br, nodes + cur, hit.t * WP_HIT_CULL_SCALE, &tn);
#if defined(WP_STATS)
            stats->box_tests += WP_BVH_WIDTH;
#endif
            if (sc >= 0) cand &= any_hit ? WP_SLOTS_AFTER(sc) : wp_after(tn, sc);
        }
        resume = 0;
        // Children in order: leaves at once, the first interior child is descended into.
        int next = -1;
        while (cand != 0) {
            int s = any_hit ? wp_ctz32((uint)cand) : wp_nearest(tn, cand);
            cand &= ~(1 << s);
            int c = wp_child(nodes, cur, s);
            if (c >= 0) {
                next = c;
                break;
            }
            if (wp_intersect_leaf(&tr, c, tris, prim_ids, &hit, stats WP_ALPHA_ARG)) {
                if (any_hit) return hit;
                // Drop the children that now start behind the closest hit.
                cand &= wp_wmask_le(tn, wp_wsplat(hit.t * WP_HIT_CULL_SCALE));
            }
        }
        if (next >= 0) {
            if (cand != 0) {
                ring_top = (ring_top + 1) & (WP_BVH_SHORT_STACK - 1);
                ring_node[ring_top] = cur;
                ring_cand[ring_top] = cand;
                ring_tn[ring_top] = tn;
                ring_count = min(ring_count + 1, WP_BVH_SHORT_STACK);
            }
            bits = (bits << 1) | (cand != 0 ? 1u : 0u);
            cur = next;
            sc = -1;
            continue;
        }
        // Climb to the deepest ancestor that may have children left: from the ring, or by
        // the up-links and a re-test.
        if (bits == 0) return hit;
        int k = wp_ctz64(bits);
        bits = (bits >> k) >> 1;
        if (ring_count > 0) {
            cur = ring_node[ring_top];
            tn = ring_tn[ring_top];
            cand = ring_cand[ring_top] & wp_wmask_le(tn, wp_wsplat(hit.t * WP_HIT_CULL_SCALE));
            ring_top = (ring_top - 1) & (WP_BVH_SHORT_STACK - 1);
            --ring_count;
            resume = 1;
            continue;
        }
        for (int j = 0; j <= k; ++j) {
            BvhLinks l = links[cur];
            sc = l.slot;
            cur = l.parent;
        }
    }
}

// Closest hit: the walk of wp_trace_stackless with any_hit = 0, specialised: each node's
// boxes are tested where the walk arrives at it (on the way down, or after an up-link
// climb, then with wp_after on the slot it came from), so the loop has no "resumed from the
// ring" flag, no sc = -1 state and no any_hit selects; the cull distance is kept in a
// variable that changes only with the closest hit. The same node tests, candidates and
// order as the generic walk, so the same hits bit for bit (tested against it on the host).
WP_FN Hit wp_trace_closest(Ray ray, WP_GLOBAL const BvhNode* nodes, WP_GLOBAL const BvhLinks* links,
                           WP_GLOBAL const TriBlock* tris, WP_GLOBAL const int* prim_ids,
                           TraceStats* stats WP_ALPHA_PARAM) {
    Hit hit = wp_miss(ray);
    BoxRay br = wp_box_ray(ray);
    TriRay tr = wp_tri_ray(ray);
    float tcull = hit.t * WP_HIT_CULL_SCALE;
    ulong bits = 0;  // bit k: the ancestor k + 1 levels above `cur` may have children left
    int cur = 0;
    int ring_node[WP_BVH_SHORT_STACK];
    int ring_cand[WP_BVH_SHORT_STACK];
    WpLanes ring_tn[WP_BVH_SHORT_STACK];
    int ring_top = 0, ring_count = 0;  // the newest entry; how many entries are valid
    WpLanes tn;
    int cand = wp_intersect_node(&br, nodes, tcull, &tn);
#if defined(WP_STATS)
    stats->box_tests += WP_BVH_WIDTH;
#endif
    for (;;) {
        // Children in order: leaves at once, the first interior child is descended into.
        int next = -1;
        while (cand != 0) {
            int s = wp_nearest(tn, cand);
            cand &= ~(1 << s);
            int c = wp_child(nodes, cur, s);
            if (c >= 0) {
                next = c;
                break;
            }
            if (wp_intersect_leaf(&tr, c, tris, prim_ids, &hit, stats WP_ALPHA_ARG)) {
                // Drop the children that now start behind the closest hit.
                tcull = hit.t * WP_HIT_CULL_SCALE;
                cand &= wp_wmask_le(tn, wp_wsplat(tcull));
            }
        }
        if (next >= 0) {
            if (cand != 0) {
                ring_top = (ring_top + 1) & (WP_BVH_SHORT_STACK - 1);
                ring_node[ring_top] = cur;
                ring_cand[ring_top] = cand;
                ring_tn[ring_top] = tn;
                ring_count = min(ring_count + 1, WP_BVH_SHORT_STACK);
            }
            bits = (bits << 1) | (cand != 0 ? 1u : 0u);
            cur = next;
            cand = wp_intersect_node(&br, nodes + cur, tcull, &tn);
#if defined(WP_STATS)
            stats->box_tests += WP_BVH_WIDTH;
#endif
            continue;
        }
        // Climb to the deepest ancestor that may have children left: from the ring, or by
        // the up-links and a re-test.
        if (bits == 0) return hit;
        int k = wp_ctz64(bits);
        bits = (bits >> k) >> 1;
        if (ring_count > 0) {
            cur = ring_node[ring_top];
            tn = ring_tn[ring_top];
            cand = ring_cand[ring_top] & wp_wmask_le(tn, wp_wsplat(tcull));
            ring_top = (ring_top - 1) & (WP_BVH_SHORT_STACK - 1);
            --ring_count;
            continue;
        }
        int sc = 0;
        for (int j = 0; j <= k; ++j) {
            BvhLinks l = links[cur];
            sc = l.slot;
            cur = l.parent;
        }
        cand = wp_intersect_node(&br, nodes + cur, tcull, &tn);
        cand &= wp_after(tn, sc);
#if defined(WP_STATS)
        stats->box_tests += WP_BVH_WIDTH;
#endif
    }
}

// Any hit: the same slot-order walk as wp_trace_stackless(any_hit = 1) (the same leaves in
// the same order, so the same occlusion on every ray), specialised. Within the first leaf
// that is hit it stops at the first triangle (wp_intersect_leaf_any), so the hit it reports
// may be another triangle of that leaf than the generic walk's. As it stops at the first
// hit, its cull distance never changes: one broadcast tmax * WP_HIT_CULL_SCALE for every
// box test (no reload of the hit, no multiply per node), and a box's candidates stay
// exactly the ones its first test gave, so the ring keeps only (node, children left) — no
// entry distances to store, reload or re-cull.
// Eight bytes an entry make a deeper ring cheap (WP_BVH_ANY_RING); past it the climb
// falls back to the up-links and a re-test, as in the closest-hit traversal.
WP_FN Hit wp_trace_any(Ray ray, WP_GLOBAL const BvhNode* nodes, WP_GLOBAL const BvhLinks* links,
                       WP_GLOBAL const TriBlock* tris, WP_GLOBAL const int* prim_ids,
                       TraceStats* stats WP_ALPHA_PARAM) {
    Hit hit = wp_miss(ray);
    BoxRay br = wp_box_ray(ray);
    TriRay tr = wp_tri_ray(ray);
    const float tcull = hit.t * WP_HIT_CULL_SCALE;  // hit.t stays tmax until the return
    ulong bits = 0;  // bit k: the ancestor k + 1 levels above `cur` may have children left
    int cur = 0;
    int cand = 0;
    int ring_node[WP_BVH_ANY_RING];
    int ring_cand[WP_BVH_ANY_RING];
    int ring_top = 0, ring_count = 0;
    WpLanes tn;
    cand = wp_intersect_node(&br, nodes, tcull, &tn);
#if defined(WP_STATS)
    stats->box_tests += WP_BVH_WIDTH;
#endif
    for (;;) {
        int next = -1;
        while (cand != 0) {
            int s = wp_ctz32((uint)cand);
            cand &= cand - 1;
            int c = wp_child(nodes, cur, s);
            if (c >= 0) {
                next = c;
                break;
            }
            if (wp_intersect_leaf_any(&tr, c, tris, prim_ids, &hit, stats WP_ALPHA_ARG)) return hit;
        }
        if (next >= 0) {
            if (cand != 0) {
                ring_top = (ring_top + 1) & (WP_BVH_ANY_RING - 1);
                ring_node[ring_top] = cur;
                ring_cand[ring_top] = cand;
                ring_count = min(ring_count + 1, WP_BVH_ANY_RING);
            }
            bits = (bits << 1) | (cand != 0 ? 1u : 0u);
            cur = next;
            cand = wp_intersect_node(&br, nodes + cur, tcull, &tn);
#if defined(WP_STATS)
            stats->box_tests += WP_BVH_WIDTH;
#endif
            continue;
        }
        if (bits == 0) return hit;
        int k = wp_ctz64(bits);
        bits = (bits >> k) >> 1;
        if (ring_count > 0) {
            cur = ring_node[ring_top];
            cand = ring_cand[ring_top];
            ring_top = (ring_top - 1) & (WP_BVH_ANY_RING - 1);
            --ring_count;
            continue;
        }
        int sc = 0;
        for (int j = 0; j <= k; ++j) {
            BvhLinks l = links[cur];
            sc = l.slot;
            cur = l.parent;
        }
        cand = wp_intersect_node(&br, nodes + cur, tcull, &tn) & WP_SLOTS_AFTER(sc);
#if defined(WP_STATS)
        stats->box_tests += WP_BVH_WIDTH;
#endif
    }
}

// Ordered traversal with a private stack of (child reference, entry distance): the same
// visiting order as wp_trace_closest, the remaining children pushed far to near.
WP_FN Hit wp_trace_closest_stack(Ray ray, WP_GLOBAL const BvhNode* nodes,
                                 WP_GLOBAL const BvhLinks* links, WP_GLOBAL const TriBlock* tris,
                                 WP_GLOBAL const int* prim_ids, TraceStats* stats WP_ALPHA_PARAM) {
    (void)links;  // same arguments as the stackless traversal; the stack needs no up-links
    Hit hit = wp_miss(ray);
    BoxRay br = wp_box_ray(ray);
    TriRay tr = wp_tri_ray(ray);
    int stack_ref[WP_BVH_STACK_SIZE];
    float stack_t[WP_BVH_STACK_SIZE];
    int sp = 0;
    int next = 0;
    for (;;) {
        if (next >= 0) {
            int cur = next;
            WpLanes tn;
            int cand = wp_intersect_node(&br, nodes + cur, hit.t * WP_HIT_CULL_SCALE, &tn);
#if defined(WP_STATS)
            stats->box_tests += WP_BVH_WIDTH;
#endif
            next = -1;
            while (cand != 0) {
                int s = wp_nearest(tn, cand);
                cand &= ~(1 << s);
                int c = wp_child(nodes, cur, s);
                if (c >= 0) {
                    next = c;
                    break;
                }
                if (wp_intersect_leaf(&tr, c, tris, prim_ids, &hit, stats WP_ALPHA_ARG))
                    cand &= wp_wmask_le(tn, wp_wsplat(hit.t * WP_HIT_CULL_SCALE));
            }
            while (cand != 0) {
                int s = wp_farthest(tn, cand);
                cand &= ~(1 << s);
                stack_ref[sp] = wp_child(nodes, cur, s);
                stack_t[sp] = wp_wlane(tn, s);
                ++sp;
            }
            if (next >= 0) continue;
        } else if (next != -1) {
            wp_intersect_leaf(&tr, next, tris, prim_ids, &hit, stats WP_ALPHA_ARG);
        }
        // Pop the nearest pending entry that can still hold a closer hit.
        next = -1;
        while (sp > 0) {
            --sp;
            if (stack_t[sp] <= hit.t * WP_HIT_CULL_SCALE) {
                next = stack_ref[sp];
                break;
            }
        }
        if (next == -1) return hit;
    }
}

// The closest hit of a last-bounce ray in a scene whose escaped rays carry no light
// (intersect.cl, intersect_final; shade.cl, shade_final): first through the BVH of the
// emitting triangles alone (e_*; prim_ids in scene order); a ray that meets no emitter gets
// that miss. One that meets an emitter at t_e is traced through the whole scene for hits at
// t <= t_e (tmax: the next float above t_e), which is its unrestricted closest hit bit for
// bit (the closest hit is the smallest (t, prim) among the ray's hits, and (t_e, that
// emitter) is one of them). One loop over the two BVHs, so that the traversal is inlined
// once: each inlined copy costs PoCL's compile time and, left as a call, the walk itself.
// The hit goes to *hit: a function that returns a struct and is inlined leaves an
// llvm.experimental.noalias.scope.decl (for its return slot) that Oclgrind cannot run.
WP_FN void wp_trace_final(Ray r, WP_GLOBAL const BvhNode* nodes, WP_GLOBAL const BvhLinks* links,
                          WP_GLOBAL const TriBlock* tris, WP_GLOBAL const int* prim_ids,
                          WP_GLOBAL const BvhNode* e_nodes, WP_GLOBAL const BvhLinks* e_links,
                          WP_GLOBAL const TriBlock* e_tris, WP_GLOBAL const int* e_prim_ids, Hit* hit,
                          TraceStats* stats WP_ALPHA_PARAM) {
    for (int whole = 0; whole < 2; ++whole) {
        *hit = wp_trace_closest(r, whole ? nodes : e_nodes, whole ? links : e_links, whole ? tris : e_tris,
                                whole ? prim_ids : e_prim_ids, stats WP_ALPHA_ARG);
        if (hit->prim < 0) break;                // no emitter on the ray (or, whole: cannot be)
        r.dir.w = as_float(as_int(hit->t) + 1);  // hits at t <= t_e
    }
}

WP_NAMESPACE_END

#endif  // WP_BVH_TRAVERSE_H
