// bvh_traverse.h — closest-hit and any-hit traversal of the two-wide BVH (types.h).
//
// Three traversals over the same nodes:
//   * wp_trace_closest: stackless and ordered (near child first). The state is the
//     current node, a 64-bit "pending" bitstack (one bit per level: the far child is
//     still to visit) and a 64-bit "order" word (which child was the far one), and
//     parent links to climb back. After Áfra & Szirmay-Kalos, "Stackless Multi-BVH
//     Traversal for CPU, MIC and GPU Ray Tracing", CGF 33(1), 2014, and Hapala et al.,
//     "Efficient Stack-less BVH Traversal for Ray Tracing", SCCG 2011.
//   * wp_trace_closest_stack: the classic ordered traversal with a 64-entry private
//     stack that remembers each far child's entry distance; the oracle and the speed
//     reference for the stackless one.
//   * wp_trace_any: stackless, unordered (child 0 first), stops at the first hit.
//
// Box tests are conservative (Ize, "Robust BVH Ray Traversal", JCGT 2(2), 2013): the far
// distance is scaled by 1 + 2*gamma(3), and zero direction components get a reciprocal of
// 1/FLT_MIN (finite) instead of infinity, so no 0*inf NaN arises. A box whose entry
// distance equals the current closest t is still visited, so ties are found and broken by
// the rule in triangle.h.
#ifndef WP_BVH_TRAVERSE_H
#define WP_BVH_TRAVERSE_H

#include "triangle.h"

WP_NAMESPACE_BEGIN

#define WP_BOX_FAR_SCALE 1.00000036f  // 1 + 2 * gamma(3), rounded up (Ize 2013)
// Boxes are culled against the closest hit so far only when they start clearly behind it:
// the triangle test's own rounding (a few ulps, more at grazing angles) must not decide
// which of two nearly coincident hits (overlapping coplanar triangles) is visited, or the
// winner would depend on the traversal order. 1 + 2^-14.
#define WP_HIT_CULL_SCALE 1.00006104f

// Per-ray constants of the box test.
typedef struct BoxRay {
    float ox, oy, oz;
    float ix, iy, iz;  // safe reciprocal direction
    float tmin;
} BoxRay;

WP_FN float wp_safe_rcp(float d) { return 1.0f / (fabs(d) >= FLT_MIN ? d : copysign(FLT_MIN, d)); }

WP_FN BoxRay wp_box_ray(Ray ray) {
    BoxRay b;
    b.ox = ray.org.x;
    b.oy = ray.org.y;
    b.oz = ray.org.z;
    b.ix = wp_safe_rcp(ray.dir.x);
    b.iy = wp_safe_rcp(ray.dir.y);
    b.iz = wp_safe_rcp(ray.dir.z);
    b.tmin = ray.org.w;
    return b;
}

// Tests both child boxes of a node against [tmin, tmax]. Returns a bit mask (bit 0: child
// 0 hit, bit 1: child 1 hit) and the entry distances.
WP_FN int wp_intersect_node(const BoxRay* r, BvhNode n, float tmax, float* t0, float* t1) {
    // Lanes (lo0, lo1, hi0, hi1) of each axis become slab distances; swapping halves and
    // taking min/max sorts them into entry (lanes x,y) and exit (lanes z,w) per child.
    float4 tx = (n.x - r->ox) * r->ix;
    float4 ty = (n.y - r->oy) * r->iy;
    float4 tz = (n.z - r->oz) * r->iz;
    float4 sx = wp_swap_halves(tx), sy = wp_swap_halves(ty), sz = wp_swap_halves(tz);
    float4 tnear = max(max(min(tx, sx), min(ty, sy)), min(tz, sz));
    float4 tfar = min(min(max(tx, sx), max(ty, sy)), max(tz, sz));
    float near0 = max(tnear.x, r->tmin), near1 = max(tnear.y, r->tmin);
    // The far bound (box exit or current closest t) is widened, so rounding in either
    // never culls a box whose true entry lies before it.
    float tcull = tmax * WP_HIT_CULL_SCALE;
    float far0 = min(tfar.x * WP_BOX_FAR_SCALE, tcull);
    float far1 = min(tfar.y * WP_BOX_FAR_SCALE, tcull);
    *t0 = near0;
    *t1 = near1;
    return (near0 <= far0 ? 1 : 0) | (near1 <= far1 ? 2 : 0);
}

WP_FN int wp_leaf_first(int ref) { return (~ref) >> WP_LEAF_COUNT_BITS; }
WP_FN int wp_leaf_count(int ref) { return (~ref) & WP_LEAF_MAX_COUNT; }

