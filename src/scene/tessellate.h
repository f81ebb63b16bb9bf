// tessellate.h — triangle meshes of the analytic shapes that scene loaders share (Mitsuba 3's
// and pbrt-v4's sphere), in the shape's own space.
#pragma once

#include <vector>

#include <glm/glm.hpp>

namespace wp {

// Vertex positions, triangles (counter-clockwise = front = outward) and optional per-vertex
// shading normals and uvs (wavepath's convention, scene.h TextureRef).
struct TessellatedShape {
    std::vector<glm::vec3> positions;
    std::vector<glm::uvec3> triangles;
    std::vector<glm::vec3> normals;  // empty, or one per position
    std::vector<glm::vec2> uvs;      // empty, or one per position
};

// Subdivisions of the icosphere of tessellated_sphere: 20 * 4^4 = 5,120 triangles.
constexpr int kSphereSubdivisions = 4;

// The unit sphere around the origin: an icosphere of 20 * 4^kSphereSubdivisions triangles
// whose radius is scaled (by about 1.0006) so that its area is exactly 4π (an emitter keeps
// its power), normals p / |p| (the analytic normal). With uvs (u, v) = (φ / 2π, θ / π),
// φ = atan2(y, x) in [0, 2π), θ measured from +z: Mitsuba 3's sphere uvs, and pbrt-v4's
// (u = φ / φmax, v = 1 - θ / π with v up) after wavepath's v -> 1 - v. Vertices on the seam
// and at the poles are split (scene/shape_uv.h), so the triangle count does not change.
TessellatedShape tessellated_sphere(bool with_uvs);

}  // namespace wp
