#include "bvh/flatten.h"

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <limits>

#include "util/error.h"

namespace wp::bvh {

namespace {

constexpr int kEmptyLeaf = -1;  // ~0: first 0, count 0

struct Flattener {
    const Bvh& bvh;
    FlatBvh& out;
    int max_level = 0;

    // Child boxes are widened on every side by one ulp and by at least 2^-64 (never to a
    // denormal: NOTES-pocl.md trap 1), so every point of a triangle lies strictly inside
    // its boxes, at least 2^-65 from each face. Why: the box test reads a zero direction
    // component as 1 / FLT_MIN = 2^126 (bvh_traverse.h), the triangle test as exactly
    // zero. A ray with d.z = 0 whose origin lay exactly on a face plane z = hi of a tight
    // box got (hi - o.z) * 2^126 = 0 as its exit distance and skipped the box although it
    // runs inside the slab (tests/test_hard.cpp: zero directions and origins on box
    // faces). With the margin its exit distance is >= 2^-65 * 2^126 = 2^61 instead.
    static float widen_down(float x) {
        float y = std::min(std::nextafter(x, -FLT_MAX), static_cast<float>(static_cast<double>(x) - 0x1p-64));
        return (y > -FLT_MIN && y < FLT_MIN) ? -FLT_MIN : y;
    }
    static float widen_up(float x) {
        float y = std::max(std::nextafter(x, FLT_MAX), static_cast<float>(static_cast<double>(x) + 0x1p-64));
        return (y > -FLT_MIN && y < FLT_MIN) ? FLT_MIN : y;
    }
    static void set_child(BvhNode& dn, int slot, const Aabb& b, bool widen = true) {
        float* lo[3] = {reinterpret_cast<float*>(&dn.lo_x), reinterpret_cast<float*>(&dn.lo_y),
                        reinterpret_cast<float*>(&dn.lo_z)};
        float* hi[3] = {reinterpret_cast<float*>(&dn.hi_x), reinterpret_cast<float*>(&dn.hi_y),
                        reinterpret_cast<float*>(&dn.hi_z)};
        for (int a = 0; a < 3; ++a) {
            lo[a][slot] = widen ? widen_down(b.lo[a]) : b.lo[a];
            hi[a][slot] = widen ? widen_up(b.hi[a]) : b.hi[a];
        }
    }
    // The inverted box of an unused slot: no ray enters it (types.h).
    static void set_empty_child(BvhNode& dn, int slot) {
        Aabb none;
        none.lo = glm::vec3(FLT_MAX);
        none.hi = glm::vec3(-FLT_MAX);
        set_child(dn, slot, none, false);
    }

    // The collapse plan of one host node (Ylitie, Karras & Laine, "Efficient Incoherent Ray
    // Traversal on GPUs Through Compressed Wide BVHs", HPG 2017, section 4): for every slot
    // budget i = 1..W, the cheapest way to hang the subtree into at most i slots of a wide
    // node, under the SAH with a cost per wide-node visit and per triangle test.
    //   one[i]: the subtree takes one slot (then `leaf` says how: one leaf of all its
    //           triangles, or an interior wide node of its own);
    //   k[i]:   otherwise its left child gets k[i] slots and its right child i - k[i].
    struct Plan {
        std::uint16_t one = 0;  // bit i: the subtree takes one slot when given i
        bool leaf = false;
        std::int8_t k[WP_BVH_WIDTH + 1] = {};
    };
    std::vector<Plan> plan;
    std::vector<int> sub_first, sub_count;  // each host subtree's range of prim_order
    FlattenOptions opt;

    static double area(const Aabb& b) {  // in double: huge scenes would overflow float
        double ex = static_cast<double>(b.hi.x) - b.lo.x, ey = static_cast<double>(b.hi.y) - b.lo.y,
               ez = static_cast<double>(b.hi.z) - b.lo.z;
        return std::max(0.0, ex * ey + ey * ez + ez * ex);
    }

    // A leaf of `count` triangles is tested a block of WP_TRI_BLOCK lanes at a time, so it
    // costs its lanes, padding included: whole blocks fill first.
    double leaf_cost(int count) const {
        return opt.tri_cost * WP_TRI_BLOCK * ((count + WP_TRI_BLOCK - 1) / WP_TRI_BLOCK);
    }
    using Costs = std::array<double, WP_BVH_WIDTH + 1>;  // [i]: at most i slots (i >= 1)

