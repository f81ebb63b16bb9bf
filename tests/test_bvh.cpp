// test_bvh.cpp — BVH invariants on the host tree and on the flattened device layout, for
// ordinary and degenerate input.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>

#include "bvh/build.h"
#include "bvh/flatten.h"
#include "scene/builtin.h"
#include "scene/procedural.h"
#include "support.h"

using namespace wp;

namespace {

struct Case {
    std::string name;
    Mesh mesh;
};

// The meshes every invariant is checked on.
std::vector<Case> cases() {
    std::vector<Case> out;
    out.push_back({"random soup", make_random_soup(3000, 1, {-1, -1, -1}, {1, 1, 1}, 0.3f)});
    out.push_back({"uv sphere (closed)", make_uv_sphere({0.1f, 0.2f, 0.3f}, 1.5f, 40, 60)});
    Scene box = make_cornell_box();
    out.push_back({"cornell box", Mesh{box.positions, box.triangles}});
    Mesh coplanar = make_random_soup(2000, 2, {-1, -1, 0}, {1, 1, 0}, 0.2f);  // all in z = 0
    out.push_back({"all coplanar", coplanar});
    Mesh same;
    same.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    for (int i = 0; i < 1000; ++i) same.triangles.push_back({0, 1, 2});
    out.push_back({"all identical", same});
    Mesh single;
    single.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    single.triangles = {{0, 1, 2}};
    out.push_back({"single triangle", single});
    Mesh zero_area;
    test::Rng rng(3);
    for (int i = 0; i < 500; ++i) {
        glm::vec3 p{rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)};
        glm::vec3 q = p + glm::vec3(rng.uniform(), rng.uniform(), rng.uniform());
        auto base = static_cast<unsigned>(zero_area.positions.size());
        zero_area.positions.insert(zero_area.positions.end(), {p, q, 0.5f * (p + q)});  // collinear
        zero_area.triangles.push_back({base, base + 1, base + 2});
        zero_area.positions.push_back(p);  // a point triangle
        zero_area.triangles.push_back({base + 3, base + 3, base + 3});
    }
    out.push_back({"zero-area triangles", zero_area});
    out.push_back({"empty", Mesh{}});
    return out;
}

Aabb triangle_box(const Mesh& m, std::uint32_t i) {
    Aabb b;
    for (int k = 0; k < 3; ++k) b.grow(m.positions[m.triangles[i][k]]);
    return b;
}

// Reads child `slot` of a device node back into an Aabb.
Aabb child_box(const BvhNode& n, int slot) {
    const float* lo[3] = {reinterpret_cast<const float*>(&n.lo_x), reinterpret_cast<const float*>(&n.lo_y),
                          reinterpret_cast<const float*>(&n.lo_z)};
    const float* hi[3] = {reinterpret_cast<const float*>(&n.hi_x), reinterpret_cast<const float*>(&n.hi_y),
                          reinterpret_cast<const float*>(&n.hi_z)};
    Aabb b;
    for (int a = 0; a < 3; ++a) {
        b.lo[a] = lo[a][slot];
        b.hi[a] = hi[a][slot];
    }
    return b;
}

void check_host_tree(const Mesh& m, const bvh::Bvh& b, const bvh::BuildOptions& opt) {
    std::size_t n = m.triangles.size();
    REQUIRE(b.prim_order.size() == n);
    if (n == 0) {
        CHECK(b.nodes.empty());
        return;
    }
    std::vector<int> seen(n, 0);
    int max_depth = 0;
    std::function<void(int, int)> walk = [&](int i, int depth) {
        const bvh::Node& nd = b.nodes[i];
        if (nd.leaf()) {
            max_depth = std::max(max_depth, depth);
            CHECK(nd.count >= 1);
            CHECK(nd.count <= opt.max_leaf);
            for (int k = nd.first; k < nd.first + nd.count; ++k) {
                std::uint32_t p = b.prim_order[k];
                seen[p] += 1;
                CHECK(nd.box.contains(triangle_box(m, p)));
            }
            return;
        }
        CHECK(nd.box.contains(b.nodes[nd.left].box));
        CHECK(nd.box.contains(b.nodes[nd.right].box));
        walk(nd.left, depth + 1);
        walk(nd.right, depth + 1);
    };
    walk(0, 0);
    for (std::size_t p = 0; p < n; ++p) {
        INFO("triangle " << p);
        REQUIRE(seen[p] == 1);  // every triangle in exactly one leaf
    }
    CHECK(max_depth == b.depth);
    CHECK(b.depth <= opt.max_depth);
}

