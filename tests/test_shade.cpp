// test_shade.cpp — the shade stage alone, on hand-built hits.
//
// Emission, throughput, pushed rays and the queue compaction are checked against values
// worked out by hand; the diffuse and glossy direction densities by χ² goodness-of-fit
// tests (1e6 directions drawn by shade_surface itself, bins with < 5 expected merged,
// α = 0.01), whose expected bin probabilities come from numerical integration of the
// stated densities written here from scratch (pbrt-v4's bsdfs_test.cpp does the same).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <map>
#include <string>
#include <numeric>
#include <random>
#include <vector>

#include <glm/glm.hpp>

#include "render/stages/shade.h"
#include "scene/upload.h"
#include "shared/types.h"
#include "chi2.h"
#include "support.h"

using namespace wp;
using test::bin_of;
using test::bin_probabilities;
using test::chi2_pvalue;

namespace {

struct ShadeCase {
    std::vector<Ray> rays;
    std::vector<PathState> paths;
    std::vector<Hit> hits;
    std::vector<Triangle> tris;
    std::vector<int> material_ids;
    std::vector<MaterialData> materials;
    float4 background{0, 0, 0, 0};
    cl_uint seed = 1, sample = 0;
    int bounce = 0, max_depth = 5;
    int pixels = 0;  // radiance buffer size (> every path's item)
    // The original estimator (uniform hemisphere, Phong, pcg4d numbers, no roulette, no
    // NEE) with every material kind, unless a test says otherwise.
    render::KernelConfig config = [] {
        render::KernelConfig k;
        k.estimator = render::Estimator::original();
        return k;
    }();
    // The light table (with NEE): cdf, triangles, per-triangle area density.
    std::vector<float> light_cdf;
    std::vector<int> light_prims;
    std::vector<float> light_pdf_area;
    // Back-to-back light pairs per triangle (configs with light_pairs on); empty: none uploaded.
    std::vector<LightPair> light_pairs;
    // Per-triangle shading normals (configs with normals on); empty: none uploaded.
    std::vector<TriNormals> normals;
    // The material tables (MaterialData.table: rough plastics); empty: none uploaded.
    std::vector<float> tables;
};

struct ShadeOut {
    std::vector<float4> radiance;
    std::vector<Ray> rays;
    std::vector<PathState> paths;
    int count = 0;
    std::vector<int> counters;
    // The shadow queue shade filled (with NEE).
    std::vector<Ray> shadow_rays;
    std::vector<int> shadow_items;
    std::vector<float4> shadow_contrib;
};

// The shade stage built for a configuration, once per option string.
render::ShadeStage& shade_stage(const render::KernelConfig& config) {
    static std::map<std::string, render::ShadeStage> stages;
    auto it = stages.find(config.shade_options());
    if (it == stages.end())
        it = stages.emplace(config.shade_options(), render::ShadeStage(test::device(), config)).first;
    return it->second;
}

// Runs shade_surface once over the case's paths through the stage's launcher.
ShadeOut run_shade(const ShadeCase& c) {
    auto& dev = test::device();
    const std::size_t n = c.rays.size();
    render::PathQueue in, out;
    in.rays = ocl::Array<Ray>::upload(dev, c.rays, "rays");
    in.paths = ocl::Array<PathState>::upload(dev, c.paths, "paths");
    in.count = ocl::Array<int>::upload(dev, {static_cast<int>(n)}, "count");
    out.rays = ocl::Array<Ray>::allocate(dev, n, "rays out");
    out.paths = ocl::Array<PathState>::allocate(dev, n, "paths out");
    out.count = ocl::Array<int>::zeros(dev, 1, "count out");
    auto hits = ocl::Array<Hit>::upload(dev, c.hits, "hits");
    render::ShadingScene scene;
    scene.tris = ocl::Array<Triangle>::upload(dev, c.tris, "tris");
    scene.tri_frames = ocl::Array<float4>::allocate(dev, c.tris.size(), "tri frames");
    scene.material_ids = ocl::Array<int>::upload(dev, c.material_ids, "material ids");
    scene.materials = ocl::Array<MaterialData>::upload(dev, c.materials, "materials");
    scene.background = c.background;
    scene.light_cdf = ocl::Array<float>::upload(dev, c.light_cdf, "light cdf");
    const std::vector<int> guide = build_cdf_guide(c.light_cdf);
    scene.light_guide = ocl::Array<int>::upload(dev, guide, "light guide");
    scene.light_guide_size = static_cast<int>(guide.size()) - 1;
    scene.light_prims = ocl::Array<int>::upload(dev, c.light_prims, "light prims");
    scene.light_pdf_area = ocl::Array<float>::upload(dev, c.light_pdf_area, "light pdf");
    scene.light_count = static_cast<int>(c.light_prims.size());
    if (!c.light_pairs.empty()) scene.light_pairs = ocl::Array<LightPair>::upload(dev, c.light_pairs, "light pairs");
    if (!c.normals.empty()) scene.tri_normals = ocl::Array<TriNormals>::upload(dev, c.normals, "normals");
    if (!c.tables.empty()) scene.material_tables = ocl::Array<float>::upload(dev, c.tables, "material tables");
    render::ShadowQueue shadow;
    shadow.rays = ocl::Array<Ray>::allocate(dev, n, "shadow rays");
    shadow.items = ocl::Array<int>::allocate(dev, n, "shadow items");
    shadow.contrib = ocl::Array<float4>::allocate(dev, n, "shadow contrib");
    shadow.count = ocl::Array<int>::zeros(dev, 1, "shadow count");
    auto radiance = ocl::Array<float4>::zeros(dev, c.pixels, "radiance");
    auto counters = ocl::Array<int>::zeros(dev, WP_COUNTER_COUNT, "counters");
    shade_stage(c.config).prepare(scene);
    shade_stage(c.config).enqueue(n, in, hits, scene, c.seed, c.bounce, c.max_depth, radiance,
                                  counters, out, shadow);
    ShadeOut o;
    o.count = out.count.read(dev)[0];
    o.radiance = radiance.read(dev);
    o.counters = counters.read(dev);
    o.rays = out.rays.read(dev, 0, o.count);
    o.paths = out.paths.read(dev, 0, o.count);
    int ns = shadow.count.read(dev)[0];
    o.shadow_rays = shadow.rays.read(dev, 0, ns);
    o.shadow_items = shadow.items.read(dev, 0, ns);
    o.shadow_contrib = shadow.contrib.read(dev, 0, ns);
    return o;
}

// The unit right triangle in the plane z = 0, counter-clockwise seen from +z: its front
// normal is +z. A hit with barycentrics (u, v) = (0.25, 0.25) is at (0.25, 0.25, 0).
Triangle floor_triangle() { return {{0, 0, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 0}}; }

// `exponent`: a Phong exponent, stored as the GGX alpha the host derives from it.
MaterialData material(int kind, glm::vec3 albedo, glm::vec3 emission = glm::vec3(0), float exponent = 0) {
    MaterialData m{};
    m.albedo = {albedo.x, albedo.y, albedo.z, 0};
    m.alpha = kind == WP_MATERIAL_GLOSSY ? std::sqrt(2.0f / (exponent + 2.0f)) : 0.0f;
    m.emission = {emission.x, emission.y, emission.z, 0};
    m.kind = kind;
    return m;
}

// One path per entry: ray from `from` towards (0.25, 0.25, 0) with throughput `beta`.
void add_path(ShadeCase& c, glm::vec3 dir, glm::vec3 beta, int pixel, bool miss = false) {
    glm::vec3 d = glm::normalize(dir);
    glm::vec3 o = glm::vec3(0.25f, 0.25f, 0.0f) - d * 2.0f;
    c.rays.push_back(test::make_ray(o, d));
    PathState p{};
    p.throughput = {beta.x, beta.y, beta.z, 0};
    p.pixel = pixel;
    p.sample = c.sample;
    p.item = pixel;  // the radiance slot: one per path here
    c.paths.push_back(p);
    c.hits.push_back(miss ? Hit{FLT_MAX, -1, 0, 0} : Hit{2.0f, 0, 0.25f, 0.25f});
    c.pixels = std::max(c.pixels, pixel + 1);
}

ShadeCase single_triangle(MaterialData m) {
    ShadeCase c;
    c.tris = {floor_triangle()};
    c.material_ids = {0};
    c.materials = {m};
    return c;
}

glm::vec3 v3(float4 v) { return {v.x, v.y, v.z}; }


// 1e6 paths hitting the floor triangle from direction `dir`, each its own pixel (so its
// own random numbers).
ShadeCase many_paths(MaterialData m, glm::vec3 dir, int n) {
    ShadeCase c = single_triangle(m);
    c.rays.reserve(n);
    for (int i = 0; i < n; ++i) add_path(c, dir, glm::vec3(1.0f), i);
    return c;
}

}  // namespace

