#include "scene/light_pairs.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>

#include <glm/geometric.hpp>

namespace wp {

namespace {

// Union-find over light triangles.
struct Sets {
    std::vector<int> up;
    explicit Sets(std::size_t n) : up(n) { std::iota(up.begin(), up.end(), 0); }
    int find(int a) {
        while (up[a] != a) a = up[a] = up[up[a]];
        return a;
    }
    void join(int a, int b) { up[find(a)] = find(b); }
};

struct LightTri {
    int prim;
    glm::dvec3 centroid, normal;  // normal: unnormalised, cross(b - a, c - a)
    double area;
};

// Pairs the triangles of one emitter (indices into tris); writes mate[k] (index into tris,
// or -1) for both triangles of each pair.
void pair_emitter(const std::vector<LightTri>& tris, const std::vector<int>& members, std::vector<int>& mate) {
    if (members.size() < 2) return;
    glm::dvec3 centre(0.0), lo(INFINITY), hi(-INFINITY);
    double total = 0.0;
    for (int k : members) {
        centre += tris[k].centroid * tris[k].area;
        total += tris[k].area;
        lo = glm::min(lo, tris[k].centroid);
        hi = glm::max(hi, tris[k].centroid);
    }
    centre /= total;
    // A uniform grid of cells about the triangles' spacing on the emitter's surface, as a
    // sorted list of (cell, triangle); the 27 cells around a reflected centroid are searched.
    const double extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 1e-30});
    const double cell = std::max(std::sqrt(total / static_cast<double>(members.size())), extent / 1e6);
    auto coord = [&](double v, double l) {
        return static_cast<std::int64_t>(std::floor((v - l) / cell)) + 2;  // >= 1 inside the box
    };
    auto key = [](std::int64_t x, std::int64_t y, std::int64_t z) -> std::uint64_t {
        if (x < 0 || y < 0 || z < 0 || x >= (1 << 21) || y >= (1 << 21) || z >= (1 << 21)) return ~0ull;
        return (static_cast<std::uint64_t>(x) << 42) | (static_cast<std::uint64_t>(y) << 21) | static_cast<std::uint64_t>(z);
    };
    std::vector<std::pair<std::uint64_t, int>> grid;
    grid.reserve(members.size());
    for (int k : members) {
        const glm::dvec3& c = tris[k].centroid;
        grid.push_back({key(coord(c.x, lo.x), coord(c.y, lo.y), coord(c.z, lo.z)), k});
    }
    std::sort(grid.begin(), grid.end());
    // Occupied cells in an open-addressing table: cell key -> its run [first, last) of grid.
    struct Run {
        std::uint64_t key = ~0ull;
        std::uint32_t first = 0, last = 0;
    };
    std::size_t slots = 16;
    while (slots < 2 * grid.size()) slots <<= 1;
    std::vector<Run> table(slots);
    auto home = [&](std::uint64_t q) { return static_cast<std::size_t>((q * 0x9e3779b97f4a7c15ull) >> 20) & (slots - 1); };
    for (std::size_t i = 0; i < grid.size();) {
        std::size_t e = i;
        while (e < grid.size() && grid[e].first == grid[i].first) ++e;
        std::size_t h = home(grid[i].first);
        while (table[h].key != ~0ull) h = (h + 1) & (slots - 1);
        table[h] = {grid[i].first, static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(e)};
        i = e;
    }
    auto run_of = [&](std::uint64_t q) -> const Run* {
        for (std::size_t h = home(q);; h = (h + 1) & (slots - 1)) {
            if (table[h].key == q) return &table[h];
            if (table[h].key == ~0ull) return nullptr;
        }
    };
    // Candidate pairs: triangles facing opposite ways whose centroids are near each other's
    // reflection; the cost |c_k + c_j - 2 centre|² is the same seen from either. Each
    // triangle keeps its few cheapest; they are matched greedily, cheapest first (ties by
    // index), so a mesh whose halves are not exact mirror images (a UV sphere's diagonals)
    // still pairs nearly every triangle.
    struct Edge {
        double cost;
        int k, j;
        bool operator<(const Edge& o) const {
            return cost != o.cost ? cost < o.cost : k != o.k ? k < o.k : j < o.j;
        }
    };
    constexpr std::size_t kKeep = 4;
    std::vector<Edge> edges, mine;
    edges.reserve(members.size() * 2);
    for (int k : members) {
        const glm::dvec3 target = 2.0 * centre - tris[k].centroid;
        const std::int64_t cx = coord(target.x, lo.x), cy = coord(target.y, lo.y), cz = coord(target.z, lo.z);
        mine.clear();
        for (std::int64_t dz = -1; dz <= 1; ++dz)
            for (std::int64_t dy = -1; dy <= 1; ++dy)
                for (std::int64_t dx = -1; dx <= 1; ++dx) {
                    const std::uint64_t q = key(cx + dx, cy + dy, cz + dz);
                    const Run* run = q == ~0ull ? nullptr : run_of(q);
                    if (run == nullptr) continue;
                    for (std::uint32_t g = run->first; g < run->last; ++g) {
                        const int j = grid[g].second;
                        if (j == k || !(glm::dot(tris[j].normal, tris[k].normal) < 0.0)) continue;
                        const glm::dvec3 e = tris[j].centroid - target;
                        mine.push_back({glm::dot(e, e), std::min(k, j), std::max(k, j)});
                    }
                }
        const std::size_t keep = std::min(kKeep, mine.size());
        std::partial_sort(mine.begin(), mine.begin() + static_cast<std::ptrdiff_t>(keep), mine.end());
        edges.insert(edges.end(), mine.begin(), mine.begin() + static_cast<std::ptrdiff_t>(keep));
    }
    std::sort(edges.begin(), edges.end());
    for (const Edge& e : edges)
        if (mate[e.k] < 0 && mate[e.j] < 0) mate[e.k] = e.j, mate[e.j] = e.k;
}

}  // namespace

