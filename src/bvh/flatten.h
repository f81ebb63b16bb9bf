// flatten.h — the host BVH turned into the device layout of kernels/shared/types.h.
//
// Interior nodes are numbered in depth-first order from the root (0). Each device node
// holds the boxes of its two children (BvhNode) and their references, plus the parent
// link for the stackless traversal (BvhLinks). Triangles are copied in leaf order
// (Triangle, .w lanes 0) with prim_ids mapping each back to its original index.
// A BVH whose root is a leaf (or that is empty) gets a root node whose second child is the
// empty leaf, so the kernels never special-case it.
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
    std::vector<Triangle> triangles;   // leaf order
    std::vector<int> prim_ids;         // leaf order -> original triangle index
    int depth = 0;                     // interior levels
};

// One box per triangle, for build().
std::vector<Aabb> triangle_boxes(std::span<const glm::vec3> positions, std::span<const glm::uvec3> indices);

FlatBvh flatten(const Bvh& bvh, std::span<const glm::vec3> positions, std::span<const glm::uvec3> indices);

// Encodes a leaf reference (types.h); throws wp::Error when first/count do not fit.
int leaf_ref(int first, int count);

}  // namespace wp::bvh