TEST_CASE("shade: triangle frames (face normal, offset share) match double precision", "[kernel][shade]") {
    // The frames shade reads instead of recomputing them per hit (kernels/shared/offset.h):
    // checked against the same quantities worked out in double on the host — the unit
    // normal of (v1 - v0) x (v2 - v0) and the offset share min(K eps L^3 / |e1 x e2|, L / 1024)
    // with K = 16, eps = 2^-24, L the longest edge — for random triangles at scales 1e-4 to
    // 1e5 (needles included), and a zero-area triangle.
    auto& dev = test::device();
    test::Rng rng(7);
    std::vector<Triangle> tris;
    for (int i = 0; i < 4000; ++i) {
        const double scale = std::pow(10.0, -4.0 + 9.0 * rng.uniform());
        const double offset = (i % 3 == 0) ? 1e5 * rng.uniform() : 0.0;
        auto vertex = [&] {
            return float4{static_cast<float>(offset + scale * (2 * rng.uniform() - 1)),
                          static_cast<float>(scale * (2 * rng.uniform() - 1)),
                          static_cast<float>(scale * (2 * rng.uniform() - 1)), 0.0f};
        };
        Triangle t{vertex(), vertex(), vertex()};
        if (i % 7 == 0) {  // a needle: v2 close to the line v0 v1
            const float a = static_cast<float>(rng.uniform());
            t.v2 = {t.v0.x + a * (t.v1.x - t.v0.x), t.v0.y + a * (t.v1.y - t.v0.y) + 1e-3f * t.v1.z,
                    t.v0.z + a * (t.v1.z - t.v0.z), 0.0f};
        }
        tris.push_back(t);
    }
    tris.push_back({{1, 2, 3, 0}, {2, 4, 6, 0}, {3, 6, 9, 0}});  // collinear: zero area
    render::ShadingScene scene;
    scene.tris = ocl::Array<Triangle>::upload(dev, tris, "tris");
    scene.tri_frames = ocl::Array<float4>::allocate(dev, tris.size(), "tri frames");
    render::KernelConfig config;
    shade_stage(config).prepare(scene);
    const std::vector<float4> frames = scene.tri_frames.read(dev);
    REQUIRE(frames.size() == tris.size());
    double worst_normal = 0.0, worst_share = 0.0;
    int checked = 0;
    for (std::size_t i = 0; i + 1 < tris.size(); ++i) {
        const glm::dvec3 v0(tris[i].v0.x, tris[i].v0.y, tris[i].v0.z);
        const glm::dvec3 v1(tris[i].v1.x, tris[i].v1.y, tris[i].v1.z);
        const glm::dvec3 v2(tris[i].v2.x, tris[i].v2.y, tris[i].v2.z);
        const glm::dvec3 c = glm::cross(v1 - v0, v2 - v0);
        const double twice_area = glm::length(c);
        const double l = std::sqrt(std::max({glm::dot(v1 - v0, v1 - v0), glm::dot(v2 - v0, v2 - v0),
                                             glm::dot(v2 - v1, v2 - v1)}));
        // The kernel's float edges, cross product and lengths err by a few eps / sin(angle)
        // relative (the vertices themselves are exact in double): skip the near-degenerate
        // ones (many of the small triangles translated by up to 1e5 collapse in float).
        const double sin_angle = twice_area / (glm::length(v1 - v0) * glm::length(v2 - v0));
        if (!(sin_angle > 1e-3)) continue;
        ++checked;
        const glm::dvec3 n = c / twice_area;
        const float4 f = frames[i];
        worst_normal = std::max(worst_normal, glm::length(glm::dvec3(f.x, f.y, f.z) - n));
        const double share = std::min(16.0 * 5.9604644775390625e-8 * l * l * l / twice_area, l / 1024.0);
        worst_share = std::max(worst_share, std::abs(f.w - share) / share);
    }
    INFO("checked " << checked << " of " << tris.size() - 1 << " triangles; worst normal error "
                    << worst_normal << ", worst relative share error " << worst_share);
    CHECK(checked > 2000);
    CHECK(worst_normal < 1e-4);  // a few eps / 1e-3 at worst
    CHECK(worst_share < 1e-4);
    // Zero area: no unit normal (OpenCL's normalize returns the zero vector), the share capped
    // at L / 1024 (L = |(3, 6, 9) - (1, 2, 3)| = sqrt(56)).
    const float4 z = frames.back();
    CHECK(!(std::sqrt(z.x * z.x + z.y * z.y + z.z * z.z) > 0.5f));
    CHECK(z.w == Approx(std::sqrt(56.0) / 1024.0).epsilon(1e-6));
}

