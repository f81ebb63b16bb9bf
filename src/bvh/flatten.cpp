#include "bvh/flatten.h"

#include <cfloat>

#include "util/error.h"

namespace wp::bvh {

namespace {

constexpr int kEmptyLeaf = -1;  // ~0: first 0, count 0

struct Flattener {
    const Bvh& bvh;
    FlatBvh& out;

    void set_child(BvhNode& dn, int slot, const Aabb& b) {
        float* rows[3] = {&dn.x.x, &dn.y.x, &dn.z.x};
        for (int a = 0; a < 3; ++a) {
            rows[a][slot] = b.lo[a];
            rows[a][slot + 2] = b.hi[a];
        }
    }
    void set_empty_child(BvhNode& dn, int slot) {
        Aabb far;
        far.lo = far.hi = glm::vec3(FLT_MAX);
        set_child(dn, slot, far);
    }

    int child_ref(int host_index, int parent) {
        const Node& n = bvh.nodes[host_index];
        if (n.leaf()) return leaf_ref(n.first, n.count);
        return emit(host_index, parent);
    }

    // Emits the interior host node as a device node; returns its index.
    int emit(int host_index, int parent) {
        int index = static_cast<int>(out.nodes.size());
        out.nodes.push_back({});
        out.links.push_back({-1, -1, parent, 0});
        const Node& n = bvh.nodes[host_index];
        const Node& l = bvh.nodes[n.left];
        const Node& r = bvh.nodes[n.right];
        BvhNode dn{};
        set_child(dn, 0, l.box);
        set_child(dn, 1, r.box);
        out.nodes[index] = dn;
        int c0 = child_ref(n.left, index);
        int c1 = child_ref(n.right, index);
        out.links[index].child0 = c0;
        out.links[index].child1 = c1;
        return index;
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
        // Root leaf (or nothing): one device node with the leaf and the empty leaf.
        BvhNode dn{};
        int ref = kEmptyLeaf;
        if (!bvh.nodes.empty()) {
            f.set_child(dn, 0, bvh.nodes[0].box);
            ref = leaf_ref(bvh.nodes[0].first, bvh.nodes[0].count);
        } else {
            f.set_empty_child(dn, 0);
        }
        f.set_empty_child(dn, 1);
        out.nodes.push_back(dn);
        out.links.push_back({ref, kEmptyLeaf, -1, 0});
        out.depth = 1;
        return out;
    }
    out.nodes.reserve(bvh.nodes.size() / 2 + 1);
    out.links.reserve(bvh.nodes.size() / 2 + 1);
    f.emit(0, -1);
    out.depth = bvh.depth;
    return out;
}

}  // namespace wp::bvh
