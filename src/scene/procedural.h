// procedural.h — triangle meshes made in code: quads, boxes, spheres, random soups and the
// BVH benchmark's stress mesh.
//
// A Mesh is an indexed triangle list. Every closed generator (box, spheres, stress mesh)
// shares its vertices, so the mesh is watertight: each undirected edge is used by exactly
// two triangles, once in each direction. Counter-clockwise winding (seen from outside)
// gives the outward normal. Generators are deterministic: the random ones use their own
// small generator (splitmix64), never std distributions, so a seed gives the same mesh on
// every standard library. Add a mesh to a Scene with Scene::add_mesh.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace wp {

struct Mesh {
    std::vector<glm::vec3> positions;  // vertex positions (world units)
    std::vector<glm::uvec3> triangles; // vertex indices, counter-clockwise = outward
};

// A planar grid of nu x nv cells (2 triangles each) spanning corner + s*edge_u + t*edge_v,
// s, t in [0, 1]; its normal is cross(edge_u, edge_v). Open (it has a border).
Mesh make_quad(glm::vec3 corner, glm::vec3 edge_u, glm::vec3 edge_v, int nu = 1, int nv = 1);

// The closed axis-aligned box [lo, hi], each face an n x n grid, shared edges welded.
// 12 n^2 triangles, 6 n^2 + 2 vertices.
Mesh make_box(glm::vec3 lo, glm::vec3 hi, int n = 1);

// A latitude/longitude sphere: `rings` bands from pole to pole (>= 2), `segments` around
// (>= 3); poles are single vertices. 2 * segments * (rings - 1) triangles.
Mesh make_uv_sphere(glm::vec3 center, float radius, int rings, int segments);

// The exact normals of a tessellated sphere around `center`: (p - center) / |p - center|
// per position (computed in double; zero at the centre itself), for Scene::add_mesh's
// normals argument, so the sphere shades smooth (its vertices lie on the sphere, so this is
// the analytic normal there).
std::vector<glm::vec3> sphere_normals(const std::vector<glm::vec3>& positions, glm::vec3 center);

// An icosahedron whose triangles are split in four `subdivisions` times, vertices pushed
// onto the sphere. 20 * 4^subdivisions triangles.
Mesh make_icosphere(glm::vec3 center, float radius, int subdivisions);

// n independent triangles (no shared vertices), each with vertices inside [lo, hi] and
// every edge at most max_edge long. Deterministic for a seed.
Mesh make_random_soup(std::size_t n, std::uint64_t seed, glm::vec3 lo, glm::vec3 hi,
                      float max_edge);

// The BVH-build benchmark object: a bumpy tube around a (2, 3) torus knot, closed and
// deterministic, with about target_triangles triangles (exactly 250,000 for 250,000).
// Fits in [-3.5, 3.5] x [-3.5, 3.5] x [-1.5, 1.5].
Mesh make_stress_mesh(std::size_t target_triangles = 250000);

// The mesh with every position transformed as a point by m. A transform that mirrors
// (negative determinant) also reverses the winding, so outward stays outward.
Mesh transform(const Mesh& mesh, const glm::mat4& m);

// Appends src to dst, offsetting its vertex indices.
void append(Mesh& dst, const Mesh& src);

// Reverses the winding of every triangle (outward becomes inward).
void flip_winding(Mesh& mesh);

} // namespace wp