TEST_CASE("shade: emission is one-sided, misses see the background", "[kernel][shade]") {
    ShadeCase c = single_triangle(material(WP_MATERIAL_DIFFUSE, glm::vec3(0.5f), {2, 3, 4}));
    c.background = {0.1f, 0.2f, 0.4f, 0};
    add_path(c, {0.2f, 0.1f, -1}, {0.5f, 1, 2}, 0);       // front face
    add_path(c, {0.2f, 0.1f, 1}, {1, 1, 1}, 1);           // back face: no emission
    add_path(c, {0.0f, 0.0f, -1}, {0.5f, 1, 2}, 2, true);  // miss
    c.max_depth = 0;                                      // emission only, nothing pushed
    ShadeOut o = run_shade(c);
    CHECK(v3(o.radiance[0]) == glm::vec3(1, 3, 8));
    CHECK(v3(o.radiance[1]) == glm::vec3(0, 0, 0));
    CHECK(v3(o.radiance[2]) == glm::vec3(0.05f, 0.2f, 0.8f));
    CHECK(o.count == 0);
    CHECK(o.counters[WP_COUNTER_SHADE_NONFINITE] == 0);
}

TEST_CASE("shade: mirror reflects exactly and pushes an offset ray", "[kernel][shade]") {
    ShadeCase c = single_triangle(material(WP_MATERIAL_MIRROR, {0.9f, 0.5f, 0.25f}));
    c.bounce = 1;
    add_path(c, {1, 0, -1}, {1, 2, 4}, 7);   // 45 degrees onto the front
    add_path(c, {0, -3, 4}, {1, 1, 1}, 3);   // onto the back: reflects below the plane
    ShadeOut o = run_shade(c);
    REQUIRE(o.count == 2);
    for (int k = 0; k < 2; ++k) {
        const Ray& r = o.rays[k];
        const PathState& p = o.paths[k];
        glm::vec3 d(r.dir.x, r.dir.y, r.dir.z), org(r.org.x, r.org.y, r.org.z);
        CHECK(p.item == p.pixel);  // the continued path keeps its sample
        CHECK(p.throughput.w == 0.0f);  // a specular bounce has no density
        CHECK(r.org.w == 0.0f);
        CHECK(r.dir.w == FLT_MAX);
        // Origin: next to the hit point, strictly on the side the ray came from.
        CHECK(glm::length(org - glm::vec3(0.25f, 0.25f, 0)) < 1e-4f);
        if (p.pixel == 7) {
            CHECK(org.z > 0.0f);
            CHECK(std::abs(d.x - std::sqrt(0.5f)) < 1e-6f);
            CHECK(d.y == 0.0f);
            CHECK(std::abs(d.z - std::sqrt(0.5f)) < 1e-6f);
            CHECK(v3(p.throughput) == glm::vec3(0.9f, 1.0f, 1.0f));
        } else {
            REQUIRE(p.pixel == 3);
            CHECK(org.z < 0.0f);
            CHECK(d.x == 0.0f);
            CHECK(std::abs(d.y - -0.6f) < 1e-6f);
            CHECK(std::abs(d.z - -0.8f) < 1e-6f);
            CHECK(v3(p.throughput) == glm::vec3(0.9f, 0.5f, 0.25f));
        }
    }
}

TEST_CASE("shade: diffuse and glossy throughput, depth limit and dead paths", "[kernel][shade]") {
    SECTION("diffuse: weight 2 albedo cos(theta) for a uniform hemisphere sample") {
        ShadeCase c = single_triangle(material(WP_MATERIAL_DIFFUSE, {0.8f, 0.4f, 0.2f}));
        for (int i = 0; i < 256; ++i) add_path(c, {0.3f, -0.1f, -1}, {1, 0.5f, 2}, i);
        ShadeOut o = run_shade(c);
        REQUIRE(o.count == 256);
        for (int k = 0; k < o.count; ++k) {
            const Ray& r = o.rays[k];
            float cos_t = r.dir.z;  // the normal is +z
            REQUIRE(cos_t > 0.0f);
            REQUIRE(glm::length(glm::vec3(r.dir.x, r.dir.y, r.dir.z)) == Approx(1.0f).epsilon(1e-6));
            glm::vec3 t = v3(o.paths[k].throughput);
            CHECK(t.x == Approx(0.8f * 2 * cos_t).epsilon(1e-5));
            CHECK(t.y == Approx(0.5f * 0.4f * 2 * cos_t).epsilon(1e-5));
            CHECK(t.z == Approx(2.0f * 0.2f * 2 * cos_t).epsilon(1e-5));
            CHECK(r.org.z > 0.0f);
        }
    }
    SECTION("glossy: weight albedo, directions above the surface only") {
        ShadeCase c = single_triangle(material(WP_MATERIAL_GLOSSY, {0.7f, 0.6f, 0.5f}, {}, 5.0f));
        for (int i = 0; i < 256; ++i) add_path(c, {1, 0, -0.3f}, {1, 1, 1}, i);
        ShadeOut o = run_shade(c);
        REQUIRE(o.count > 0);
        REQUIRE(o.count < 256);  // grazing incidence: some of the lobe falls below
        for (int k = 0; k < o.count; ++k) {
            CHECK(o.rays[k].dir.z > 0.0f);
            CHECK(v3(o.paths[k].throughput) == glm::vec3(0.7f, 0.6f, 0.5f));
        }
    }
    SECTION("at the depth limit only emission is added; black paths are not pushed") {
        ShadeCase c = single_triangle(material(WP_MATERIAL_DIFFUSE, glm::vec3(0.5f), {1, 1, 1}));
        c.materials.push_back(material(WP_MATERIAL_DIFFUSE, glm::vec3(0.0f)));
        c.bounce = 3;
        c.max_depth = 3;
        add_path(c, {0, 0, -1}, {1, 1, 1}, 0);
        ShadeOut o = run_shade(c);
        CHECK(v3(o.radiance[0]) == glm::vec3(1, 1, 1));
        CHECK(o.count == 0);
        c.max_depth = 4;
        c.material_ids = {1};  // albedo 0
        o = run_shade(c);
        CHECK(o.count == 0);
    }
    SECTION("NaN throughput is counted and never reaches the radiance") {
        ShadeCase c = single_triangle(material(WP_MATERIAL_DIFFUSE, glm::vec3(0.5f), {1, 1, 1}));
        add_path(c, {0, 0, -1}, {NAN, 1, 1}, 0);
        ShadeOut o = run_shade(c);
        CHECK(v3(o.radiance[0]) == glm::vec3(0, 0, 0));
        CHECK(o.count == 0);
        // The entry guard ends the path and counts it once (before, the emission and the
        // scattering each counted it: one NaN, two counts).
        CHECK(o.counters[WP_COUNTER_SHADE_NONFINITE] == 1);
    }
}

