// shape_uv.h — texture coordinates for the round shapes the scene loaders tessellate.
//
// A sphere's (or any closed surface's) u goes once around an axis and wraps from 1 back to
// 0, and on the axis itself (the poles) u is undefined: per-vertex uvs interpolated across
// a triangle would smear the whole texture over the triangles at the wrap and the poles.
// wrap_uvs gives those triangles copies of their vertices with uvs that interpolate right.
#pragma once

#include <functional>
#include <vector>

#include <glm/glm.hpp>

namespace wp {

// Fills `uvs` (one per vertex, new vertices included) from uv_of(position), u in [0, 1).
// A triangle whose u span exceeds 1/2 crosses the wrap: its vertices with u < 1/2 are
// replaced by copies with u + 1 (the same texels under repeat wrapping). A vertex on the
// axis (on_axis(position)) gets a copy per triangle with the mean u of the triangle's other
// vertices and its own v. Copies keep the position and, when `normals` is not empty, the
// normal, so the surface is unchanged; triangles keep their order and winding.
void wrap_uvs(std::vector<glm::vec3>& positions, std::vector<glm::uvec3>& triangles,
              std::vector<glm::vec3>& normals, std::vector<glm::vec2>& uvs,
              const std::function<glm::vec2(glm::vec3)>& uv_of,
              const std::function<bool(glm::vec3)>& on_axis);

}  // namespace wp
