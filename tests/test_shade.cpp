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
#include <map>
#include <string>
#include <numeric>
#include <vector>

#include <glm/glm.hpp>

#include "render/stages/shade.h"
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
    scene.material_ids = ocl::Array<int>::upload(dev, c.material_ids, "material ids");
    scene.materials = ocl::Array<MaterialData>::upload(dev, c.materials, "materials");
    scene.background = c.background;
    scene.light_cdf = ocl::Array<float>::upload(dev, c.light_cdf, "light cdf");
    scene.light_prims = ocl::Array<int>::upload(dev, c.light_prims, "light prims");
    scene.light_pdf_area = ocl::Array<float>::upload(dev, c.light_pdf_area, "light pdf");
    scene.light_count = static_cast<int>(c.light_prims.size());
    render::ShadowQueue shadow;
    shadow.rays = ocl::Array<Ray>::allocate(dev, n, "shadow rays");
    shadow.items = ocl::Array<int>::allocate(dev, n, "shadow items");
    shadow.contrib = ocl::Array<float4>::allocate(dev, n, "shadow contrib");
    shadow.count = ocl::Array<int>::zeros(dev, 1, "shadow count");
    auto radiance = ocl::Array<float4>::zeros(dev, c.pixels, "radiance");
    auto counters = ocl::Array<int>::zeros(dev, WP_COUNTER_COUNT, "counters");
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
        CHECK(p.flags == WP_PATH_SPECULAR);
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