TEST_CASE("shade: diffuse directions follow the uniform hemisphere density (chi2)",
          "[kernel][shade][stat]") {
    const int n = 1000000, nt = 20, np = 40;
    ShadeCase c = many_paths(material(WP_MATERIAL_DIFFUSE, glm::vec3(0.5f)), {0.3f, -0.2f, -1}, n);
    ShadeOut o = run_shade(c);
    REQUIRE(o.count == n);
    std::vector<double> obs(nt * np, 0.0);
    for (const Ray& r : o.rays) obs[bin_of({r.dir.x, r.dir.y, r.dir.z}, nt, np)] += 1;
    // Uniform over the upper hemisphere of the +z normal: 1 / (2π) for z > 0.
    auto prob = bin_probabilities(nt, np, [](glm::dvec3 w) { return w.z > 0 ? 1.0 / (2 * M_PI) : 0.0; });
    std::vector<double> expct(prob.size());
    for (std::size_t i = 0; i < prob.size(); ++i) expct[i] = prob[i] * n;
    int dof = 0;
    double p = chi2_pvalue(obs, expct, &dof);
    INFO("chi2 p-value " << p << " with " << dof << " degrees of freedom");
    CHECK(dof > 300);
    CHECK(p > 0.01);
}

TEST_CASE("shade: glossy directions follow the Phong lobe around the mirror direction (chi2)",
          "[kernel][shade][stat]") {
    const int n = 1000000, nt = 40, np = 40;
    const double e = 12.0;
    glm::dvec3 din = glm::normalize(glm::dvec3(1.0, 0.4, -0.6));
    ShadeCase c = many_paths(material(WP_MATERIAL_GLOSSY, glm::vec3(0.9f), {}, float(e)),
                             glm::vec3(din), n);
    ShadeOut o = run_shade(c);
    // Mirror direction about the +z normal, and the normalised Phong lobe around it.
    glm::dvec3 r(din.x, din.y, -din.z);
    auto lobe = [&](glm::dvec3 w) {
        double ca = glm::dot(w, r);
        return ca > 0 ? (e + 1) / (2 * M_PI) * std::pow(ca, e) : 0.0;
    };
    auto prob = bin_probabilities(nt, np, lobe);
    // Bins over the whole sphere; samples below the surface are absorbed, so they form one
    // extra bin whose probability is the lobe's mass below the plane.
    std::vector<double> obs(nt * np + 1, 0.0), expct(nt * np + 1, 0.0);
    double above = 0;
    for (int i = 0; i < nt * np; ++i) {
        bool upper = i / np < nt / 2;  // θ < π/2
        if (upper) {
            expct[i] = prob[i] * n;
            above += prob[i];
        }
    }
    expct[nt * np] = (1.0 - above) * n;
    for (const Ray& ray : o.rays) obs[bin_of({ray.dir.x, ray.dir.y, ray.dir.z}, nt, np)] += 1;
    obs[nt * np] = n - o.count;
    INFO("absorbed " << obs[nt * np] << ", expected " << expct[nt * np]);
    REQUIRE(expct[nt * np] > 1000);  // the case exercises the below-surface part
    int dof = 0;
    double p = chi2_pvalue(obs, expct, &dof);
    INFO("chi2 p-value " << p << " with " << dof << " degrees of freedom");
    CHECK(dof > 100);
    CHECK(p > 0.01);
}

// ---- The shipped configuration: MIS + GGX + NEE + Russian roulette + Sobol ----------------

namespace {

// The floor point (0.25, 0.25, 0) (normal +z) under a square light of side 0.5 at height 1,
// facing down, with radiance le: triangles 1 and 2, material 1.
ShadeCase lit_floor(MaterialData floor, float le) {
    ShadeCase c;
    c.config = render::KernelConfig{};  // the shipped estimator, every kind, NEE on
    c.tris = {floor_triangle(),
              {{0, 0, 1, 0}, {0.5f, 0.5f, 1, 0}, {0.5f, 0, 1, 0}},   // winding: front -z
              {{0, 0, 1, 0}, {0, 0.5f, 1, 0}, {0.5f, 0.5f, 1, 0}}};
    c.material_ids = {0, 1, 1};
    c.materials = {floor, material(WP_MATERIAL_DIFFUSE, glm::vec3(0), glm::vec3(le))};
    // The light table by hand: two equal triangles of area 1/8, chosen with 1/2 each.
    c.light_cdf = {0.5f, 1.0f};
    c.light_prims = {1, 2};
    c.light_pdf_area = {0.0f, 4.0f, 4.0f};
    return c;
}

// ∫ f(wo, wi) le cos_i cos_l / r² dA over the light (midpoint rule, double), the direct
// light the floor point sends towards -d; f from `brdf(wo, wi)` with +z the normal.
template <typename Brdf>
double direct_light(glm::dvec3 d, double le, Brdf brdf) {
    const glm::dvec3 x(0.25, 0.25, 0.0), wo = -glm::normalize(d);
    const int m = 600;
    double sum = 0.0, da = (0.5 / m) * (0.5 / m);
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < m; ++j) {
            glm::dvec3 y((i + 0.5) * 0.5 / m, (j + 0.5) * 0.5 / m, 1.0);
            glm::dvec3 to = y - x;
            double r2 = glm::dot(to, to);
            glm::dvec3 wi = to / std::sqrt(r2);
            sum += brdf(wo, wi) * le * wi.z * wi.z / r2 * da;  // cos_i = cos_l = wi.z
        }
    return sum;
}

struct DirectEstimate {
    double mean = 0, se = 0;       // per-path estimate of the direct light, and its s.e.
    double light_part = 0;         // mean of the light-sampled (NEE) part
    double bsdf_part = 0;          // mean of the BSDF-sampled part (hits of the light)
};

