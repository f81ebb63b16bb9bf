#include "scene/procedural.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <unordered_map>
#include <utility>

#include "util/error.h"
#include "util/splitmix.h"

namespace wp {

namespace {

constexpr float kPi = std::numbers::pi_v<float>;

// Appends the two triangles of the grid cell whose corners are a (s, t), b (s+1, t),
// c (s+1, t+1), d (s, t+1): counter-clockwise around cross(u, v).
void push_cell(std::vector<glm::uvec3>& tris, std::uint32_t a, std::uint32_t b, std::uint32_t c,
               std::uint32_t d) {
    tris.emplace_back(a, b, c);
    tris.emplace_back(a, c, d);
}

} // namespace

Mesh make_quad(glm::vec3 corner, glm::vec3 edge_u, glm::vec3 edge_v, int nu, int nv) {
    if (nu < 1 || nv < 1) fail("make_quad: need at least 1 x 1 cells, got {} x {}", nu, nv);
    Mesh m;
    m.positions.reserve(std::size_t(nu + 1) * std::size_t(nv + 1));
    // Vertices row by row (t outer, s inner)
    for (int j = 0; j <= nv; ++j)
        for (int i = 0; i <= nu; ++i)
            m.positions.push_back(corner + edge_u * (float(i) / float(nu)) +
                                  edge_v * (float(j) / float(nv)));
    // Two triangles per cell
    auto id = [&](int i, int j) { return std::uint32_t(j * (nu + 1) + i); };
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i)
            push_cell(m.triangles, id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
    return m;
}

Mesh make_box(glm::vec3 lo, glm::vec3 hi, int n) {
    if (n < 1) fail("make_box: need at least 1 cell per face, got {}", n);
    if (!glm::all(glm::lessThan(lo, hi))) fail("make_box: lo must be below hi on every axis");
    Mesh m;
    // Vertices are the surface points of the (n+1)^3 lattice; one id per lattice point, so
    // faces that meet at an edge use the very same vertices (welded by construction).
    const int s = n + 1;
    std::vector<std::uint32_t> id(std::size_t(s) * s * s, ~0u);
    auto vertex = [&](int i, int j, int k) {
        std::uint32_t& v = id[(std::size_t(k) * s + j) * s + i];
        if (v == ~0u) {
            v = std::uint32_t(m.positions.size());
            glm::vec3 f(float(i) / float(n), float(j) / float(n), float(k) / float(n));
            glm::vec3 p = lo + (hi - lo) * f;
            // Exact faces: the last lattice point is hi itself, not lo + (hi - lo) * 1
            for (int a = 0; a < 3; ++a) {
                int c = a == 0 ? i : a == 1 ? j : k;
                if (c == n) p[a] = hi[a];
            }
            m.positions.push_back(p);
        }
        return v;
    };
    // Each face: the fixed axis a at side c, grid axes (u, v) with cross(e_u, e_v) outward.
    // cross(y, z) = +x, cross(z, x) = +y, cross(x, y) = +z; swapping u and v turns it inward.
    for (int a = 0; a < 3; ++a) {
        for (int side = 0; side < 2; ++side) {
            int u = (a + 1) % 3, v = (a + 2) % 3;
            if (side == 0) std::swap(u, v); // the lo face looks down the axis
            int c = side == 0 ? 0 : n;
            auto at = [&](int su, int sv) {
                int ijk[3];
                ijk[a] = c;
                ijk[u] = su;
                ijk[v] = sv;
                return vertex(ijk[0], ijk[1], ijk[2]);
            };
            for (int sv = 0; sv < n; ++sv)
                for (int su = 0; su < n; ++su)
                    push_cell(m.triangles, at(su, sv), at(su + 1, sv), at(su + 1, sv + 1),
                              at(su, sv + 1));
        }
    }
    return m;
}

Mesh make_uv_sphere(glm::vec3 center, float radius, int rings, int segments) {
    if (rings < 2 || segments < 3)
        fail("make_uv_sphere: need rings >= 2 and segments >= 3, got {} and {}", rings, segments);
    Mesh m;
    // Vertices: north pole, (rings - 1) latitude circles, south pole
    m.positions.push_back(center + glm::vec3(0.0f, radius, 0.0f));
    for (int r = 1; r < rings; ++r) {
        float theta = kPi * float(r) / float(rings);
        float y = std::cos(theta), sr = std::sin(theta);
        for (int s = 0; s < segments; ++s) {
            float phi = 2.0f * kPi * float(s) / float(segments);
            m.positions.push_back(center +
                                  radius * glm::vec3(sr * std::sin(phi), y, sr * std::cos(phi)));
        }
    }
    const auto south = std::uint32_t(m.positions.size());
    m.positions.push_back(center - glm::vec3(0.0f, radius, 0.0f));
    auto id = [&](int r, int s) { return std::uint32_t(1 + (r - 1) * segments + s % segments); };
    // Caps: fans around the poles. phi grows towards +x from +z, so going around with
    // increasing s is counter-clockwise seen from above (+y).
    for (int s = 0; s < segments; ++s) {
        m.triangles.emplace_back(0u, id(1, s), id(1, s + 1));
        m.triangles.emplace_back(south, id(rings - 1, s + 1), id(rings - 1, s));
    }
    // Bands between consecutive latitude circles
    for (int r = 1; r < rings - 1; ++r)
        for (int s = 0; s < segments; ++s)
            push_cell(m.triangles, id(r, s), id(r + 1, s), id(r + 1, s + 1), id(r, s + 1));
    return m;
}

Mesh make_icosphere(glm::vec3 center, float radius, int subdivisions) {
    if (subdivisions < 0 || subdivisions > 10)
        fail("make_icosphere: subdivisions must be in [0, 10], got {}", subdivisions);
    // Unit icosahedron: the 12 vertices (0, ±1, ±g), (±1, ±g, 0), (±g, 0, ±1)
    const float g = (1.0f + std::sqrt(5.0f)) / 2.0f;
    std::vector<glm::vec3> pos = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0},
                                  {0, -1, g}, {0, 1, g}, {0, -1, -g}, {0, 1, -g},
                                  {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
    for (auto& p : pos)
        p = glm::normalize(p);
    std::vector<glm::uvec3> tris = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                    {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                    {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                    {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    // Subdivide: one new vertex per edge, shared by the two triangles of that edge
    for (int level = 0; level < subdivisions; ++level) {
        std::unordered_map<std::uint64_t, std::uint32_t> midpoint;
        auto mid = [&](std::uint32_t a, std::uint32_t b) {
            std::uint64_t key = (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
            auto [it, fresh] = midpoint.try_emplace(key, std::uint32_t(pos.size()));
            if (fresh) pos.push_back(glm::normalize(pos[a] + pos[b]));
            return it->second;
        };
        std::vector<glm::uvec3> next;
        next.reserve(tris.size() * 4);
        for (const auto& t : tris) {
            std::uint32_t ab = mid(t.x, t.y), bc = mid(t.y, t.z), ca = mid(t.z, t.x);
            next.emplace_back(t.x, ab, ca);
            next.emplace_back(t.y, bc, ab);
            next.emplace_back(t.z, ca, bc);
            next.emplace_back(ab, bc, ca);
        }
        tris = std::move(next);
    }
    Mesh m;
    m.positions.reserve(pos.size());
    for (const auto& p : pos)
        m.positions.push_back(center + radius * p);
    m.triangles = std::move(tris);
    return m;
}

std::vector<glm::vec3> sphere_normals(const std::vector<glm::vec3>& positions, glm::vec3 center) {
    std::vector<glm::vec3> normals;
    normals.reserve(positions.size());
    for (const auto& p : positions) {
        const glm::dvec3 d = glm::dvec3(p) - glm::dvec3(center);
        const double len = glm::length(d);
        normals.push_back(len > 0.0 ? glm::vec3(d / len) : glm::vec3(0.0f));
    }
    return normals;
}

Mesh make_random_soup(std::size_t n, std::uint64_t seed, glm::vec3 lo, glm::vec3 hi,
                      float max_edge) {
    if (!glm::all(glm::lessThanEqual(lo, hi))) fail("make_random_soup: lo must not exceed hi");
    if (!(max_edge > 0.0f)) fail("make_random_soup: max_edge must be positive");
    SplitMix64 rng(seed);
    auto in_box = [&](glm::vec3 a, glm::vec3 b) {
        return glm::vec3(a.x + (b.x - a.x) * rng.uniform(), a.y + (b.y - a.y) * rng.uniform(),
                         a.z + (b.z - a.z) * rng.uniform());
    };
    Mesh m;
    m.positions.reserve(3 * n);
    m.triangles.reserve(n);
    const float r = 0.5f * max_edge;
    for (std::size_t i = 0; i < n; ++i) {
        // A centre in the box, three vertices in the ball of radius max_edge / 2 around it
        // (so every edge is at most max_edge), clamped into the box (clamping to a convex
        // set never lengthens an edge).
        glm::vec3 c = in_box(lo, hi);
        for (int k = 0; k < 3; ++k) {
            glm::vec3 d;
            do {
                d = in_box(glm::vec3(-1.0f), glm::vec3(1.0f));
            } while (glm::dot(d, d) > 1.0f);
            m.positions.push_back(glm::clamp(c + r * 0.999f * d, lo, hi));
        }
        auto b = std::uint32_t(3 * i);
        m.triangles.emplace_back(b, b + 1, b + 2);
    }
    return m;
}

Mesh make_stress_mesh(std::size_t target_triangles) {
    // Grid of nu (along the knot) x nv (around the tube) cells, 2 triangles each, closed in
    // both directions; nu = 8 nv keeps the cells roughly square.
    const double cells = double(std::max<std::size_t>(target_triangles, 2 * 8 * 3)) / 2.0;
    const int nv = std::max(3, int(std::lround(std::sqrt(cells / 8.0))));
    const int nu = std::max(3, int(std::lround(cells / nv)));
    const float p = 2.0f, q = 3.0f, tube = 0.35f;
    Mesh m;
    m.positions.reserve(std::size_t(nu) * nv);
    for (int i = 0; i < nu; ++i) {
        // Centre line of the (2, 3) torus knot and its analytic tangent
        float phi = 2.0f * kPi * float(i) / float(nu);
        float r = 2.0f + std::cos(q * phi);
        glm::vec3 c(r * std::cos(p * phi), r * std::sin(p * phi), -std::sin(q * phi));
        glm::vec3 dr(-q * std::sin(q * phi) * std::cos(p * phi) - p * r * std::sin(p * phi),
                     -q * std::sin(q * phi) * std::sin(p * phi) + p * r * std::cos(p * phi),
                     -q * std::cos(q * phi));
        // Periodic frame: the tangent is never parallel to z (its xy part is >= p in length)
        glm::vec3 t = glm::normalize(dr);
        glm::vec3 nrm = glm::normalize(glm::cross(t, glm::vec3(0.0f, 0.0f, 1.0f)));
        glm::vec3 bin = glm::cross(t, nrm);
        for (int j = 0; j < nv; ++j) {
            // Bumps: +-15% of the tube radius, so triangle sizes and boxes vary
            float theta = 2.0f * kPi * float(j) / float(nv);
            float rad = tube * (1.0f + 0.15f * std::sin(7.0f * theta) * std::sin(37.0f * phi));
            m.positions.push_back(c + rad * (std::cos(theta) * nrm + std::sin(theta) * bin));
        }
    }
    // Cells: (nrm, bin, t) is right-handed, so theta turns counter-clockwise around t and
    // the cell (i, j) -> (i, j+1) -> (i+1, j+1) faces outward.
    auto id = [&](int i, int j) { return std::uint32_t((i % nu) * nv + (j % nv)); };
    m.triangles.reserve(2 * std::size_t(nu) * nv);
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j)
            push_cell(m.triangles, id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i + 1, j));
    return m;
}

Mesh transform(const Mesh& mesh, const glm::mat4& m) {
    Mesh out;
    out.positions.reserve(mesh.positions.size());
    for (const auto& p : mesh.positions) {
        glm::vec4 h = m * glm::vec4(p, 1.0f);
        out.positions.push_back(glm::vec3(h) / h.w);
    }
    out.triangles = mesh.triangles;
    if (glm::determinant(glm::mat3(m)) < 0.0f) flip_winding(out);
    return out;
}

void append(Mesh& dst, const Mesh& src) {
    auto base = std::uint32_t(dst.positions.size());
    dst.positions.insert(dst.positions.end(), src.positions.begin(), src.positions.end());
    dst.triangles.reserve(dst.triangles.size() + src.triangles.size());
    for (const auto& t : src.triangles)
        dst.triangles.push_back(t + glm::uvec3(base));
}

void flip_winding(Mesh& mesh) {
    for (auto& t : mesh.triangles)
        std::swap(t.y, t.z);
}

} // namespace wp