    // Plans the subtree under host node n (post order); returns its costs.
    Costs plan_node(int n) {
        const Node& nd = bvh.nodes[n];
        Plan& pl = plan[n];
        Costs c{};
        const double a = area(nd.box);
        if (nd.leaf()) {
            sub_first[n] = nd.first;
            sub_count[n] = nd.count;
            pl.leaf = true;
            for (int i = 1; i <= WP_BVH_WIDTH; ++i) {
                c[i] = a * leaf_cost(nd.count);
                pl.one |= static_cast<std::uint16_t>(1u << i);
            }
            return c;
        }
        const Costs cl = plan_node(nd.left), cr = plan_node(nd.right);
        sub_first[n] = sub_first[nd.left];
        sub_count[n] = sub_count[nd.left] + sub_count[nd.right];
        Costs dist{};  // [i >= 2]: both children, i slots between them
        for (int i = 2; i <= WP_BVH_WIDTH; ++i) {
            dist[i] = std::numeric_limits<double>::infinity();
            for (int k = 1; k < i; ++k) {
                double v = cl[k] + cr[i - k];
                if (v < dist[i] || k == 1) {
                    dist[i] = v;
                    pl.k[i] = static_cast<std::int8_t>(k);
                }
            }
        }
        const double interior = a * opt.node_cost + dist[WP_BVH_WIDTH];
        double one = interior;
        if (sub_count[n] <= opt.max_leaf) {
            const double leaf = a * leaf_cost(sub_count[n]);
            if (leaf <= interior) {
                one = leaf;
                pl.leaf = true;
            }
        }
        c[1] = one;
        pl.one |= 2u;
        for (int i = 2; i <= WP_BVH_WIDTH; ++i) {
            if (one <= dist[i]) {
                c[i] = one;
                pl.one |= static_cast<std::uint16_t>(1u << i);
            } else {
                c[i] = dist[i];
            }
        }
        return c;
    }

    // The host subtrees that fill the slots of host node n given i slots, left to right.
    void collect(int n, int i, std::vector<int>& out) const {
        const Node& nd = bvh.nodes[n];
        if (nd.leaf() || (plan[n].one >> i) & 1u) {
            out.push_back(n);
            return;
        }
        collect(nd.left, plan[n].k[i], out);
        collect(nd.right, i - plan[n].k[i], out);
    }

