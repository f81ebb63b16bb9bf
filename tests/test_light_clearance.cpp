// test_light_clearance.cpp — shadow segments that end at the light's clearance
// (scene/light_clearance.h, kernels/shared/offset.h wp_shadow_end_clear).
//
//  * [unit] triangle_distance against a second implementation: the exact minimum of the
//    convex problem by enumerating its active sets (each pair of faces of the two triangles,
//    vertices, edges or the triangles themselves, solved in their affine hulls; a solution
//    inside both counts), and closed forms;
//  * [unit] the clearances of made scenes against their geometry: the built-in box's light
//    sees the ceiling 2 cm above it, a sphere light touches itself, an occluder sets it;
//  * [hard][unit] random lights with occluders from 1e-6 to 3 light sizes away, coplanar
//    neighbours and touching triangles, at scales 1e-3 to 1e4: every shadow segment cut at
//    the clearance meets an occluder exactly when the whole segment does (brute force with
//    the shared watertight test), and with four times the clearance some do not (the test
//    has teeth);
//  * [render] the built-in box and a lamp under a shade render the same image bit for bit
//    with and without the clearance, in both shade kernels.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <tuple>
#include <vector>

#include "bvh/build.h"
#include "bvh/flatten.h"
#include "render/loop.h"
#include "render/wavefront.h"
#include "scene/builtin.h"
#include "scene/light_clearance.h"
#include "scene/procedural.h"
#include "shared/offset.h"
#include "shared/lights.h"
#include "shared/triangle.h"
#include "support.h"

using namespace wp;

namespace {

using glm::dvec3;

// Solves the n x n system m x = r (n <= 4) by Gaussian elimination with partial pivoting;
// false when a pivot falls below tiny (a singular or nearly singular system).
bool solve(int n, double m[4][5], double* x, double tiny) {
    for (int c = 0; c < n; ++c) {
        int p = c;
        for (int r = c + 1; r < n; ++r)
            if (std::fabs(m[r][c]) > std::fabs(m[p][c])) p = r;
        if (std::fabs(m[p][c]) <= tiny) return false;
        for (int k = 0; k <= n; ++k) std::swap(m[c][k], m[p][k]);
        for (int r = 0; r < n; ++r) {
            if (r == c) continue;
            const double f = m[r][c] / m[c][c];
            for (int k = c; k <= n; ++k) m[r][k] -= f * m[c][k];
        }
    }
    for (int c = 0; c < n; ++c) x[c] = m[c][n] / m[c][c];
    return true;
}

// The exact distance of two triangles as a convex quadratic program: the minimum of
// |P - Q| over P in a, Q in b lies in the relative interior of some face of each (a vertex,
// an edge or the triangle); for every pair of faces solve the unconstrained problem in their
// affine hulls and keep solutions whose barycentric weights are all >= 0.
double enumerated_distance(const dvec3 a[3], const dvec3 b[3]) {
    // Faces as vertex subsets (bit masks of 1..7).
    double scale = 0.0;
    for (int k = 0; k < 3; ++k) scale = std::max({scale, glm::length(a[k] - a[0]), glm::length(b[k] - a[0])});
    double best = 1e300;
    for (int fa = 1; fa < 8; ++fa)
        for (int fb = 1; fb < 8; ++fb) {
            std::vector<dvec3> pa, pb;
            for (int k = 0; k < 3; ++k) {
                if (fa & (1 << k)) pa.push_back(a[k]);
                if (fb & (1 << k)) pb.push_back(b[k]);
            }
            // P = pa0 + sum s_i (pa_i - pa0), Q = pb0 + sum t_j (pb_j - pb0): columns of
            // the map x -> P - Q.
            std::vector<dvec3> cols;
            for (std::size_t i = 1; i < pa.size(); ++i) cols.push_back(pa[i] - pa[0]);
            for (std::size_t j = 1; j < pb.size(); ++j) cols.push_back(-(pb[j] - pb[0]));
            const dvec3 d0 = pa[0] - pb[0];
            const int n = static_cast<int>(cols.size());
            double x[4] = {0, 0, 0, 0};
            if (n > 0) {
                double m[4][5];
                for (int r = 0; r < n; ++r) {
                    for (int c = 0; c < n; ++c) m[r][c] = glm::dot(cols[r], cols[c]);
                    m[r][n] = -glm::dot(cols[r], d0);
                }
                if (!solve(n, m, x, 1e-13 * scale * scale)) continue;
            }
            // Barycentric weights of both faces: all >= 0 (within rounding).
            const int na = static_cast<int>(pa.size()) - 1;
            double sa = 0, sb = 0;
            bool inside = true;
            for (int i = 0; i < n; ++i) {
                inside &= x[i] >= -1e-12;
                (i < na ? sa : sb) += x[i];
            }
            inside &= sa <= 1.0 + 1e-12 && sb <= 1.0 + 1e-12;
            if (!inside) continue;
            dvec3 diff = d0;
            for (int i = 0; i < n; ++i) diff += x[i] * cols[i];
            best = std::min(best, glm::length(diff));
        }
    return best;
}

dvec3 rnd3(test::Rng& rng) { return dvec3(rng.unit_vector()) * double(rng.uniform()); }

}  // namespace

