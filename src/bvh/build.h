// build.h — binned-SAH BVH builder (host).
//
// Builds a binary BVH over primitive boxes with the surface area heuristic evaluated on
// centroid bins (Wald, "On fast Construction of SAH-based Bounding Volume Hierarchies",
// IRT 2007). Subtrees above a size threshold are built in parallel.
//
// Guarantees, whatever the input (identical, coplanar or zero-area primitives included):
//   * every primitive is in exactly one leaf, leaves hold at most max_leaf primitives;
//   * the number of interior levels is at most max_depth: below depth - 24 (or where the
//     SAH finds no split) the builder splits at the object median, which halves the count.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "bvh/aabb.h"

namespace wp::bvh {

struct BuildOptions {
    int bins = 16;             // SAH bins per axis
    int max_leaf = 8;          // at most this many primitives per leaf (<= WP_LEAF_MAX_COUNT)
    int max_depth = 64;        // interior levels (the stackless traversal's bitstack)
    float traversal_cost = 1.0f;  // SAH cost of one node visit, relative to one primitive test
    int threads = 0;           // 0: std::thread::hardware_concurrency()
};

struct Node {
    Aabb box;
    int left = -1;   // interior: children indices; leaf: -1
    int right = -1;
    int first = 0;   // leaf: range [first, first + count) of Bvh::prim_order
    int count = 0;
    bool leaf() const { return left < 0; }
};

struct Bvh {
    std::vector<Node> nodes;                 // nodes[0] is the root (absent for 0 primitives)
    std::vector<std::uint32_t> prim_order;   // leaf order -> original primitive index
    int depth = 0;                           // interior levels on the longest path
    double build_ms = 0.0;
};

Bvh build(std::span<const Aabb> prim_boxes, const BuildOptions& options = {});

// SAH cost of a built BVH (traversal_cost per interior node, 1 per primitive test),
// normalised by the root area: a quality figure for reports and tests.
double sah_cost(const Bvh& bvh, float traversal_cost = 1.0f);

}  // namespace wp::bvh