// Intersects the triangles of one leaf, keeping the closest hit (ties: smallest prim).
// Returns 1 when any triangle was hit (the any-hit traversal stops there).
WP_FN int wp_intersect_leaf(const TriRay* tr, int ref, WP_GLOBAL const Triangle* tris,
                            WP_GLOBAL const int* prim_ids, Hit* hit, TraceStats* stats) {
    int first = wp_leaf_first(ref), count = wp_leaf_count(ref);
    int any = 0;
    for (int i = first; i < first + count; ++i) {
        Triangle tri = tris[i];
        float t, u, v;
#if defined(WP_STATS)
        stats->tri_tests += 1;
#endif
        if (wp_intersect_triangle(tr, tri.v0, tri.v1, tri.v2, &t, &u, &v)) {
            int prim = prim_ids[i];
            if (t < hit->t || (t == hit->t && prim < hit->prim)) {
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

WP_FN Hit wp_miss(Ray ray) {
    Hit h;
    h.t = ray.dir.w;
    h.prim = -1;
    h.u = 0.0f;
    h.v = 0.0f;
    return h;
}

// Stackless traversal shared by closest hit (ordered) and any hit (unordered, early out).
WP_FN Hit wp_trace_stackless(Ray ray, WP_GLOBAL const BvhNode* nodes,
                             WP_GLOBAL const BvhLinks* links, WP_GLOBAL const Triangle* tris,
                             WP_GLOBAL const int* prim_ids, int any_hit, TraceStats* stats) {
    Hit hit = wp_miss(ray);
    BoxRay br = wp_box_ray(ray);
    TriRay tr = wp_tri_ray(ray);
    ulong pending = 0;  // bit k: the far child at depth (current - k) is still to visit
    ulong order = 0;    // bit k: that far child is child 0 (the near one was child 1)
    int cur = 0;
    for (;;) {
        // Visit the interior node `cur`: test both children, push one level of state.
        float t0, t1;
        int mask = wp_intersect_node(&br, nodes[cur], hit.t, &t0, &t1);
#if defined(WP_STATS)
        stats->box_tests += 2;
#endif
        BvhLinks l = links[cur];
        int next;
        if (mask == 3) {
            int swap = any_hit ? 0 : (t1 < t0);
            next = swap ? l.child1 : l.child0;
            pending = (pending << 1) | 1;
            order = (order << 1) | (ulong)swap;
        } else {
            next = mask == 1 ? l.child0 : l.child1;
            pending <<= 1;
            order <<= 1;
            if (mask == 0) next = -1;  // an empty leaf: go straight to backtracking
        }
        // Leaves and pending far children until an interior node is reached.
        for (;;) {
            if (next >= 0) break;
            if (next != -1 && wp_intersect_leaf(&tr, next, tris, prim_ids, &hit, stats) && any_hit)
                return hit;
            // Backtrack: climb to the deepest level with a pending far child.
            if (pending == 0) return hit;
            int up = wp_ctz64(pending);
            pending >>= up;
            order >>= up;
            for (int k = 0; k < up; ++k) cur = links[cur].parent;
            pending ^= 1;
            BvhLinks pl = links[cur];
            next = (order & 1) ? pl.child0 : pl.child1;
#if defined(WP_STACKLESS_RETEST)
            // Re-test the far child: the closest hit may have moved in front of it.
            float r0, r1;
            int m = wp_intersect_node(&br, nodes[cur], hit.t, &r0, &r1);
#if defined(WP_STATS)
            stats->box_tests += 1;
#endif
            if (!(m & ((order & 1) ? 1 : 2))) next = -1;
#endif
        }
        cur = next;
    }
}

WP_FN Hit wp_trace_closest(Ray ray, WP_GLOBAL const BvhNode* nodes, WP_GLOBAL const BvhLinks* links,
                           WP_GLOBAL const Triangle* tris, WP_GLOBAL const int* prim_ids,
                           TraceStats* stats) {
    return wp_trace_stackless(ray, nodes, links, tris, prim_ids, 0, stats);
}

WP_FN Hit wp_trace_any(Ray ray, WP_GLOBAL const BvhNode* nodes, WP_GLOBAL const BvhLinks* links,
                       WP_GLOBAL const Triangle* tris, WP_GLOBAL const int* prim_ids,
                       TraceStats* stats) {
    return wp_trace_stackless(ray, nodes, links, tris, prim_ids, 1, stats);
}

// Ordered traversal with a private stack of (child reference, entry distance).
WP_FN Hit wp_trace_closest_stack(Ray ray, WP_GLOBAL const BvhNode* nodes,
                                 WP_GLOBAL const BvhLinks* links, WP_GLOBAL const Triangle* tris,
                                 WP_GLOBAL const int* prim_ids, TraceStats* stats) {
    Hit hit = wp_miss(ray);
    BoxRay br = wp_box_ray(ray);
    TriRay tr = wp_tri_ray(ray);
    int stack_ref[WP_BVH_MAX_DEPTH];
    float stack_t[WP_BVH_MAX_DEPTH];
    int sp = 0;
    int next = 0;
    for (;;) {
        if (next >= 0) {
            // Interior node: near child next, far child on the stack.
            float t0, t1;
            int mask = wp_intersect_node(&br, nodes[next], hit.t, &t0, &t1);
#if defined(WP_STATS)
            stats->box_tests += 2;
#endif
            BvhLinks l = links[next];
            if (mask == 3) {
                int swap = t1 < t0;
                stack_ref[sp] = swap ? l.child0 : l.child1;
                stack_t[sp] = swap ? t0 : t1;
                ++sp;
                next = swap ? l.child1 : l.child0;
                continue;
            }
            if (mask != 0) {
                next = mask == 1 ? l.child0 : l.child1;
                continue;
            }
        } else if (next != -1) {
            wp_intersect_leaf(&tr, next, tris, prim_ids, &hit, stats);
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

WP_NAMESPACE_END

#endif  // WP_BVH_TRAVERSE_H