void check_flat(const Mesh& m, const bvh::FlatBvh& f) {
    std::size_t n = m.triangles.size();
    REQUIRE(f.nodes.size() == f.links.size());
    REQUIRE(!f.nodes.empty());
    REQUIRE(f.triangle_count == n);
    REQUIRE(f.prim_ids.size() == f.triangles.size() * WP_TRI_BLOCK);
    CHECK(f.links[0].parent == -1);
    std::vector<int> covered(n, 0), visited(f.nodes.size(), 0), block_used(f.triangles.size(), 0);
    // Lane l of block b as a triangle's three vertices.
    auto lane = [&](std::size_t b, int l, int vertex) {
        const float4* r = &f.triangles[b].row[3 * vertex];
        return glm::vec3(reinterpret_cast<const float*>(&r[0])[l], reinterpret_cast<const float*>(&r[1])[l],
                         reinterpret_cast<const float*>(&r[2])[l]);
    };
    std::function<void(int, int)> walk = [&](int i, int depth) {
        visited[i] += 1;
        CHECK(depth <= WP_BVH_MAX_DEPTH);
        CHECK(depth <= f.depth);
        const BvhNode& nd = f.nodes[i];
        for (int k = 0; k < WP_BVH_WIDTH; ++k) CHECK((&nd.pad0)[k] == 0);
        const int* refs = &nd.child0;
        bool unused_seen = false;
        int used = 0;
        for (int s = 0; s < WP_BVH_WIDTH; ++s) {
            int c = refs[s];
            Aabb box = child_box(f.nodes[i], s);
            if (c == -1 && (n > 0 || s > 0)) {
                // An unused slot: the inverted box, no used slot after it.
                CHECK(box.lo == glm::vec3(FLT_MAX));
                CHECK(box.hi == glm::vec3(-FLT_MAX));
                unused_seen = true;
                continue;
            }
            CHECK(!unused_seen);
            ++used;
            if (c >= 0) {
                REQUIRE(c < static_cast<int>(f.nodes.size()));
                CHECK(f.links[c].parent == i);  // parent links for the stackless climb
                CHECK(f.links[c].slot == s);
                Aabb inner;
                for (int k = 0; k < WP_BVH_WIDTH; ++k)
                    if ((&f.nodes[c].child0)[k] != -1) inner.grow(child_box(f.nodes[c], k));
                CHECK(box.contains(inner));
                walk(c, depth + 1);
            } else {
                // The leaf's blocks: its triangles in lanes 0..count-1, then padding.
                int first = (~c) >> WP_LEAF_COUNT_BITS, count = (~c) & WP_LEAF_MAX_COUNT;
                const int blocks = (count + WP_TRI_BLOCK - 1) / WP_TRI_BLOCK;
                REQUIRE(first + blocks <= static_cast<int>(f.triangles.size()));
                for (int j = 0; j < blocks * WP_TRI_BLOCK; ++j) {
                    const std::size_t b = static_cast<std::size_t>(first + j / WP_TRI_BLOCK);
                    const int l = j % WP_TRI_BLOCK;
                    if (l == 0) block_used[b] += 1;
                    const int id = f.prim_ids[b * WP_TRI_BLOCK + l];
                    if (j >= count) {  // a padding lane: no triangle, zero vertices
                        CHECK(id == -1);
                        for (int v = 0; v < 3; ++v) CHECK(lane(b, l, v) == glm::vec3(0.0f));
                        continue;
                    }
                    REQUIRE(id >= 0);
                    REQUIRE(id < static_cast<int>(n));
                    covered[static_cast<std::size_t>(id)] += 1;
                    // The lane is the original triangle.
                    const glm::uvec3& o = m.triangles[static_cast<std::size_t>(id)];
                    for (int v = 0; v < 3; ++v) CHECK(lane(b, l, v) == m.positions[o[v]]);
                    Aabb tb = triangle_box(m, id);
                    CHECK(box.contains(tb));
                }
            }
        }
        // Interior nodes are full unless their subtree ran out of interior nodes.
        if (i > 0 || n > WP_LEAF_MAX_COUNT) CHECK(used >= 2);
    };
    walk(0, 1);
    for (std::size_t k = 0; k < n; ++k) REQUIRE(covered[k] == 1);
    for (std::size_t i = 0; i < visited.size(); ++i) REQUIRE(visited[i] == 1);
    for (std::size_t b = 0; b < block_used.size(); ++b) REQUIRE(block_used[b] == 1);  // no block shared or lost
    std::vector<int> ids;
    for (int id : f.prim_ids)
        if (id >= 0) ids.push_back(id);
    std::sort(ids.begin(), ids.end());
    REQUIRE(ids.size() == n);
    for (std::size_t k = 0; k < n; ++k) REQUIRE(ids[k] == static_cast<int>(k));
}

}  // namespace