// n paths from direction d onto the lit floor: bounce 0 shades them (light samples and the
// scattered rays), the scattered rays are traced against the three triangles by brute
// force, and bounce 1 (max_depth 1) adds the light they hit with its MIS weight.
DirectEstimate estimate_direct(ShadeCase c, glm::vec3 d, int n) {
    for (int i = 0; i < n; ++i) add_path(c, d, glm::vec3(1.0f), i);
    c.max_depth = 1;
    ShadeOut o0 = run_shade(c);
    std::vector<double> est(n, 0.0), light(n, 0.0);
    for (std::size_t k = 0; k < o0.shadow_items.size(); ++k) {
        light[o0.shadow_items[k]] += o0.shadow_contrib[k].x;  // nothing occludes the light
        est[o0.shadow_items[k]] += o0.shadow_contrib[k].x;
    }
    // Bounce 1: the scattered rays against the scene, by brute force.
    std::vector<glm::vec3> pos;
    std::vector<glm::uvec3> tris;
    for (const Triangle& t : c.tris) {
        unsigned b = static_cast<unsigned>(pos.size());
        pos.push_back({t.v0.x, t.v0.y, t.v0.z});
        pos.push_back({t.v1.x, t.v1.y, t.v1.z});
        pos.push_back({t.v2.x, t.v2.y, t.v2.z});
        tris.push_back({b, b + 1, b + 2});
    }
    ShadeCase c1 = c;
    c1.rays = o0.rays;
    c1.paths = o0.paths;
    c1.hits = test::brute_force(pos, tris, o0.rays);
    c1.bounce = 1;
    ShadeOut o1 = run_shade(c1);
    CHECK(o1.count == 0);  // max_depth 1: nothing continues
    DirectEstimate r;
    double s2 = 0.0;
    for (int i = 0; i < n; ++i) {
        est[i] += o1.radiance[i].x;
        r.bsdf_part += o1.radiance[i].x / n;
        r.light_part += light[i] / n;
        r.mean += est[i] / n;
    }
    for (int i = 0; i < n; ++i) s2 += (est[i] - r.mean) * (est[i] - r.mean);
    r.se = std::sqrt(s2 / (n - 1) / n);
    CHECK(o0.counters[WP_COUNTER_SHADE_NONFINITE] == 0);
    CHECK(o1.counters[WP_COUNTER_SHADE_NONFINITE] == 0);
    return r;
}

}  // namespace

TEST_CASE("shade (shipped configuration): light samples and BSDF samples combined by MIS give "
          "the direct light of an area light", "[kernel][shade][stat]") {
    const int n = 200000;
    const float le = 4.0f;
    const glm::vec3 d(0.3f, -0.2f, -1.0f);
    SECTION("diffuse floor") {
        const double rho = 0.5;
        DirectEstimate e = estimate_direct(lit_floor(material(WP_MATERIAL_DIFFUSE, glm::vec3(0.5f)), le), d, n);
        double expected = direct_light(d, le, [&](glm::dvec3, glm::dvec3) { return rho / M_PI; });
        INFO("estimate " << e.mean << " +- " << e.se << " (light part " << e.light_part
                         << ", BSDF part " << e.bsdf_part << "), expected " << expected);
        CHECK(std::abs(e.mean - expected) < 4.0 * e.se);
        CHECK(e.se < 0.01 * expected);  // the test resolves a 4 % bias
        // Both strategies carry weight (MIS, not one of them alone), and the test sees it:
        // without the BSDF-sampled part the estimate would be off by > 4 s.e.
        CHECK(e.light_part > 0.5 * expected);
        CHECK(e.bsdf_part > 0.003 * expected);
        CHECK(std::abs(e.light_part - expected) > 4.0 * e.se);
    }
    SECTION("GGX floor (alpha 0.3, F0 0.8)") {
        const double alpha = 0.3, f0 = 0.8;
        MaterialData m = material(WP_MATERIAL_GLOSSY, glm::vec3(float(f0)));
        m.alpha = float(alpha);
        DirectEstimate e = estimate_direct(lit_floor(m, le), d, n);
        // GGX from its definition (Walter et al. 2007; height-correlated Smith, Heitz 2014),
        // in double, written here independently of kernels/shared.
        auto lambda = [&](glm::dvec3 w) {
            double t2 = (1.0 - w.z * w.z) / (w.z * w.z);
            return (-1.0 + std::sqrt(1.0 + alpha * alpha * t2)) / 2.0;
        };
        auto brdf = [&](glm::dvec3 wo, glm::dvec3 wi) {
            glm::dvec3 h = glm::normalize(wo + wi);
            double a2 = alpha * alpha, c2 = h.z * h.z;
            double dd = a2 / (M_PI * std::pow(c2 * (a2 - 1.0) + 1.0, 2.0));
            double g2 = 1.0 / (1.0 + lambda(wo) + lambda(wi));
            double fr = f0 + (1.0 - f0) * std::pow(1.0 - glm::dot(wo, h), 5.0);
            return fr * dd * g2 / (4.0 * wo.z * wi.z);
        };
        double expected = direct_light(d, le, brdf);
        INFO("estimate " << e.mean << " +- " << e.se << " (light part " << e.light_part
                         << ", BSDF part " << e.bsdf_part << "), expected " << expected);
        CHECK(std::abs(e.mean - expected) < 4.0 * e.se);
        CHECK(e.se < 0.02 * expected);
        CHECK(e.light_part > 0.5 * expected);
        CHECK(e.bsdf_part > 0.01 * expected);
        CHECK(std::abs(e.light_part - expected) > 4.0 * e.se);
    }
}

namespace {

// The outputs of two shade runs over the same n paths (item i = path i) that differ in any
// bit: radiance slots, pushed rays and throughputs, shadow rays and contributions, and
// paths pushed by one run only. Queue order depends on which work-group (or work-item)
// reserved its slots first, so queue entries are matched by item.
int output_differences(const ShadeOut& a, const ShadeOut& b, int n) {
    auto same = [](float4 x, float4 y) { return std::memcmp(&x, &y, sizeof x) == 0; };
    int differ = 0;
    for (int i = 0; i < n; ++i) differ += !same(a.radiance[i], b.radiance[i]);
    std::vector<int> at(n, -1), bt(n, -1);
    for (int k = 0; k < a.count; ++k) at[a.paths[k].item] = k;
    for (int k = 0; k < b.count; ++k) bt[b.paths[k].item] = k;
    for (int i = 0; i < n; ++i) {
        const int ka = at[i], kb = bt[i];
        if (ka < 0 || kb < 0) {
            differ += (ka < 0) != (kb < 0);
            continue;
        }
        differ += !same(a.rays[ka].org, b.rays[kb].org) + !same(a.rays[ka].dir, b.rays[kb].dir) +
                  !same(a.paths[ka].throughput, b.paths[kb].throughput) +
                  (a.paths[ka].pixel != b.paths[kb].pixel) + (a.paths[ka].sample != b.paths[kb].sample);
    }
    std::vector<int> as(n, -1), bs(n, -1);
    for (std::size_t k = 0; k < a.shadow_rays.size(); ++k) as[a.shadow_items[k]] = int(k);
    for (std::size_t k = 0; k < b.shadow_rays.size(); ++k) bs[b.shadow_items[k]] = int(k);
    for (int i = 0; i < n; ++i) {
        const int ka = as[i], kb = bs[i];
        if (ka < 0 || kb < 0) {
            differ += (ka < 0) != (kb < 0);
            continue;
        }
        differ += !same(a.shadow_rays[ka].org, b.shadow_rays[kb].org) +
                  !same(a.shadow_rays[ka].dir, b.shadow_rays[kb].dir) +
                  !same(a.shadow_contrib[ka], b.shadow_contrib[kb]);
    }
    return differ;
}

}  // namespace

