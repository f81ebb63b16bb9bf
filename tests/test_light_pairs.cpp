// test_light_pairs.cpp — back-to-back pairs of light triangles (scene/light_pairs.h): which
// triangles pair, and the densities the light table gives them. The renders that check the
// paired estimator against Lambert's formula are in test_hard_lights.cpp; the lane kernel's
// bits against the scalar one's with pairs in test_shade.cpp.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "scene/light_pairs.h"
#include "scene/procedural.h"
#include "scene/upload.h"

using namespace wp;

namespace {

std::uint32_t lamp(Scene& s, glm::vec3 le) {
    Material m;
    m.name = "lamp";
    m.emission = le;
    return s.add_material(m);
}

glm::dvec3 centroid(const Scene& s, std::size_t t) {
    const glm::uvec3& v = s.triangles[t];
    return (glm::dvec3(s.positions[v.x]) + glm::dvec3(s.positions[v.y]) + glm::dvec3(s.positions[v.z])) / 3.0;
}

glm::dvec3 normal(const Scene& s, std::size_t t) {
    const glm::uvec3& v = s.triangles[t];
    glm::dvec3 a(s.positions[v.x]), b(s.positions[v.y]), c(s.positions[v.z]);
    return glm::cross(b - a, c - a);
}

// Brute force: the triangle in [first, last) other than t whose centroid lies nearest to the
// reflection of t's centroid through `centre`.
std::size_t nearest_to_reflection(const Scene& s, std::size_t t, std::size_t first, std::size_t last,
                                  glm::dvec3 centre) {
    const glm::dvec3 target = 2.0 * centre - centroid(s, t);
    std::size_t best = t;
    double best_d = INFINITY;
    for (std::size_t j = first; j < last; ++j) {
        if (j == t) continue;
        const double d = glm::length(centroid(s, j) - target);
        if (d < best_d) best = j, best_d = d;
    }
    return best;
}

}  // namespace

TEST_CASE("light pairs: closed symmetric lights pair every triangle with its antipode", "[scene][lights]") {
    struct Case {
        const char* name;
        Mesh mesh;
        glm::vec3 centre;
    };
    const glm::vec3 c(0.3f, -1.2f, 2.5f);
    for (const Case& k : {Case{"icosphere", make_icosphere(c, 0.7f, 3), c},
                          Case{"uv sphere", make_uv_sphere(c, 0.5f, 6, 12), c},
                          Case{"box", make_box(c - glm::vec3(0.5f, 1.0f, 2.0f), c + glm::vec3(0.5f, 1.0f, 2.0f), 3), c}}) {
        Scene s;
        s.add_mesh(k.mesh.positions, k.mesh.triangles, lamp(s, {1, 2, 3}));
        const std::vector<int> partner = find_light_partners(s);
        const std::size_t n = s.triangles.size();
        int paired = 0, mutual = 0, opposite = 0, antipodal = 0;
        for (std::size_t t = 0; t < n; ++t) {
            if (partner[t] < 0) continue;
            ++paired;
            const auto q = static_cast<std::size_t>(partner[t]);
            mutual += partner[q] == static_cast<int>(t);
            opposite += glm::dot(normal(s, t), normal(s, q)) < 0.0;
            antipodal += q == nearest_to_reflection(s, t, 0, n, glm::dvec3(k.centre));
        }
        INFO(k.name << ": " << n << " triangles, " << paired << " paired");
        CHECK(mutual == paired);
        CHECK(opposite == paired);
        if (k.name == std::string("uv sphere")) {
            // Its bands' diagonals do not mirror: most triangles still pair, with a near
            // neighbour of the reflection.
            CHECK(paired >= static_cast<int>(n) * 9 / 10);
        } else {
            CHECK(paired == static_cast<int>(n));
            CHECK(antipodal == paired);
        }
    }
}