TEST_CASE("BVH invariants hold on ordinary and degenerate input", "[unit][bvh]") {
    for (const auto& c : cases()) {
        SECTION(c.name) {
            bvh::BuildOptions opt;
            auto boxes = bvh::triangle_boxes(c.mesh.positions, c.mesh.triangles);
            bvh::Bvh b = bvh::build(boxes, opt);
            check_host_tree(c.mesh, b, opt);
            bvh::FlatBvh f = bvh::flatten(b, c.mesh.positions, c.mesh.triangles);
            check_flat(c.mesh, f);
        }
    }
}

TEST_CASE("the builder keeps the depth within a tight cap", "[unit][bvh]") {
    Mesh m = make_random_soup(5000, 9, {-1, -1, -1}, {1, 1, 1}, 0.2f);
    bvh::BuildOptions opt;
    opt.max_depth = 12;  // 5000 / 2^11 < 8 per leaf: reachable only with median splits
    auto boxes = bvh::triangle_boxes(m.positions, m.triangles);
    bvh::Bvh b = bvh::build(boxes, opt);
    check_host_tree(m, b, opt);
    CHECK(b.depth <= 12);
}

TEST_CASE("single-threaded and parallel builds give the same tree", "[unit][bvh]") {
    Mesh m = make_stress_mesh(60000);
    auto boxes = bvh::triangle_boxes(m.positions, m.triangles);
    bvh::BuildOptions one, many;
    one.threads = 1;
    many.threads = 4;
    bvh::Bvh a = bvh::build(boxes, one), b = bvh::build(boxes, many);
    check_host_tree(m, b, many);
    CHECK(a.prim_order == b.prim_order);
    CHECK(bvh::sah_cost(a) == Approx(bvh::sah_cost(b)));
}

TEST_CASE("the SAH tree is much cheaper than a median tree", "[unit][bvh]") {
    // An independent quality check: the SAH cost of the binned-SAH tree against a tree
    // forced to median splits everywhere (max_depth low enough that median starts at once).
    Scene box = make_cornell_box();
    auto boxes = bvh::triangle_boxes(box.positions, box.triangles);
    bvh::BuildOptions sah, median;
    median.max_depth = 24;  // median splits from depth 0 (max_depth - 24)
    double c_sah = bvh::sah_cost(bvh::build(boxes, sah));
    double c_med = bvh::sah_cost(bvh::build(boxes, median));
    INFO("SAH cost " << c_sah << ", median cost " << c_med);
    CHECK(c_sah < 0.8 * c_med);
}

