// normals.h — shading normals and tangents computed on the host, for meshes that lack them.
//
// smooth_normals gives triangles without shading normals angle-weighted vertex normals
// (Thürmer & Wüthrich 1998) with a crease angle; corner_tangents gives every triangle
// corner a MikkTSpace-compatible tangent (Mikkelsen 2008) for normal maps. Loaders call
// them (a format without normals where the user asks for smooth shading; glTF without
// TANGENT); nothing here knows about OpenCL.
#pragma once

#include <cstddef>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace wp {

// Gives the triangles [first_triangle, end) that have no shading normals (scene.normals
// empty, or all three of the triangle's vertex normals zero) unit vertex normals: the sum
// of the face normals around the vertex, each weighted by the face's angle at the vertex
// (Thürmer & Wüthrich 1998), so the result does not depend on how faces are triangulated.
//
// Smoothing groups: two faces meeting at a vertex smooth together when a chain of faces
// around that vertex joins them, each consecutive pair sharing an edge (vertices compared by
// position, so vertices split at uv seams still smooth together) across which their
// normals differ by at most crease_deg. Where a vertex (by index) ends up in several groups
// it is split: new positions are appended (copying uv and tangent where present) and the
// triangles re-indexed, so hard edges stay hard. A vertex also used by triangles outside
// the set keeps its own (zero) normal and the set gets a copy. crease_deg >= 180 smooths
// everything: every shared edge joins and so does every pair of faces sharing a vertex
// index (Mitsuba 3's recompute_vertex_normals for meshes without normals).
// Degenerate faces (zero area, non-finite) contribute nothing and take the normal of a
// group at their vertex; a vertex with only degenerate faces, or whose faces cancel out
// (a sheet folded flat), keeps a zero normal (it shades flat). Afterwards scene.normals has
// one entry per position (zeros outside the set); when nothing got a non-zero normal the
// scene is left unchanged. O(n log n) in the number of triangles.
// Throws wp::Error for a crease angle that is negative or NaN, a vertex index out of range
// or an attribute of the wrong size.
void smooth_normals(Scene& scene, float crease_deg, std::size_t first_triangle = 0);

// A tangent per triangle corner, 3 per triangle in scene order, for tangent-space normal
// maps: xyz the unit tangent (direction of +u), w = ±1 with the bitangent b = w · cross(n, t)
// (scene.h), where n is the corner's shading normal (normalised scene.normals when the
// triangle has all three, else the triangle's geometric normal). b points to the image's
// top, -dP/dv in wavepath's v-down uvs: glTF's and MikkTSpace's convention for normal maps
// (green = +Y = up), so tangents baked by Blender/MikkTSpace and exported to glTF agree with
// these. Where scene.tangents has a non-zero tangent at the vertex it is used as given
// (w reduced to its sign).
//
// Computed as MikkTSpace does (Mikkelsen 2008, mikktspace.c): per face the uv derivative
// direction dP/du (times the sign of the uv area in v-up coordinates, that sign giving w);
// per corner it is projected onto the plane of n and summed with the corner's angle (of the
// edges projected onto that plane) as weight over every corner of the same vertex and the
// same sign; the sum is normalised (Gram-Schmidt against n). Vertices are identified as
// MikkTSpace does: by equal position, normal and uv, not by index.
// Where this differs from mikktspace.c (same results on manifold meshes with
// well-conditioned uvs, up to float rounding; this works in double):
//   - mikktspace.c groups a vertex's faces of one sign by edge adjacency around the vertex
//     (Build4RuleGroups); here all faces of the vertex with that sign form one group, so
//     two same-sign fans that touch only at a vertex share a tangent;
//   - faces with degenerate uvs (zero uv area) or zero area take the tangent and sign of a
//     group at the same vertex (the + sign first) instead of a neighbour's by adjacency;
//     with none there, or when a group's sum cancels, any unit tangent orthogonal to n and
//     w = 1 (mikktspace.c leaves a zero or arbitrary vector);
//   - quads: mikktspace.c can take quads and splits them itself; here triangles only, so a
//     quad baked with another diagonal differs slightly inside that quad;
//   - no angular threshold option (mikktspace.c's default, 180 degrees, never splits).
// Every computed tangent is finite and unit, orthogonal to n (to float rounding).
// Throws wp::Error for a vertex index out of range or an attribute of the wrong size.
std::vector<glm::vec4> corner_tangents(const Scene& scene);

}  // namespace wp
