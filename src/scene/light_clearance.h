// light_clearance.h — how far from each light triangle the nearest other surface lies, so
// that shadow segments can stop there instead of at the light (kernels/shared/offset.h,
// wp_shadow_end_clear).
//
// A shadow segment of next-event estimation runs from a receiver to a point y on a light
// triangle L and ends short of L's plane (wp_shadow_tmax). Its last stretch is the
// expensive one: it sits next to L, inside the boxes of L's BVH leaf, and the traversal tests
// L and its neighbours there only to find that the segment stops before them (measured on
// the built-in box: 1.8 of a shadow ray's 2.6 triangle tests, 28 % of the shadow stage).
// The clearance c(L) is the distance from L to the nearest triangle that reaches in front of
// L's plane (the emitting side). Every point of the segment within c(L) of y is then within
// c(L) of L, where every triangle lies in L's plane or behind it; and such a triangle cannot
// be met by a segment that comes from the front and ends before that plane. So the segment
// can end where its distance to y falls below c(L) (less the rounding margins the kernel
// adds) and report the same occlusion: the stretch it no longer traces holds nothing it
// could hit. The kernel cuts only segments that come from the front and end a full offset
// before the plane (wp_shadow_end_clear), where that argument holds.
//
// "In L's plane or behind it": every vertex at most 1e-7 of L's longest edge in front of the
// plane (in double). The kernels' end lies at least ~1.1e-6 of that edge before the plane
// (the triangle's offset share, wp_triangle_offset), ten times farther. A convex emitter (a
// tessellated sphere light, a glowing box) has every other triangle of its own behind each
// of its planes, so its clearance is the gap to the other objects, and its segments stop
// before they enter its part of the BVH; a quad light under a ceiling gets the gap to the
// walls; a concave emitter whose triangles fold towards each other gets 0.
//
// The search is capped at kClearanceCapEdges times L's longest edge, which bounds its cost
// (the neighbourhood it visits): veach-mis' shadow stage, 15,360 sphere-light triangles
// (docs/performance.md, "Twelfth round"), took 0.65 / 0.28 / 0.17 / 0.15 ms per spp with
// caps of 1, 4, 16 and unbounded edges, for 67 / 135 / 142 / 350 ms of one thread at load.
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

// The search radius in longest edges of the light triangle (above).
inline constexpr double kClearanceCapEdges = 16.0;

// Per scene triangle (scene order): the clearance of each triangle in `lights` as a float no
// larger than 0.99 times the double value, capped at kClearanceCapEdges times the triangle's
// longest edge; 0 for every other triangle. `bvh` is a BVH over the scene's triangles
// (bvh::build of triangle_boxes), used to visit only the triangles near each light. Many
// lights are searched on every hardware thread.
std::vector<float> light_clearances(const Scene& scene, const bvh::Bvh& bvh, std::span<const int> lights);

}  // namespace wp