TEST_CASE("light pairs: pairs stay within one emitter; flat and unlit meshes get none",
          "[scene][lights]") {
    Scene s;
    const std::uint32_t bright = lamp(s, {4, 4, 4}), dim = lamp(s, {0.5f, 0.2f, 0.1f});
    Material grey;
    grey.name = "grey";
    const std::uint32_t unlit = s.add_material(grey);
    // Two sphere lights side by side (a reflection through the pair's common centre would
    // land on the other sphere), a quad light, an open dome, an unlit sphere.
    const glm::vec3 a(-1.0f, 0.0f, 0.0f), b(1.0f, 0.0f, 0.0f);
    Mesh sa = make_icosphere(a, 0.4f, 2), sb = make_uv_sphere(b, 0.3f, 4, 8);
    const std::size_t a0 = s.add_mesh(sa.positions, sa.triangles, bright);
    const std::size_t b0 = s.add_mesh(sb.positions, sb.triangles, dim);
    Mesh quad = make_quad({0.0f, 2.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f}, 2, 2);
    const std::size_t q0 = s.add_mesh(quad.positions, quad.triangles, bright);
    Mesh cap = make_icosphere({0.0f, -3.0f, 0.0f}, 0.5f, 2);
    std::vector<glm::uvec3> upper;
    for (const glm::uvec3& t : cap.triangles)
        if (cap.positions[t.x].y > -3.0f && cap.positions[t.y].y > -3.0f && cap.positions[t.z].y > -3.0f)
            upper.push_back(t);
    const std::size_t c0 = s.add_mesh(cap.positions, upper, bright);
    Mesh grey_sphere = make_icosphere({0.0f, 3.0f, 3.0f}, 0.5f, 1);
    const std::size_t g0 = s.add_mesh(grey_sphere.positions, grey_sphere.triangles, unlit);
    const std::size_t end = s.triangles.size();
    REQUIRE(a0 == 0);
    const std::vector<int> partner = find_light_partners(s);
    REQUIRE(partner.size() == end);
    auto range_of = [&](std::size_t t) { return t < b0 ? 0 : t < q0 ? 1 : t < c0 ? 2 : t < g0 ? 3 : 4; };
    int crossing = 0, quad_paired = 0, cap_paired = 0, unlit_paired = 0, sphere_paired = 0;
    for (std::size_t t = 0; t < end; ++t) {
        if (partner[t] < 0) continue;
        crossing += range_of(t) != range_of(static_cast<std::size_t>(partner[t]));
        quad_paired += range_of(t) == 2;
        cap_paired += range_of(t) == 3;
        unlit_paired += range_of(t) == 4;
        sphere_paired += range_of(t) <= 1;
    }
    CHECK(crossing == 0);
    CHECK(quad_paired == 0);  // coplanar: no triangle faces the other way
    CHECK(unlit_paired == 0);
    CHECK(sphere_paired >= static_cast<int>(b0 + (q0 - b0) * 9 / 10));  // the icosphere all, the UV sphere most
    // The open dome pairs opposite sides of itself (a side seen from behind gives its samples
    // to one seen from the front), within itself (crossing above).
    CHECK(cap_paired > 0);

    // The table's paired densities: P(partner) / area, P from the power fractions.
    const LightTable plain = build_light_table(s), lt = build_light_table(s, true);
    CHECK(plain.pairs.empty());
    REQUIRE(lt.pairs.size() == end);
    CHECK(lt.cdf == plain.cdf);
    CHECK(lt.pdf_area == plain.pdf_area);
    auto area = [&](std::size_t t) { return 0.5 * glm::length(normal(s, t)); };
    double total = 0.0;
    std::vector<double> power(end, 0.0);
    for (std::size_t t = 0; t < end; ++t) {
        if (!is_light_triangle(s, t)) continue;
        const glm::vec3 le = s.materials[s.material_ids[t]].emission;
        power[t] = area(t) * (0.2126 * le.x + 0.7152 * le.y + 0.0722 * le.z);
        total += power[t];
    }
    int bad = 0;
    for (std::size_t t = 0; t < end; ++t) {
        const LightPair p = lt.pairs[t];
        if (p.partner != partner[t]) ++bad;
        if (p.partner < 0) {
            bad += p.pdf != 0.0f;
            continue;
        }
        // In probability: the float CDF's differences are within 2^-22 of the fractions.
        const double want = power[static_cast<std::size_t>(p.partner)] / total;
        bad += !(std::abs(p.pdf * area(t) - want) < 3e-7 + 1e-6 * want);
    }
    CHECK(bad == 0);
}