TEST_CASE("shade: with shading normals compiled, a triangle without vertex normals shades "
          "exactly as without the feature", "[kernel][shade]") {
    // The generic build (and any scene where some triangles have normals) runs flat
    // triangles with WP_HAVE_NORMALS=1 and zero normals. Their shading normal is the face
    // normal, so the bent-normal guard and the terminator factor must not act: every output
    // bit equals the build without normals, also for glossy and mirror floors seen within
    // cos 1e-3 of grazing (where the guard would bend a face normal) and for the light
    // samples (where the factor is 1 only up to rounding).
    for (int kind : {WP_MATERIAL_DIFFUSE, WP_MATERIAL_GLOSSY, WP_MATERIAL_MIRROR}) {
        MaterialData m = material(kind, glm::vec3(0.7f));
        if (kind == WP_MATERIAL_GLOSSY) m.alpha = 0.3f;
        ShadeCase flat = lit_floor(m, 4.0f);
        flat.bounce = 1;
        const int n = 20000;
        for (int i = 0; i < n; ++i) {
            // Elevations from 1e-5 (grazing) to straight down, azimuths all round.
            const float cz = std::pow(10.0f, -5.0f + 5.0f * float(i % 100) / 99.0f);
            const float phi = 0.37f * float(i);
            const float sz = std::sqrt(1.0f - cz * cz);
            add_path(flat, {sz * std::cos(phi), sz * std::sin(phi), -cz}, glm::vec3(1.0f), i);
            flat.paths.back().throughput.w = 0.5f;  // the density of the arriving direction
        }
        flat.pixels = n;
        ShadeCase smooth = flat;
        smooth.config.normals = true;
        smooth.normals.assign(flat.tris.size(), TriNormals{});  // zero: no vertex normals
        const ShadeOut a = run_shade(flat), b = run_shade(smooth);
        INFO("kind " << kind);
        REQUIRE(a.count == b.count);
        REQUIRE(a.shadow_rays.size() == b.shadow_rays.size());
        CHECK(a.count > n / 4);
        if (kind != WP_MATERIAL_MIRROR) CHECK(a.shadow_rays.size() > std::size_t(n / 4));
        const int differ = output_differences(a, b, n);
        CHECK(differ == 0);
    }
}

TEST_CASE("shade (shipped configuration): Russian roulette keeps paths with probability "
          "min(1, max throughput) and divides by it", "[kernel][shade][stat]") {
    const int n = 100000;
    ShadeCase c = single_triangle(material(WP_MATERIAL_DIFFUSE, {0.5f, 0.25f, 0.1f}));
    c.config = render::KernelConfig{};  // roulette from bounce 3 (limits.h), Sobol, MIS
    c.bounce = 5;
    c.max_depth = 10;
    for (int i = 0; i < n; ++i) add_path(c, {0.2f, 0.3f, -1}, {0.8f, 0.8f, 0.8f}, i);
    ShadeOut o = run_shade(c);
    // Cosine sampling: the weight is the albedo, so every path's throughput before the
    // roulette is 0.8 * albedo and q = 0.4.
    const float bx = 0.8f * 0.5f, by = 0.8f * 0.25f, bz = 0.8f * 0.1f, q = bx;
    const double p = q, sd = std::sqrt(p * (1 - p) / n);
    INFO("survivors " << o.count << " of " << n << ", expected " << p * n);
    CHECK(std::abs(double(o.count) / n - p) < 4 * sd);
    for (int k = 0; k < o.count; ++k) {
        REQUIRE(o.paths[k].throughput.x == bx * (1.0f / q));
        REQUIRE(o.paths[k].throughput.y == by * (1.0f / q));
        REQUIRE(o.paths[k].throughput.z == bz * (1.0f / q));
    }
    // Before the roulette bounce nothing is dropped.
    c.bounce = 2;
    CHECK(run_shade(c).count == n);
}