TEST_CASE("light clearance: triangle distance against active-set enumeration and closed forms", "[unit]") {
    // Closed forms: parallel planes, a shared edge, a crossing, skew edges.
    const dvec3 a[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    const dvec3 up[3] = {{0.1, 0.1, 0.5}, {2, 0.1, 0.5}, {0.1, 2, 0.5}};
    CHECK(triangle_distance(a, up) == Approx(0.5).epsilon(1e-14));
    const dvec3 hinge[3] = {{0, 0, 0}, {1, 0, 0}, {0.3, -0.5, 0.8}};
    CHECK(triangle_distance(a, hinge) == 0.0);
    const dvec3 pierce[3] = {{0.2, 0.2, -1}, {0.3, 0.2, 1}, {0.2, 0.3, 1}};
    CHECK(triangle_distance(a, pierce) < 1e-15);
    // Edge (0,0,0)-(1,0,0) against edge (0.5,-1,2)-(0.5,1,2) of a triangle leaning away:
    // the closest pair is (0.5,0,0), (0.5,0,2).
    const dvec3 skew[3] = {{0.5, -1, 2}, {0.5, 1, 2}, {0.5, 0, 5}};
    const dvec3 edge_tri[3] = {{0, 0, 0}, {1, 0, 0}, {0.5, 0, -3}};
    CHECK(triangle_distance(edge_tri, skew) == Approx(2.0).epsilon(1e-14));

    test::Rng rng(0xc1ea7);
    int compared = 0, thin = 0;
    double worst = 0.0;
    for (int q = 0; q < 6000; ++q) {
        const double scale = std::pow(10.0, double(rng.uniform(-3.0f, 4.0f)));
        const dvec3 shift = (q % 3 == 0) ? dvec3(1e3, -2e3, 5e2) * scale : dvec3(0.0);
        dvec3 p[3], r[3];
        for (auto& v : p) v = rnd3(rng);
        switch (q % 8) {
            case 0:  // two random triangles
                for (auto& v : r) v = rnd3(rng) + dvec3(0.5, 0, 0);
                break;
            case 1: {  // parallel, offset along the normal
                const dvec3 n = glm::normalize(glm::cross(p[1] - p[0], p[2] - p[0]));
                const double h = std::pow(10.0, double(rng.uniform(-6.0f, 0.0f)));
                for (int k = 0; k < 3; ++k) r[k] = p[k] + 0.3 * rnd3(rng) * 0.1 + h * n;
                break;
            }
            case 2:  // sharing an edge, hinged
                r[0] = p[0], r[1] = p[1], r[2] = rnd3(rng);
                break;
            case 3:  // sharing a vertex
                r[0] = p[2], r[1] = rnd3(rng), r[2] = rnd3(rng);
                break;
            case 4: {  // thin: a sliver of aspect 1e2 .. 1e6
                for (auto& v : r) v = rnd3(rng);
                const double w = std::pow(10.0, double(rng.uniform(-6.0f, -2.0f)));
                r[2] = 0.5 * (r[0] + r[1]) + w * rnd3(rng);
                break;
            }
            case 5: {  // degenerate: collinear or a point
                r[0] = rnd3(rng), r[1] = rnd3(rng);
                r[2] = (q % 16 == 5) ? r[0] : r[0] + 0.37 * (r[1] - r[0]);
                break;
            }
            case 6: {  // coplanar, apart
                const dvec3 n = glm::normalize(glm::cross(p[1] - p[0], p[2] - p[0]));
                const dvec3 e = glm::normalize(p[1] - p[0]);
                for (int k = 0; k < 3; ++k) {
                    dvec3 s = rnd3(rng);
                    r[k] = p[k] + 1.5 * e + (s - glm::dot(s, n) * n) * 0.2;
                }
                break;
            }
            default:  // one crossing the other near its middle
                r[0] = (p[0] + p[1] + p[2]) / 3.0 + rnd3(rng) * 0.1;
                r[1] = r[0] + rnd3(rng) * 2.0;
                r[2] = r[0] - rnd3(rng) * 2.0;
                break;
        }
        for (int k = 0; k < 3; ++k) p[k] = p[k] * scale + shift, r[k] = r[k] * scale + shift;
        const double ours = triangle_distance(p, r), exact = enumerated_distance(p, r);
        INFO("case " << q << " scale " << scale << " ours " << ours << " exact " << exact);
        REQUIRE(exact < 1e299);
        // Never above the true distance (the safe side) beyond rounding ...
        CHECK(ours <= exact + 1e-12 * scale + 1e-15 * glm::length(shift));
        // ... and close to it (a thin triangle loses at most its width).
        const bool has_thin = q % 8 == 4 || q % 8 == 5;
        thin += has_thin;
        if (!has_thin) {
            CHECK(ours >= exact - 1e-9 * scale - 1e-13 * glm::length(shift));
            worst = std::max(worst, std::fabs(ours - exact) / scale);
        } else {
            CHECK(ours >= exact - 2e-2 * scale);
        }
        ++compared;
    }
    std::printf("triangle distance: %d pairs (%d thin or degenerate), largest |ours - exact| / scale %.2e\n",
                compared, thin, worst);
}

namespace {

Material emitter() {
    Material m;
    m.name = "light";
    m.albedo = glm::vec3(0.0f);
    m.emission = glm::vec3(5.0f);
    return m;
}

std::vector<int> emitting(const Scene& s) {
    std::vector<int> v;
    for (std::size_t i = 0; i < s.triangles.size(); ++i)
        if (s.triangle_emits(i)) v.push_back(static_cast<int>(i));
    return v;
}

std::vector<float> clearances_of(const Scene& s) {
    const bvh::Bvh b = bvh::build(bvh::triangle_boxes(s.positions, s.triangles));
    return light_clearances(s, b, emitting(s));
}

}  // namespace

TEST_CASE("light clearance: the clearances of made scenes follow their geometry", "[unit]") {
    {
        // The built-in box: its light 2 cm under the ceiling (behind it: no limit), both
        // triangles reaching its left edge x = -0.24, 0.76 from the left wall (the right wall
        // 0.77, the back wall 0.78, the objects below farther).
        const Scene box = make_cornell_box(2000);
        const std::vector<float> c = clearances_of(box);
        const std::vector<int> lights = emitting(box);
        REQUIRE(lights.size() == 2);
        const double gap = 1.0 - double(0.24f);
        for (int l : lights) {
            const glm::uvec3 t = box.triangles[std::size_t(l)];
            double edge = 0.0;
            for (int k = 0; k < 3; ++k)
                edge = std::max(edge, double(glm::length(box.positions[t[k]] - box.positions[t[(k + 1) % 3]])));
            CHECK(double(c[std::size_t(l)]) <= 0.99 * gap - 1e-5 * edge);
            CHECK(double(c[std::size_t(l)]) == Approx(0.99 * gap - 1e-5 * edge).epsilon(1e-6));
        }
        for (std::size_t i = 0; i < c.size(); ++i)
            if (!box.triangle_emits(i)) REQUIRE(c[i] == 0.0f);
    }
    auto longest = [](const Scene& s, std::size_t i) {
        const glm::uvec3 t = s.triangles[i];
        double e = 0.0;
        for (int k = 0; k < 3; ++k)
            e = std::max(e, glm::length(dvec3(s.positions[t[k]]) - dvec3(s.positions[t[(k + 1) % 3]])));
        return e;
    };
    {
        // A sphere light alone: every other triangle of it lies behind each triangle's plane,
        // nothing else is near, so each triangle gets the cap.
        Scene s;
        const auto light = s.add_material(emitter());
        const Mesh ball = make_icosphere(glm::vec3(0.0f), 1.0f, 2);
        s.add_mesh(ball.positions, ball.triangles, light);
        const std::vector<float> c = clearances_of(s);
        for (std::size_t i = 0; i < c.size(); ++i) {
            const double edge = longest(s, i);
            CHECK(double(c[i]) == Approx(0.99 * kClearanceCapEdges * edge - 1e-5 * edge).epsilon(1e-6));
        }
        // Turned inside out (each triangle faces the others across the ball): a concave
        // emitter, whose neighbours at its corners reach in front of it: 0.
        for (glm::uvec3& t : s.triangles) std::swap(t.y, t.z);
        for (float f : clearances_of(s)) CHECK(f == 0.0f);
    }
    // A glowing unit cube, faces outward, under a plate g above its top that overhangs it:
    // the top's and the sides' triangles get g (the plate reaches in front of their planes),
    // the bottom's the cap (the plate and the cube lie behind it).
    for (const double g : {0.05, 1e-4}) {
        INFO("gap " << g);
        Scene s;
        Material white;
        white.name = "white";
        const auto w = s.add_material(white), light = s.add_material(emitter());
        const glm::vec3 ex(1, 0, 0), ey(0, 1, 0), ez(0, 0, 1);
        for (const Mesh& f : {make_quad({0, 0, 1}, ex, ey), make_quad({0, 0, 0}, ey, ex), make_quad({0, 0, 0}, ex, ez),
                              make_quad({0, 1, 0}, ez, ex), make_quad({0, 0, 0}, ez, ey), make_quad({1, 0, 0}, ey, ez)})
            s.add_mesh(f.positions, f.triangles, light);
        const Mesh plate = make_quad({-1, -1, float(1.0 + g)}, {3, 0, 0}, {0, 3, 0});
        s.add_mesh(plate.positions, plate.triangles, w);
        const std::vector<float> c = clearances_of(s);
        const std::vector<int> lights = emitting(s);
        REQUIRE(lights.size() == 12);
        for (int l : lights) {
            const glm::uvec3 t = s.triangles[std::size_t(l)];
            const glm::vec3 a = s.positions[t.x], b = s.positions[t.y], d = s.positions[t.z];
            const glm::vec3 n = glm::normalize(glm::cross(b - a, d - a));
            INFO("face normal " << n.x << " " << n.y << " " << n.z);
            const double edge = longest(s, std::size_t(l));
            REQUIRE(edge == Approx(std::sqrt(2.0)));
            const double gap = n.z < -0.5f ? kClearanceCapEdges * edge : double(float(1.0 + g)) - 1.0;
            CHECK(double(c[std::size_t(l)]) == Approx(0.99 * gap - 1e-5 * edge).epsilon(1e-6));
        }
    }
    {
        // A quad light (edge 1) facing down, a flush ceiling around it (in its plane: no
        // limit), a wall 0.6 to its side and, optionally, a plate 0.3 below it and a
        // triangle leaning on its edge; capped at the longest edge.
        auto scene = [](bool plate, bool lean) {
            Scene s;
            Material white;
            white.name = "white";
            const auto w = s.add_material(white), light = s.add_material(emitter());
            const Mesh lamp = make_quad({0, 1, 0}, {1, 0, 0}, {0, 0, 1});  // normal -y
            s.add_mesh(lamp.positions, lamp.triangles, light);
            const Mesh ceiling = make_quad({1, 1, 0}, {2, 0, 0}, {0, 0, 1});
            s.add_mesh(ceiling.positions, ceiling.triangles, w);
            const Mesh wall = make_quad({-0.6f, 0, 0}, {0, 0, 1}, {0, 1, 0});
            s.add_mesh(wall.positions, wall.triangles, w);
            if (plate) {
                const Mesh p = make_quad({0.2f, 0.7f, 0.2f}, {0.1f, 0, 0}, {0, 0, 0.1f});
                s.add_mesh(p.positions, p.triangles, w);
            }
            if (lean) s.add_mesh({{0, 1, 0}, {1, 1, 0}, {0.5f, 0.5f, -0.3f}}, {{0, 1, 2}}, w);
            return s;
        };
        const double edge = std::sqrt(2.0);
        for (auto [plate, lean, gap] : {std::tuple{true, false, 1.0 - double(0.7f)}, std::tuple{false, false, 0.6},
                                        std::tuple{true, true, 0.0}}) {
            INFO("plate " << plate << ", leaning triangle " << lean);
            const Scene s = scene(plate, lean);
            const std::vector<float> c = clearances_of(s);
            REQUIRE(emitting(s).size() == 2);
            for (int l : emitting(s)) {
                if (gap == 0.0)
                    CHECK(c[std::size_t(l)] == 0.0f);
                else
                    CHECK(double(c[std::size_t(l)]) == Approx(0.99 * gap - 1e-5 * edge).epsilon(1e-6));
            }
        }
    }
}

namespace {

float3 f3(const glm::vec3& v) { return make_float3(v.x, v.y, v.z); }
float4 f4(const glm::vec3& v) { return make_float4(v.x, v.y, v.z, 0.0f); }

struct Occlusion {
    long segments = 0, cut = 0, blocked = 0, mismatches = 0, mismatches_wide = 0;
};

// One random scene: a light (a quad of 2 triangles, a coplanar fan, a quad on a box or a
// sphere) of size `size` at `origin`, turned at random; occluders near it; shadow segments from random receivers in
// front of it to points sampled on it, traced by brute force with and without the cut.
void trace_scene(test::Rng& rng, double size, glm::dvec3 origin, Occlusion& o) {
    Scene s;
    Material white;
    white.name = "white";
    const auto w = s.add_material(white), light = s.add_material(emitter());
    const dvec3 n = dvec3(rng.unit_vector());
    const dvec3 e1 = glm::normalize(glm::cross(n, std::fabs(n.x) < 0.9 ? dvec3(1, 0, 0) : dvec3(0, 1, 0)));
    const dvec3 e2 = glm::cross(n, e1);  // (e1, e2, n) right-handed: the light faces n
    auto at = [&](double u, double v, double h) { return glm::vec3(origin + size * (u * e1 + v * e2 + h * n)); };
    // Light: corners (0,0) (1,0) (1,1) (0,1), as a quad, a fan around its centre or the
    // quad on top of a closed box 0.5 deep behind it; or a convex emitter, a sphere of
    // diameter 1 under that square touching it at its centre.
    std::vector<glm::vec3> lp;
    std::vector<glm::uvec3> lt;
    const float kind = rng.uniform();
    if (kind < 0.3f) {
        lp = {at(0, 0, 0), at(1, 0, 0), at(1, 1, 0), at(0, 1, 0)};
        lt = {{0, 1, 2}, {0, 2, 3}};
    } else if (kind < 0.55f) {
        lp = {at(0.5, 0.5, 0), at(0, 0, 0), at(1, 0, 0), at(1, 1, 0), at(0, 1, 0)};
        lt = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 1}};
    } else if (kind < 0.8f) {
        lp = {at(0, 0, 0), at(1, 0, 0), at(1, 1, 0), at(0, 1, 0)};
        lt = {{0, 1, 2}, {0, 2, 3}};
        s.add_mesh({at(0, 0, 0), at(1, 0, 0), at(1, 1, 0), at(0, 1, 0), at(0, 0, -0.5), at(1, 0, -0.5),
                    at(1, 1, -0.5), at(0, 1, -0.5)},
                   {{4, 6, 5}, {4, 7, 6}, {0, 5, 1}, {0, 4, 5}, {1, 6, 2}, {1, 5, 6}, {2, 7, 3}, {2, 6, 7},
                    {3, 4, 0}, {3, 7, 4}},
                   w);
    } else {
        const Mesh ball = make_icosphere(at(0.5, 0.5, -0.5), float(0.5 * size), 1);
        lp = ball.positions;
        lt = ball.triangles;
    }
    s.add_mesh(lp, lt, light);
    // A flush ceiling around the light (the same plane, up to rounding) half the time.
    if (rng.uniform() < 0.5f)
        s.add_mesh({at(1, -1, 0), at(2, -1, 0), at(2, 2, 0), at(1, 2, 0)}, {{0, 1, 2}, {0, 2, 3}}, w);
    // Occluders: small plates and random triangles at distances 1e-6 .. 3 light sizes in
    // front of (or behind) the light, over it or beside it; sometimes one touching its edge.
    const int count = 1 + int(rng.uniform() * 6.0f);
    for (int k = 0; k < count; ++k) {
        const double d = std::pow(10.0, double(rng.uniform(-6.0f, 0.5f)));
        const double side = rng.uniform() < 0.85f ? 1.0 : -1.0;
        const double cu = double(rng.uniform(-0.25f, 1.25f)), cv = double(rng.uniform(-0.25f, 1.25f));
        const double r = std::pow(10.0, double(rng.uniform(-3.0f, 0.0f)));
        if (rng.uniform() < 0.5f) {  // a plate parallel to the light
            s.add_mesh({at(cu - r, cv - r, side * d), at(cu + r, cv - r, side * d), at(cu + r, cv + r, side * d),
                        at(cu - r, cv + r, side * d)},
                       {{0, 1, 2}, {0, 2, 3}}, w);
        } else {  // a random triangle around a point at that height
            const glm::vec3 c = at(cu, cv, side * d);
            s.add_mesh({c + glm::vec3(size * r * dvec3(rng.unit_vector())), c + glm::vec3(size * r * dvec3(rng.unit_vector())),
                        c + glm::vec3(size * r * dvec3(rng.unit_vector()))},
                       {{0, 1, 2}}, w);
        }
    }
    if (rng.uniform() < 0.2f)  // leaning on the light's edge (u = 1)
        s.add_mesh({at(1, 0, 0), at(1, 1, 0), at(1.3, 0.5, 0.4)}, {{0, 1, 2}}, w);

    const std::vector<int> lights = emitting(s);
    const std::vector<float> clear = clearances_of(s);
    for (int q = 0; q < 300; ++q) {
        const int l = lights[std::size_t(rng.uniform() * float(lights.size())) % lights.size()];
        const glm::uvec3 t = s.triangles[std::size_t(l)];
        const float3 l0 = f3(s.positions[t.x]), l1 = f3(s.positions[t.y]), l2 = f3(s.positions[t.z]);
        const float3 ln = normalize(cross(l1 - l0, l2 - l0));
        const float2 bl = wp_sample_triangle_barycentric(rng.uniform(), rng.uniform());
        float3 yerr;
        const float3 y = wp_hit_point(l0, l1, l2, bl.x, bl.y, &yerr);
        // A receiver in front of the light triangle: 0.01 to 100 light sizes away, any
        // direction into its front half-space. One in five behind it instead, which shade
        // never pushes: the cut must leave those alone (wp_shadow_end_clear's side test).
        dvec3 dir = dvec3(rng.unit_vector());
        const bool behind = rng.uniform() < 0.2f;
        if ((glm::dot(dir, dvec3(ln.x, ln.y, ln.z)) < 0.0) != behind) dir = -dir;
        const double dist = size * std::pow(10.0, double(rng.uniform(-2.0f, 2.0f)));
        const glm::vec3 pv(dvec3(y.x, y.y, y.z) + dist * dir);
        const float3 org = f3(pv);
        const float3 sd = y - org;
        if (!behind && !(-dot(normalize(sd), ln) > 0.0f)) continue;  // shade.cl pushes no segment
        const float tmax = wp_shadow_tmax(sd, yerr, ln, wp_triangle_offset(l0, l1, l2));
        const float cut = wp_shadow_end_clear(tmax, sd, y, yerr, ln, clear[std::size_t(l)]);
        const float wide = wp_shadow_end_clear(tmax, sd, y, yerr, ln, 4.0f * clear[std::size_t(l)]);
        const TriRay r_full = wp_tri_ray(Ray{{org.x, org.y, org.z, 0}, {sd.x, sd.y, sd.z, tmax}});
        const TriRay r_cut = wp_tri_ray(Ray{{org.x, org.y, org.z, 0}, {sd.x, sd.y, sd.z, cut}});
        const TriRay r_wide = wp_tri_ray(Ray{{org.x, org.y, org.z, 0}, {sd.x, sd.y, sd.z, wide}});
        bool hit_full = false, hit_cut = false, hit_wide = false;
        for (const glm::uvec3& tk : s.triangles) {
            const float4 a = f4(s.positions[tk.x]), b = f4(s.positions[tk.y]), c = f4(s.positions[tk.z]);
            float th, u, v;
            hit_full |= wp_intersect_triangle(&r_full, a, b, c, &th, &u, &v) && th < tmax;
            hit_cut |= wp_intersect_triangle(&r_cut, a, b, c, &th, &u, &v) && th < cut;
            hit_wide |= wp_intersect_triangle(&r_wide, a, b, c, &th, &u, &v) && th < wide;
        }
        ++o.segments;
        o.cut += cut < tmax;
        o.blocked += hit_full;
        o.mismatches += hit_full != hit_cut;
        o.mismatches_wide += hit_full != hit_wide;
    }
}

}  // namespace