    // Emits interior host node `index` as a device node (its subtree spread over the
    // WP_BVH_WIDTH slots as planned); returns its index.
    int emit(int index, int parent, int slot, int level) {
        max_level = std::max(max_level, level);
        int di = static_cast<int>(out.nodes.size());
        out.nodes.push_back({});
        out.links.push_back({parent, slot});
        std::vector<int> kids;
        const Node& nd = bvh.nodes[index];
        collect(nd.left, plan[index].k[WP_BVH_WIDTH], kids);
        collect(nd.right, WP_BVH_WIDTH - plan[index].k[WP_BVH_WIDTH], kids);
        BvhNode dn{};
        for (int s = 0; s < WP_BVH_WIDTH; ++s) {
            if (s < static_cast<int>(kids.size())) set_child(dn, s, bvh.nodes[kids[s]].box);
            else set_empty_child(dn, s);
            (&dn.child0)[s] = kEmptyLeaf;
        }
        out.nodes[di] = dn;
        for (int s = 0; s < static_cast<int>(kids.size()); ++s) {
            const int m = kids[s];
            int ref = plan[m].leaf ? leaf_ref(sub_first[m], sub_count[m]) : emit(m, di, s, level + 1);
            (&out.nodes[di].child0)[s] = ref;
        }
        return di;
    }
};

}  // namespace

int leaf_ref(int first, int count) {
    if (count < 0 || count > WP_LEAF_MAX_COUNT) fail("BVH leaf of {} triangles exceeds {}", count, WP_LEAF_MAX_COUNT);
    if (first < 0 || first >= (1 << (31 - WP_LEAF_COUNT_BITS)))
        fail("BVH leaf start {} exceeds the {}-bit index range", first, 31 - WP_LEAF_COUNT_BITS);
    return ~((first << WP_LEAF_COUNT_BITS) | count);
}

namespace {

// Rewrites every leaf reference from a range of the leaf-ordered triangles `tris` (ids:
// their original indices) to blocks of WP_TRI_BLOCK triangles in SoA rows (types.h), filling
// out.triangles and out.prim_ids (padding lanes: zero vertices, id -1).
void leaves_to_blocks(FlatBvh& out, const std::vector<Triangle>& tris, const std::vector<int>& ids) {
    out.triangles.clear();
    out.prim_ids.clear();
    out.triangle_count = tris.size();
    out.triangles.reserve(tris.size() / 2 + 1);
    out.prim_ids.reserve(tris.size() * 2 + WP_TRI_BLOCK);
    for (BvhNode& nd : out.nodes) {
        for (int s = 0; s < WP_BVH_WIDTH; ++s) {
            int& c = (&nd.child0)[s];
            if (c >= 0) continue;
            const int first = (~c) >> WP_LEAF_COUNT_BITS, count = (~c) & WP_LEAF_MAX_COUNT;
            if (count == 0) {
                c = kEmptyLeaf;
                continue;
            }
            const int b0 = static_cast<int>(out.triangles.size());
            for (int i = 0; i < count; i += WP_TRI_BLOCK) {
                TriBlock blk{};  // zeros: the padding lanes' degenerate triangle
                for (int l = 0; l < WP_TRI_BLOCK; ++l) {
                    if (i + l >= count) {
                        out.prim_ids.push_back(-1);
                        continue;
                    }
                    const Triangle& t = tris[static_cast<std::size_t>(first + i + l)];
                    const float4* v[3] = {&t.v0, &t.v1, &t.v2};
                    for (int k = 0; k < 3; ++k) {
                        reinterpret_cast<float*>(&blk.row[3 * k + 0])[l] = v[k]->x;
                        reinterpret_cast<float*>(&blk.row[3 * k + 1])[l] = v[k]->y;
                        reinterpret_cast<float*>(&blk.row[3 * k + 2])[l] = v[k]->z;
                    }
                    out.prim_ids.push_back(ids[static_cast<std::size_t>(first + i + l)]);
                }
                out.triangles.push_back(blk);
            }
            c = leaf_ref(b0, count);
        }
    }
}

}  // namespace

std::vector<Aabb> triangle_boxes(std::span<const glm::vec3> positions, std::span<const glm::uvec3> indices) {
    std::vector<Aabb> boxes(indices.size());
    for (std::size_t i = 0; i < indices.size(); ++i) {
        for (int k = 0; k < 3; ++k) boxes[i].grow(positions[indices[i][k]]);
    }
    return boxes;
}

FlatBvh flatten(const Bvh& bvh, std::span<const glm::vec3> positions, std::span<const glm::uvec3> indices,
                const FlattenOptions& options) {
    FlatBvh out;
    // Triangles in leaf order (the collapse's leaves are ranges of it); blocks at the end.
    std::vector<Triangle> tris(bvh.prim_order.size());
    std::vector<int> ids(bvh.prim_order.size());
    for (std::size_t i = 0; i < bvh.prim_order.size(); ++i) {
        std::uint32_t p = bvh.prim_order[i];
        const glm::uvec3& t = indices[p];
        auto v = [&](int k) {
            const glm::vec3& q = positions[t[k]];
            return float4{q.x, q.y, q.z, 0.0f};
        };
        tris[i] = {v(0), v(1), v(2)};
        ids[i] = static_cast<int>(p);
    }
    if (options.max_leaf < 1 || options.max_leaf > WP_LEAF_MAX_COUNT)
        fail("BVH flatten: max_leaf {} outside 1..{}", options.max_leaf, WP_LEAF_MAX_COUNT);
    if (!(options.node_cost > 0.0f && options.tri_cost > 0.0f && std::isfinite(options.node_cost) &&
          std::isfinite(options.tri_cost)))
        fail("BVH flatten: costs must be positive and finite (node {}, triangle {})", options.node_cost,
             options.tri_cost);
    Flattener f{bvh, out, 0, {}, {}, {}, options};
    if (bvh.nodes.empty() || bvh.nodes[0].leaf()) {
        // Root leaf (or nothing): one device node holding the leaf in slot 0.
        BvhNode dn{};
        for (int s = 0; s < WP_BVH_WIDTH; ++s) {
            Flattener::set_empty_child(dn, s);
            (&dn.child0)[s] = kEmptyLeaf;
        }
        if (!bvh.nodes.empty()) {
            Flattener::set_child(dn, 0, bvh.nodes[0].box);
            dn.child0 = leaf_ref(bvh.nodes[0].first, bvh.nodes[0].count);
        }
        out.nodes.push_back(dn);
        out.links.push_back({-1, 0});
        out.depth = 1;
        leaves_to_blocks(out, tris, ids);
        return out;
    }
    f.plan.resize(bvh.nodes.size());
    f.sub_first.resize(bvh.nodes.size());
    f.sub_count.resize(bvh.nodes.size());
    f.plan_node(0);
    out.nodes.reserve(bvh.nodes.size() / 3 + 1);
    out.links.reserve(bvh.nodes.size() / 3 + 1);
    f.emit(0, -1, 0, 1);
    out.depth = f.max_level;
    if (out.depth > WP_BVH_MAX_DEPTH) fail("BVH of {} levels exceeds the traversal's {}", out.depth, WP_BVH_MAX_DEPTH);
    leaves_to_blocks(out, tris, ids);
    return out;
}

FlatBvh flatten_subset(std::span<const glm::vec3> positions, std::span<const glm::uvec3> indices,
                       std::span<const int> subset) {
    std::vector<glm::uvec3> tris;
    tris.reserve(subset.size());
    for (int k : subset) tris.push_back(indices[static_cast<std::size_t>(k)]);
    FlatBvh flat = flatten(build(triangle_boxes(positions, tris)), positions, tris);
    for (int& p : flat.prim_ids)
        if (p >= 0) p = subset[static_cast<std::size_t>(p)];  // -1: a block's padding lane
    return flat;
}

}  // namespace wp::bvh