namespace {

// Random hits for the lane tests: 40 triangles from 1e-3 to 1e3 units (the first six
// emitters, seen from both sides), vertex normals on every other one bent by up to ~35
// degrees (one vertex normal reversed now and then), misses, paths that arrived by a Dirac
// lobe, NaN and infinite throughputs, a queue length that is not a multiple of eight.
// material_of(t) gives triangle t's material (emission is set here for the lights).
ShadeCase random_lane_case(std::mt19937& rng, const std::function<MaterialData(int)>& material_of) {
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    ShadeCase base;
    const int tris = 40, lights = 6;
    float total = 0.0f;
    std::vector<float> weights;
    for (int t = 0; t < tris; ++t) {
        const float scale = std::pow(10.0f, -3.0f + 6.0f * u01(rng));
        const glm::vec3 c(4 * u01(rng) - 2, 4 * u01(rng) - 2, 4 * u01(rng) - 2);
        auto vert = [&] {
            glm::vec3 p = c + scale * glm::vec3(u01(rng) - 0.5f, u01(rng) - 0.5f, u01(rng) - 0.5f);
            return float4{p.x, p.y, p.z, 0};
        };
        base.tris.push_back({vert(), vert(), vert()});
        const bool light = t < lights;
        base.material_ids.push_back(t);
        MaterialData m = light ? material(WP_MATERIAL_DIFFUSE, {u01(rng), u01(rng), u01(rng)},
                                          glm::vec3(1 + 9 * u01(rng), 2, 3 * u01(rng)))
                               : material_of(t);
        base.materials.push_back(m);
        TriNormals tn{};
        if (t % 2 == 1) {
            const Triangle& tr = base.tris.back();
            const glm::vec3 fn = glm::normalize(glm::cross(v3(tr.v1) - v3(tr.v0), v3(tr.v2) - v3(tr.v0)));
            float4* rows[3] = {&tn.n0, &tn.n1, &tn.n2};
            for (int k = 0; k < 3; ++k) {
                glm::vec3 vn = fn + 0.7f * glm::vec3(u01(rng) - 0.5f, u01(rng) - 0.5f, u01(rng) - 0.5f);
                if (t % 7 == 3 && k == 0) vn = -vn;
                *rows[k] = {vn.x, vn.y, vn.z, 0};
            }
        }
        base.normals.push_back(tn);
        if (light) {
            base.light_prims.push_back(t);
            weights.push_back(0.5f + u01(rng));
            total += weights.back();
        }
    }
    for (float w : weights) base.light_cdf.push_back((base.light_cdf.empty() ? 0.0f : base.light_cdf.back()) + w / total);
    base.light_cdf.back() = 1.0f;
    base.light_pdf_area.assign(tris, 0.0f);
    for (int k = 0; k < lights; ++k) {
        const Triangle& t = base.tris[base.light_prims[k]];
        const glm::vec3 e1 = v3(t.v1) - v3(t.v0), e2 = v3(t.v2) - v3(t.v0);
        base.light_pdf_area[base.light_prims[k]] = weights[k] / total / (0.5f * glm::length(glm::cross(e1, e2)));
    }
    // Light pairs (for configurations with them): lights 0-1, 2-3, 4-5, the partner's chance
    // over this triangle's area.
    base.light_pairs.assign(tris, LightPair{-1, 0.0f});
    for (int k = 0; k < lights; ++k) {
        const Triangle& t = base.tris[base.light_prims[k]];
        const glm::vec3 e1 = v3(t.v1) - v3(t.v0), e2 = v3(t.v2) - v3(t.v0);
        base.light_pairs[base.light_prims[k]] = {base.light_prims[k ^ 1],
                                                 weights[k ^ 1] / total / (0.5f * glm::length(glm::cross(e1, e2)))};
    }
    const int n = 8 * 600 + 5;
    for (int i = 0; i < n; ++i) {
        glm::vec3 d(2 * u01(rng) - 1, 2 * u01(rng) - 1, 2 * u01(rng) - 1);
        d *= 0.5f + u01(rng);  // directions need not be unit length
        PathState p{};
        p.throughput = {u01(rng), u01(rng), 1.5f * u01(rng), i % 7 == 0 ? 0.0f : 2 * u01(rng)};
        if (i % 101 == 0) p.throughput.y = std::nanf("");
        if (i % 103 == 0) p.throughput.x = INFINITY;
        p.pixel = int(rng() % 100000);
        p.sample = rng() % 1000;
        p.item = i;
        base.paths.push_back(p);
        base.rays.push_back(test::make_ray({0, 0, 0}, d));
        float bu = u01(rng), bv = u01(rng);
        if (bu + bv > 1) bu = 1 - bu, bv = 1 - bv;
        base.hits.push_back(i % 9 == 0 ? Hit{FLT_MAX, -1, 0, 0} : Hit{0.1f + 10 * u01(rng), int(rng() % tris), bu, bv});
    }
    base.pixels = n;
    base.background = {0.25f, 0.5f, 0.75f, 0};
    return base;
}

// Shades `base` with shade_surface and with shade_surface8 in four estimators (default
// MIS/Sobol/roulette, the original, NEE with roulette from bounce 1, cosine + Phong), with
// and without shading normals, at bounces 0, 1 and at the depth limit, the default also with
// light pairs, with the material kinds `kinds` compiled, and requires every output bit to
// agree (and the pairs to change the outputs); the lane kernel pushes with non-temporal
// stores (as on a CPU device), and so does shade_surface once (the default estimator).
void check_lanes_match_scalar(const ShadeCase& base, const std::vector<MaterialKind>& kinds) {
    const int n = static_cast<int>(base.rays.size());
    std::vector<render::Estimator> estimators = {render::Estimator{}, render::Estimator::original(),
                                                 {render::Sampling::Nee, render::GlossyModel::Ggx, true, 1},
                                                 {render::Sampling::Cosine, render::GlossyModel::Phong, false, 0}};
    // One estimator, normals and light pairs on or off, at bounces 0, 1 and the depth limit;
    // returns shade_surface's outputs at bounce 1.
    auto check = [&](const render::Estimator& e, bool normals, bool pairs) {
        ShadeOut at_bounce1;
        for (int bounce : {0, 1, 4}) {
            ShadeCase scalar = base;
            scalar.config = render::KernelConfig{};
            scalar.config.kinds.reset();
            for (MaterialKind k : kinds) scalar.config.kinds.set(static_cast<std::size_t>(k));
            scalar.config.estimator = e;
            scalar.config.normals = normals;
            scalar.config.light_pairs = pairs;
            if (!pairs) scalar.light_pairs.clear();
            if (!normals) scalar.normals.clear();
            scalar.bounce = bounce;
            scalar.max_depth = bounce == 4 ? 4 : 8;  // at the depth limit: emission only
            scalar.seed = 11u + unsigned(bounce);
            ShadeCase lanes = scalar;
            lanes.config.lanes = true;
            // Pushes with non-temporal stores, as renders on a CPU device: the same bits as
            // plain ones.
            lanes.config.stream_stores = true;
            REQUIRE(lanes.config.shade_lanes());
            REQUIRE_FALSE(scalar.config.shade_lanes());
            const ShadeOut a = run_shade(scalar), b = run_shade(lanes);
            INFO("sampling " << render::sampling_name(e.sampling) << ", glossy " << render::glossy_name(e.glossy)
                             << ", normals " << normals << ", light pairs " << pairs << ", bounce " << bounce);
            CHECK(a.count == b.count);
            CHECK(a.shadow_rays.size() == b.shadow_rays.size());
            CHECK(a.counters == b.counters);
            CHECK(a.counters[WP_COUNTER_SHADE_NONFINITE] > 0);
            if (bounce < 4) CHECK(a.count > n / 4);
            if (bounce < 4 && lanes.config.nee()) CHECK(a.shadow_rays.size() > std::size_t(n / 10));
            CHECK(output_differences(a, b, n) == 0);
            if (bounce == 0 && normals && !pairs && e.sampling == render::Sampling::Mis && e.rr_depth == WP_DEFAULT_RR_DEPTH) {
                ShadeCase streamed = scalar;
                streamed.config.stream_stores = true;
                CHECK(output_differences(a, run_shade(streamed), n) == 0);
            }
            if (bounce == 1) at_bounce1 = a;
        }
        return at_bounce1;
    };
    const bool has_pairs = std::any_of(base.light_pairs.begin(), base.light_pairs.end(),
                                       [](const LightPair& q) { return q.partner >= 0; });
    for (std::size_t k = 0; k < estimators.size(); ++k)
        for (bool normals : {false, true}) {
            const ShadeOut unpaired = check(estimators[k], normals, false);
            // Light pairs with the default estimator (MIS): they move light samples and weigh
            // emission by the paired density, so the outputs change.
            if (k != 0) continue;
            const ShadeOut paired = check(estimators[k], normals, true);
            if (has_pairs) CHECK(output_differences(unpaired, paired, n) > 0);
        }
}

// `base` with its light table cut to its first n lights (the CDF, the densities and the
// pairs' shares scaled to the remaining power; the others emit but are never sampled, and
// pair with nothing, as the host's tables pair lights only).
ShadeCase with_lights(ShadeCase base, int n) {
    const float kept = base.light_cdf[std::size_t(n) - 1];
    base.light_cdf.resize(std::size_t(n));
    for (float& c : base.light_cdf) c /= kept;
    base.light_cdf.back() = 1.0f;
    std::vector<bool> in_table(base.tris.size(), false);
    for (int k = 0; k < n; ++k) in_table[std::size_t(base.light_prims[std::size_t(k)])] = true;
    for (std::size_t t = 0; t < base.tris.size(); ++t) {
        if (!in_table[t]) base.light_pdf_area[t] = 0.0f;
        base.light_pdf_area[t] /= kept;
        LightPair& q = base.light_pairs[t];
        if (!in_table[t] || (q.partner >= 0 && !in_table[std::size_t(q.partner)]))
            q = LightPair{-1, 0.0f};
        else
            q.pdf /= kept;
    }
    base.light_prims.resize(std::size_t(n));
    return base;
}

}  // namespace

