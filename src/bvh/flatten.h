// flatten.h — the host BVH turned into the device layout of kernels/shared/types.h.
//
// The binary SAH tree is collapsed into a WP_BVH_WIDTH-wide BVH (8; 4 is the other
// setting of the switch in types.h) by the SAH-optimal collapse of Ylitie, Karras & Laine
// (HPG 2017): a dynamic program over the binary tree finds, for every subtree and every
// budget of 1..W slots, the cheapest way to spread it over that many slots of a wide node
// (a slot holds one leaf of the subtree's triangles, at most FlattenOptions::max_leaf, or
// one wide node of its own), with FlattenOptions' costs per wide-node visit and per
// triangle test, each weighted by the surface area of the box that leads to it. A greedy
// collapse (open the largest interior child until eight) left 1,261 of the built-in box's
// 2,749 nodes with two children; this one gives 1,431 nodes, 23 of them with two
// (docs/performance.md). Children keep the binary
// tree's left-to-right order. Interior nodes are numbered in depth-first order from the
// root (0). Layout, field by field (kernels/shared/types.h has the authoritative text):
//   nodes[i] (BvhNode, 256 bytes for width 8, 128 for width 4):
//     lo_x, hi_x, lo_y, hi_y, lo_z, hi_z: six WpLanes rows (float8 / float4); lane s is a
//       bound of child slot s's box (world units), widened outward by one ulp and at least
//       2^-64 (flatten.cpp says why: zero direction components with origins on a face).
//       Used slots come first; an unused slot
//       has lo = +FLT_MAX, hi = -FLT_MAX (no ray enters it).
//     child0..child{W-1}: one integer reference per slot: >= 0 an interior node index,
//       < 0 a leaf ~((first << 5) | count) over triangles[first, first + count);
//       -1 in unused slots.
//     pad0..pad{W-1}: 0 (the node fills whole cache lines).
//   links[i] (BvhLinks, 8 bytes): parent (interior node index, -1 at the root) and slot
//     (this node's slot in its parent, 0 at the root), for the stackless climb.
//   triangles (Triangle, 48 bytes): vertices in leaf order, .w lanes 0.
//   prim_ids: leaf order -> original triangle index.
//   depth: levels of the wide tree (<= WP_BVH_MAX_DEPTH = 64, the bitstack's width; the
//     binary builder caps its depth there and collapsing only shortens paths).
// A BVH whose root is a leaf (or that is empty) gets a root node whose slot 0 holds that
// leaf (the empty scene: nothing), so the kernels never special-case it.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "bvh/build.h"
#include "shared/types.h"

namespace wp::bvh {

struct FlatBvh {
    std::vector<BvhNode> nodes;
    std::vector<BvhLinks> links;
    std::vector<TriBlock> triangles;   // the leaves' triangles in blocks of WP_TRI_BLOCK (types.h)
    std::vector<int> prim_ids;         // block * WP_TRI_BLOCK + lane -> original triangle index; -1: padding
    std::size_t triangle_count = 0;    // triangles in the leaves (the blocks' lanes minus padding)
    int depth = 0;                     // interior levels
};

// One box per triangle, for build().
std::vector<Aabb> triangle_boxes(std::span<const glm::vec3> positions, std::span<const glm::uvec3> indices);

// The collapse's SAH costs (relative to each other; measured on PoCL, docs/performance.md,
// seventeenth round: with leaf blocks a leaf costs tri_cost for each of its blocks' four
// lanes, padding included, i.e. 2.0 a block; flat block costs of 0.6, 1.0, 1.25 and 1.5
// traced 1.5-10 % slower on the built-in box).
struct FlattenOptions {
    float node_cost = 1.0f;  // one wide-node visit: WP_BVH_WIDTH box tests together
    float tri_cost = 0.5f;   // one triangle lane of a leaf block (a leaf costs its blocks' lanes)
    int max_leaf = 8;        // triangles in a leaf that merges binary leaves (1..WP_LEAF_MAX_COUNT);
                             // a binary leaf itself is never split
};

FlatBvh flatten(const Bvh& bvh, std::span<const glm::vec3> positions, std::span<const glm::uvec3> indices,
                const FlattenOptions& options = {});

// The BVH of the triangles indices[subset[k]] alone (built and flattened as above), its
// prim_ids naming them by their index in `indices` (the subset's values): the emitters' BVH
// of the last bounce (render::DeviceScene::emitter_bvh).
FlatBvh flatten_subset(std::span<const glm::vec3> positions, std::span<const glm::uvec3> indices,
                       std::span<const int> subset);

// Encodes a leaf reference (types.h); throws wp::Error when first/count do not fit.
int leaf_ref(int first, int count);

}  // namespace wp::bvh