// Criterion: 0 segments whose occlusion changes with the cut; most segments are cut; with
// four times the clearance some occlusion changes (occluders sit just beyond it).
TEST_CASE("hard: shadow segments cut at the light's clearance meet what the whole segments meet",
          "[hard][unit]") {
    test::Rng rng(0x5eedc1ea);
    Occlusion o;
    for (int scene = 0; scene < 1000; ++scene) {
        const double size = std::pow(10.0, double(rng.uniform(-3.0f, 4.0f)));
        const glm::dvec3 origin = (scene % 4 == 0) ? glm::dvec3(rng.unit_vector()) * 1e3 * size : glm::dvec3(0.0);
        trace_scene(rng, size, origin, o);
    }
    std::printf("clearance cut: %ld segments, %ld cut, %ld blocked, %ld changed (%ld with 4x the clearance)\n",
                o.segments, o.cut, o.blocked, o.mismatches, o.mismatches_wide);
    CHECK(o.segments > 250000);
    CHECK(o.mismatches == 0);
    CHECK(o.cut > o.segments / 3);
    CHECK(o.blocked > o.segments / 20);
    CHECK(o.mismatches_wide > 0);
}

// The renders: the built-in box (its light cleared), a lamp under a shade 1e-3 below it and
// a sphere light, with every NEE estimator, both shade kernels: the same film bit for bit.
TEST_CASE("render: shadow segments cut at the light's clearance give the same image bit for bit",
          "[render]") {
    auto render = [](const Scene& scene, render::Sampling sampling, bool lanes, bool clearance,
                     std::size_t* cleared) {
        render::RenderSettings s;
        s.width = 40;
        s.height = 30;
        s.depth = 3;
        s.seed = 9;
        s.estimator.sampling = sampling;
        s.shade_lanes = lanes;
        s.light_clearance = clearance;
        render::Wavefront wf(test::device(), scene, s);
        *cleared = wf.stats().cleared_lights;
        render::LoopOptions lo;
        lo.spp = 4;
        render::render_frames(wf, lo, nullptr);
        return wf.film();
    };
    // A sphere light (the quad light off) inside the box: a convex emitter, every triangle
    // of it cleared; turned inside out, a concave one with nothing cleared.
    auto ball_scene = [](bool inside_out) {
        Scene ball = make_cornell_box(200);
        Material glow = emitter();
        const auto m = ball.add_material(glow);
        Mesh b = make_icosphere(glm::vec3(0.0f, 1.5f, 0.0f), 0.2f, 2);
        if (inside_out)
            for (glm::uvec3& t : b.triangles) std::swap(t.y, t.z);
        ball.add_mesh(b.positions, b.triangles, m);
        for (std::size_t i = 0; i < ball.triangles.size(); ++i)  // the quad light off
            if (ball.triangle_emits(i) && ball.material_ids[i] != m) ball.material_ids[i] = ball.material_ids[0];
        return ball;
    };
    Scene box = make_cornell_box(2000);
    Scene lamp = make_cornell_box(2000);
    Scene ball = ball_scene(false);
    {
        Material shade;
        shade.name = "shade";
        const auto m = lamp.add_material(shade);
        const Mesh plate = make_quad({-0.1f, 1.979f, -0.1f}, {0.2f, 0, 0}, {0, 0, 0.2f});
        lamp.add_mesh(plate.positions, plate.triangles, m);
    }
    for (const Scene* scene : {&box, &lamp, &ball})
        for (auto sampling : {render::Sampling::Mis, render::Sampling::Nee})
            for (bool lanes : {true, false}) {
                INFO((scene == &box ? "box" : scene == &lamp ? "lamp" : "ball")
                     << ", " << render::sampling_name(sampling) << (lanes ? ", lanes" : ", scalar"));
                std::size_t on = 0, off = 1;
                auto a = render(*scene, sampling, lanes, true, &on);
                auto b = render(*scene, sampling, lanes, false, &off);
                CHECK(on == (scene == &ball ? 320u : 2u));
                CHECK(off == 0);
                REQUIRE(a.size() == b.size());
                CHECK(std::memcmp(a.data(), b.data(), a.size() * sizeof(FilmPixel)) == 0);
            }
    // Compiled only where some light has a clearance: the box's, not an inside-out sphere's.
    render::RenderSettings s;
    s.width = 8;
    s.height = 6;
    CHECK(render::Wavefront(test::device(), box, s).config().clear_shadow_ends());
    const Scene hollow = ball_scene(true);
    render::Wavefront wf(test::device(), hollow, s);
    CHECK(wf.stats().light_triangles > 0);
    CHECK(wf.stats().cleared_lights == 0);
    CHECK_FALSE(wf.config().clear_shadow_ends());
    CHECK(wf.options().find("WP_HAVE_LIGHT_CLEARANCE") == std::string::npos);
}
