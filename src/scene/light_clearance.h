// light_clearance.h — how far from each light triangle the nearest other surface lies, so
// that shadow segments can stop there instead of at the light (kernels/shared/offset.h,
// wp_shadow_end_clear).
//
// A shadow segment of next-event estimation runs from a receiver to a point y on a light
// triangle L and ends short of L's plane (wp_shadow_tmax). Its last stretch is the
// expensive one: it sits next to L, inside the boxes of L's BVH leaf, and the traversal tests
// L and its neighbours there only to find that the segment stops before them (measured on
// the built-in box: 1.8 of a shadow ray's 2.6 triangle tests, 28 % of the shadow stage).
// The clearance c(L) is the distance from L to the nearest triangle that does not lie in L's
// plane. Every point of the segment within c(L) of y is then within c(L) of L, where no
// such triangle is; and a triangle in L's plane cannot be met by a segment that ends before
// that plane on the receiver's side. So the segment can end where its distance to y falls
// below c(L) (less the rounding margins the kernel adds) and report the same occlusion: the
// stretch it no longer traces holds nothing it could hit.
//
// "In L's plane": every vertex within 1e-7 of L's longest edge of the plane (in double).
// The kernels' end lies at least ~1.1e-6 of that edge before the plane (the triangle's
// offset share, wp_triangle_offset), ten times farther. A curved emitter (a tessellated
// sphere light) touches neighbours that are not in its triangles' planes: its clearance is
// 0 and its segments are unchanged; a quad light under a ceiling gets the gap to the ceiling.
#pragma once

#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "bvh/build.h"
#include "scene/scene.h"

namespace wp {

// The distance between triangles a and b (double): 0 where they touch or cross. The
// minimum over the candidate closest pairs (each vertex against the other triangle, each
// pair of edges, each edge's crossing of the other's plane), each the distance of two
// actual points of the triangles, so rounding aside it is neither above nor below the true
// distance. Degenerate triangles (segments, points) are measured as their edges.
double triangle_distance(const glm::dvec3 a[3], const glm::dvec3 b[3]);

// Per scene triangle (scene order): the clearance of each triangle in `lights` as a float no
// larger than 0.99 times the double value, capped at the triangle's longest edge; 0 for
// every other triangle. `bvh` is a BVH over the scene's triangles (bvh::build of
// triangle_boxes), used to visit only the triangles near each light.
std::vector<float> light_clearances(const Scene& scene, const bvh::Bvh& bvh, std::span<const int> lights);

}  // namespace wp