namespace {

// Half the surface area of a box, in double.
double area_d(const Aabb& b) {
    double ex = double(b.hi.x) - b.lo.x, ey = double(b.hi.y) - b.lo.y, ez = double(b.hi.z) - b.lo.z;
    return ex * ey + ey * ez + ez * ex;
}

// The SAH cost of a flattened tree, read off the device layout (child boxes as stored):
// every interior node reached through a box costs node_cost times that box's area, every
// leaf tri_cost times its lanes (its triangle count rounded up to whole blocks of
// WP_TRI_BLOCK) times its box's area; the root is entered always
// (its own area: the union of its children). Relative to nothing: the same scale as the
// collapse's own costs.
// The lanes a leaf of n triangles is tested in: whole blocks.
int lanes(int n) { return (n + WP_TRI_BLOCK - 1) / WP_TRI_BLOCK * WP_TRI_BLOCK; }

double wide_sah(const bvh::FlatBvh& f, const bvh::FlattenOptions& o) {
    std::function<double(int)> node = [&](int i) {
        double c = 0.0;
        for (int s = 0; s < WP_BVH_WIDTH; ++s) {
            int ref = (&f.nodes[i].child0)[s];
            if (ref == -1) continue;
            double a = area_d(child_box(f.nodes[i], s));
            c += ref >= 0 ? a * o.node_cost + node(ref) : a * o.tri_cost * lanes((~ref) & WP_LEAF_MAX_COUNT);
        }
        return c;
    };
    Aabb root;
    for (int s = 0; s < WP_BVH_WIDTH; ++s)
        if ((&f.nodes[0].child0)[s] != -1) root.grow(child_box(f.nodes[0], s));
    return area_d(root) * o.node_cost + node(0);
}

// The cheapest collapse by brute force, a second algorithm: a wide node at binary node n
// may take any frontier of n's subtree (a set of at most W descendants that covers its
// leaves, n itself excluded) as its slots; each slot is the cheaper of one leaf of its
// triangles (when they fit) and a wide node of its own. Frontiers are enumerated as sets,
// not through the collapse's slot budgets.
struct BruteCollapse {
    const bvh::Bvh& b;
    bvh::FlattenOptions o;
    std::vector<double> best_memo;
    std::vector<int> count;

    double area(int n) const { return area_d(b.nodes[n].box); }
    int tris(int n) {
        if (count[n] >= 0) return count[n];
        const bvh::Node& nd = b.nodes[n];
        return count[n] = nd.leaf() ? nd.count : tris(nd.left) + tris(nd.right);
    }
    // Every frontier of n with at most w members ({n} included).
    std::vector<std::vector<int>> frontiers(int n, int w) const {
        std::vector<std::vector<int>> out = {{n}};
        const bvh::Node& nd = b.nodes[n];
        if (nd.leaf() || w < 2) return out;
        for (const auto& l : frontiers(nd.left, w - 1))
            for (const auto& r : frontiers(nd.right, w - 1))
                if (l.size() + r.size() <= static_cast<std::size_t>(w)) {
                    auto u = l;
                    u.insert(u.end(), r.begin(), r.end());
                    out.push_back(u);
                }
        return out;
    }
    double wide(int n) {  // n as a wide node, entered through its box
        double m = std::numeric_limits<double>::infinity();
        for (const auto& fr : frontiers(n, WP_BVH_WIDTH)) {
            if (fr.size() == 1) continue;  // {n} itself
            double s = 0.0;
            for (int k : fr) s += best(k);
            m = std::min(m, s);
        }
        return area(n) * o.node_cost + m;
    }
    double best(int n) {  // n in one slot
        if (!std::isnan(best_memo[n])) return best_memo[n];
        double c = std::numeric_limits<double>::infinity();
        if (b.nodes[n].leaf() || tris(n) <= o.max_leaf) c = area(n) * o.tri_cost * lanes(tris(n));
        if (!b.nodes[n].leaf()) c = std::min(c, wide(n));
        return best_memo[n] = c;
    }
    double root() {
        best_memo.assign(b.nodes.size(), std::numeric_limits<double>::quiet_NaN());
        count.assign(b.nodes.size(), -1);
        return wide(0);
    }
};

}  // namespace