// shade_surface8 (eight paths per work-item, kernels/shared/lanes.h) is a second spelling of
// shade_surface: on random hits (random_lane_case) every output bit must equal
// shade_surface's, in every estimator and glossy model. First the kinds it has lane code
// for (diffuse, glossy, mirror).
TEST_CASE("shade: eight paths per work-item give shade_surface's bits", "[kernel][shade]") {
    std::mt19937 rng(0x5eed8);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    const ShadeCase base = random_lane_case(rng, [&](int t) {
        const int kind = t % 3 == 0 ? WP_MATERIAL_DIFFUSE : t % 3 == 1 ? WP_MATERIAL_GLOSSY : WP_MATERIAL_MIRROR;
        MaterialData m = material(kind, {u01(rng), u01(rng), u01(rng)});
        if (kind == WP_MATERIAL_GLOSSY) m.alpha = m.alpha_v = std::pow(10.0f, -2.0f * u01(rng));
        return m;
    });
    check_lanes_match_scalar(base, {MaterialKind::Diffuse, MaterialKind::Mirror, MaterialKind::Glossy});
    // Tables of at most WP_FEW_LIGHTS (4) lights pick and load the lanes' lights by vector
    // compares and selects (shade.cl, wp_light_lanes_few8) where there are no light pairs:
    // the same bits with three lights, two and one.
    for (int lights : {3, 2, 1}) {
        INFO(lights << " lights in the table");
        check_lanes_match_scalar(with_lights(base, lights),
                                 {MaterialKind::Diffuse, MaterialKind::Mirror, MaterialKind::Glossy});
    }
    // The lane kernel is chosen wherever it models the configuration: every material kind,
    // and none of the appearance features it has no lane code for, no NaN injection.
    render::KernelConfig k;
    CHECK_FALSE(k.shade_lanes());  // lanes not allowed (a GPU, or --shade-lanes off)
    k.lanes = true;
    CHECK(k.shade_lanes());  // every kind
    k.normals = true;
    CHECK(k.shade_lanes());
    for (auto feature : {&render::KernelConfig::textures,
                         &render::KernelConfig::normal_maps, &render::KernelConfig::env,
                         &render::KernelConfig::anisotropic}) {
        render::KernelConfig f = k;
        f.*feature = true;
        CHECK_FALSE(f.shade_lanes());
    }
    k.inject_nan = 1;
    CHECK_FALSE(k.shade_lanes());
}

// The kinds without lane code (glass, conductors, rough dielectrics, thin dielectrics,
// plastics) take their scalar BSDF lane by lane inside shade_surface8: mixed with the lane
// kinds on the same random hits, every output bit must still equal shade_surface's. The
// materials come from the host's own upload (upload_scene), so their parameters, plastic
// weights and rough-plastic tables are what a scene file gives.
TEST_CASE("shade: eight paths per work-item give shade_surface's bits with every material kind",
          "[kernel][shade]") {
    std::mt19937 rng(0x5eed9);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    Scene scene;
    scene.name = "lanes";
    std::vector<MaterialKind> kinds;
    for (int k = 0; k < WP_MATERIAL_KIND_COUNT; ++k) kinds.push_back(static_cast<MaterialKind>(k));
    // Two materials of each kind: rough kinds GGX and Beckmann, separable G or not,
    // roughness from 1e-3 to 1; plastics linear and not; dielectrics entered from either side.
    for (int i = 0; i < 2 * WP_MATERIAL_KIND_COUNT; ++i) {
        Material m;
        m.kind = kinds[std::size_t(i % WP_MATERIAL_KIND_COUNT)];
        m.albedo = {u01(rng), u01(rng), u01(rng)};
        m.alpha = std::pow(10.0f, -3.0f * u01(rng));
        if (m.kind == MaterialKind::Glossy) m.alpha = std::max(m.alpha, 1e-2f);
        m.distribution = i / WP_MATERIAL_KIND_COUNT == 0 ? MicrofacetModel::GGX : MicrofacetModel::Beckmann;
        m.separable_g = i / WP_MATERIAL_KIND_COUNT == 1;
        m.ior = i % 2 ? 1.5f : 1.0f / 1.33f;
        m.specular = {0.5f + 0.5f * u01(rng), 1.0f, 0.9f};
        m.eta = {0.2f + 2 * u01(rng), 0.9f, 1.1f};
        m.k = {3 * u01(rng), 2.5f, 0.5f};
        m.nonlinear = i / WP_MATERIAL_KIND_COUNT == 1;
        scene.materials.push_back(m);
        const auto v = static_cast<std::uint32_t>(scene.positions.size());
        scene.positions.insert(scene.positions.end(), {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
        scene.triangles.push_back({v, v + 1, v + 2});
        scene.material_ids.push_back(std::uint32_t(i));
    }
    const SceneUpload up = upload_scene(scene);
    REQUIRE_FALSE(up.material_tables.empty());  // the rough plastics' tables
    int next = 0;
    ShadeCase base = random_lane_case(rng, [&](int) { return up.materials[std::size_t(next++) % up.materials.size()]; });
    base.tables = up.material_tables;
    check_lanes_match_scalar(base, kinds);
}
