#include "bvh/flatten.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

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

    // The (up to) four host nodes under interior host node `index`: its two children,
    // then repeatedly the interior one of largest surface area replaced by its children.
    std::vector<int> gather(int index) const {
        const Node& n = bvh.nodes[index];
        std::vector<int> kids = {n.left, n.right};
        while (static_cast<int>(kids.size()) < WP_BVH_WIDTH) {
            int best = -1;
            float best_area = -1.0f;
            for (int k = 0; k < static_cast<int>(kids.size()); ++k) {
                const Node& c = bvh.nodes[kids[k]];
                if (!c.leaf() && c.box.half_area() > best_area) {
                    best_area = c.box.half_area();
                    best = k;
                }
            }
            if (best < 0) break;
            const Node& c = bvh.nodes[kids[best]];
            kids[best] = c.left;
            kids.insert(kids.begin() + best + 1, c.right);
        }
        return kids;
    }

    // Emits interior host node `index` as a device node; returns its index.
    int emit(int index, int parent, int slot, int level) {
        max_level = std::max(max_level, level);
        int di = static_cast<int>(out.nodes.size());
        out.nodes.push_back({});
        out.links.push_back({parent, slot});
        std::vector<int> kids = gather(index);
        BvhNode dn{};
        for (int s = 0; s < WP_BVH_WIDTH; ++s) {
            if (s < static_cast<int>(kids.size())) set_child(dn, s, bvh.nodes[kids[s]].box);
            else set_empty_child(dn, s);
            (&dn.child0)[s] = kEmptyLeaf;
        }
        out.nodes[di] = dn;
        for (int s = 0; s < static_cast<int>(kids.size()); ++s) {
            const Node& c = bvh.nodes[kids[s]];
            int ref = c.leaf() ? leaf_ref(c.first, c.count) : emit(kids[s], di, s, level + 1);
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

std::vector<Aabb> triangle_boxes(std::span<const glm::vec3> positions, std::span<const glm::uvec3> indices) {
    std::vector<Aabb> boxes(indices.size());
    for (std::size_t i = 0; i < indices.size(); ++i) {
        for (int k = 0; k < 3; ++k) boxes[i].grow(positions[indices[i][k]]);
    }
    return boxes;
}

FlatBvh flatten(const Bvh& bvh, std::span<const glm::vec3> positions, std::span<const glm::uvec3> indices) {
    FlatBvh out;
    // Triangles in leaf order, .w lanes 0.
    out.triangles.resize(bvh.prim_order.size());
    out.prim_ids.resize(bvh.prim_order.size());
    for (std::size_t i = 0; i < bvh.prim_order.size(); ++i) {
        std::uint32_t p = bvh.prim_order[i];
        const glm::uvec3& t = indices[p];
        auto v = [&](int k) {
            const glm::vec3& q = positions[t[k]];
            return float4{q.x, q.y, q.z, 0.0f};
        };
        out.triangles[i] = {v(0), v(1), v(2)};
        out.prim_ids[i] = static_cast<int>(p);
    }
    Flattener f{bvh, out};
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
        return out;
    }
    out.nodes.reserve(bvh.nodes.size() / 3 + 1);
    out.links.reserve(bvh.nodes.size() / 3 + 1);
    f.emit(0, -1, 0, 1);
    out.depth = f.max_level;
    if (out.depth > WP_BVH_MAX_DEPTH) fail("BVH of {} levels exceeds the traversal's {}", out.depth, WP_BVH_MAX_DEPTH);
    return out;
}

FlatBvh flatten_subset(std::span<const glm::vec3> positions, std::span<const glm::uvec3> indices,
                       std::span<const int> subset) {
    std::vector<glm::uvec3> tris;
    tris.reserve(subset.size());
    for (int k : subset) tris.push_back(indices[static_cast<std::size_t>(k)]);
    FlatBvh flat = flatten(build(triangle_boxes(positions, tris)), positions, tris);
    for (int& p : flat.prim_ids) p = subset[static_cast<std::size_t>(p)];
    return flat;
}

}  // namespace wp::bvh