TEST_CASE("the wide BVH is the SAH-cheapest collapse of the binary tree", "[unit][bvh]") {
    // Small trees, so that every frontier can be enumerated; several cost settings, leaf
    // limits and meshes (a soup of varied sizes, a grid of equal triangles, a sphere).
    struct Setting {
        float node, tri;
        int max_leaf;
    };
    const Setting settings[] = {{1.0f, 0.5f, 8}, {1.0f, 0.2f, 8}, {1.0f, 2.0f, 3}, {1.0f, 0.3f, 31}};
    std::vector<std::pair<std::string, Mesh>> meshes = {
        {"soup", make_random_soup(48, 5, {-1, -1, -1}, {1, 1, 1}, 0.4f)},
        {"sphere", make_uv_sphere({0, 0, 0}, 1.0f, 5, 6)},
        {"flat soup", make_random_soup(40, 6, {-1, -1, 0}, {1, 1, 0}, 0.3f)},
    };
    for (const auto& [name, m] : meshes) {
        bvh::BuildOptions bo;
        bo.max_leaf = 2;  // deep binary trees: many ways to collapse them
        bvh::Bvh b = bvh::build(bvh::triangle_boxes(m.positions, m.triangles), bo);
        REQUIRE(!b.nodes[0].leaf());
        for (const auto& s : settings) {
            bvh::FlattenOptions o;
            o.node_cost = s.node;
            o.tri_cost = s.tri;
            o.max_leaf = s.max_leaf;
            bvh::FlatBvh f = bvh::flatten(b, m.positions, m.triangles, o);
            check_flat(m, f);
            BruteCollapse brute{b, o, {}, {}};
            const double want = brute.root(), got = wide_sah(f, o);
            INFO(name << ": node " << s.node << ", triangle " << s.tri << ", leaf " << s.max_leaf
                      << "; flattened " << got << ", brute force " << want);
            // The stored boxes are widened by an ulp: a relative 1e-5 covers that.
            CHECK(got == Approx(want).epsilon(1e-5));
            // Leaves that merge binary leaves respect the limit.
            for (const auto& nd : f.nodes)
                for (int k = 0; k < WP_BVH_WIDTH; ++k) {
                    int ref = (&nd.child0)[k];
                    if (ref < -1) CHECK(((~ref) & WP_LEAF_MAX_COUNT) <= std::max(s.max_leaf, bo.max_leaf));
                }
        }
    }
}

TEST_CASE("flatten refuses collapse costs it cannot use", "[unit][bvh]") {
    Mesh m = make_random_soup(64, 2, {-1, -1, -1}, {1, 1, 1}, 0.3f);
    bvh::Bvh b = bvh::build(bvh::triangle_boxes(m.positions, m.triangles));
    bvh::FlattenOptions o;
    o.max_leaf = 0;
    CHECK_THROWS_WITH(bvh::flatten(b, m.positions, m.triangles, o), Catch::Contains("max_leaf 0"));
    o = {};
    o.max_leaf = WP_LEAF_MAX_COUNT + 1;
    CHECK_THROWS_WITH(bvh::flatten(b, m.positions, m.triangles, o), Catch::Contains("max_leaf"));
    o = {};
    o.tri_cost = std::numeric_limits<float>::quiet_NaN();
    CHECK_THROWS_WITH(bvh::flatten(b, m.positions, m.triangles, o), Catch::Contains("costs must be positive"));
}