LightTriangle light_triangle(const Scene& scene, std::size_t i) {
    if (!scene.triangle_emits(i)) return {};
    const Material& m = scene.materials[scene.material_ids[i]];
    const double ar = scene.triangle_area(i);
    double lum = 0.2126 * m.emission.x + 0.7152 * m.emission.y + 0.0722 * m.emission.z;
    if (!(ar > 0.0 && lum > 0.0 && std::isfinite(ar * lum))) return {};
    return {ar, ar * lum};
}

std::vector<int> find_light_partners(const Scene& scene) {
    std::vector<int> partner(scene.triangles.size(), -1);
    std::vector<LightTri> tris;
    for (std::size_t i = 0; i < scene.triangles.size(); ++i) {
        if (!is_light_triangle(scene, i)) continue;
        const glm::uvec3& t = scene.triangles[i];
        glm::dvec3 a(scene.positions[t.x]), b(scene.positions[t.y]), c(scene.positions[t.z]);
        glm::dvec3 n = glm::cross(b - a, c - a);
        tris.push_back({static_cast<int>(i), (a + b + c) / 3.0, n, 0.5 * glm::length(n)});
    }
    if (tris.size() < 2) return partner;
    // Emitters: light triangles joined through vertices at the same position (meshes split
    // at seams stay one emitter): their corners sorted by position, equal runs joined.
    Sets sets(tris.size());
    std::vector<std::pair<std::array<float, 3>, int>> corners;
    corners.reserve(3 * tris.size());
    for (std::size_t k = 0; k < tris.size(); ++k) {
        const glm::uvec3& t = scene.triangles[tris[k].prim];
        for (unsigned v : {t.x, t.y, t.z}) {
            const glm::vec3 p = scene.positions[v];
            corners.push_back({{p.x, p.y, p.z}, static_cast<int>(k)});
        }
    }
    std::sort(corners.begin(), corners.end());
    for (std::size_t i = 1; i < corners.size(); ++i)
        if (corners[i].first == corners[i - 1].first) sets.join(corners[i].second, corners[i - 1].second);
    std::vector<std::vector<int>> emitters;
    std::vector<int> slot(tris.size(), -1);
    for (std::size_t k = 0; k < tris.size(); ++k) {
        int& e = slot[static_cast<std::size_t>(sets.find(static_cast<int>(k)))];
        if (e < 0) e = static_cast<int>(emitters.size()), emitters.emplace_back();
        emitters[static_cast<std::size_t>(e)].push_back(static_cast<int>(k));
    }
    std::vector<int> mate(tris.size(), -1);
    for (const std::vector<int>& members : emitters) pair_emitter(tris, members, mate);
    for (std::size_t k = 0; k < tris.size(); ++k)
        if (mate[k] >= 0) partner[tris[k].prim] = tris[mate[k]].prim;
    return partner;
}

}  // namespace wp
