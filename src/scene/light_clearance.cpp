#include "scene/light_clearance.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <future>
#include <limits>
#include <thread>
#include <unordered_map>

namespace wp {

namespace {

using glm::dvec3;

// A triangle thinner than this share of its longest edge squared (twice its area below
// 1e-3 l^2: an aspect ratio beyond ~1000) is measured as its three edges: closest-point
// barycentrics lose about 1e-16 l^4 / (2A)^2 of their precision, which stays below 1e-10
// above it. Its points lie within its width 2A / l of its edges, which the distance then
// subtracts, so it never comes out larger than the true one.
constexpr double kThin = 1e-3;

double longest_edge(const dvec3 t[3]) {
    return std::sqrt(std::max({glm::dot(t[1] - t[0], t[1] - t[0]), glm::dot(t[2] - t[0], t[2] - t[0]),
                               glm::dot(t[2] - t[1], t[2] - t[1])}));
}

// Width of a thin triangle (twice its area over its longest edge), or -1 if it is not thin.
double thin_width(const dvec3 t[3]) {
    const double l = longest_edge(t);
    const double twice_area = glm::length(glm::cross(t[1] - t[0], t[2] - t[0]));
    if (!(twice_area >= kThin * l * l)) return l > 0.0 ? twice_area / l : 0.0;
    return -1.0;
}

// The point of triangle (a, b, c) closest to p: Ericson, "Real-Time Collision Detection"
// (2005), 5.1.5, by the Voronoi region of p. Always a point of the triangle. Not for thin
// triangles (thin_width).
dvec3 closest_on_triangle(const dvec3& p, const dvec3& a, const dvec3& b, const dvec3& c) {
    const dvec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) return a;
    const dvec3 bp = p - b;
    const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) return b;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + ab * (d1 / (d1 - d3));
    const dvec3 cp = p - c;
    const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) return c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + ac * (d2 / (d2 - d6));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0)
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    const double denom = 1.0 / (va + vb + vc);
    return a + ab * (vb * denom) + ac * (vc * denom);
}

// Distance between segments (p1, q1) and (p2, q2): Ericson 5.1.9, the closest points
// clamped to both segments (points of both). Nearly parallel segments (the cross term below
// 1e-12 of the product of their squared lengths) take s = 0 and the best t for it, then the
// best s for that t: within ~1e-6 of their lengths of the distance.
double segment_distance(const dvec3& p1, const dvec3& q1, const dvec3& p2, const dvec3& q2) {
    const dvec3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
    const double a = glm::dot(d1, d1), e = glm::dot(d2, d2), f = glm::dot(d2, r);
    double s = 0.0, t = 0.0;
    if (a <= 0.0 && e <= 0.0) return glm::length(p1 - p2);
    if (a <= 0.0) {
        t = std::clamp(f / e, 0.0, 1.0);
    } else {
        const double c = glm::dot(d1, r);
        if (e <= 0.0) {
            s = std::clamp(-c / a, 0.0, 1.0);
        } else {
            const double b = glm::dot(d1, d2);
            const double denom = a * e - b * b;
            if (denom > 1e-12 * a * e) s = std::clamp((b * f - c * e) / denom, 0.0, 1.0);
            t = (b * s + f) / e;
            if (t < 0.0) {
                t = 0.0;
                s = std::clamp(-c / a, 0.0, 1.0);
            } else if (t > 1.0) {
                t = 1.0;
                s = std::clamp((b - c) / a, 0.0, 1.0);
            }
        }
    }
    return glm::length((p1 + d1 * s) - (p2 + d2 * t));
}

// Distance between segment (p, q) and a triangle that is not thin: its ends against the
// triangle, the segment against the triangle's edges, and where it crosses (or touches)
// the triangle's plane, that point against the triangle (0 where it passes through).
double segment_triangle_distance(const dvec3& p, const dvec3& q, const dvec3 t[3]) {
    double d = std::min(glm::length(p - closest_on_triangle(p, t[0], t[1], t[2])),
                        glm::length(q - closest_on_triangle(q, t[0], t[1], t[2])));
    for (int k = 0; k < 3; ++k) d = std::min(d, segment_distance(p, q, t[k], t[(k + 1) % 3]));
    const dvec3 n = glm::cross(t[1] - t[0], t[2] - t[0]);
    const double dp = glm::dot(n, p - t[0]), dq = glm::dot(n, q - t[0]);
    if ((dp <= 0.0 && dq >= 0.0) || (dp >= 0.0 && dq <= 0.0)) {
        const double s = dp != dq ? std::clamp(dp / (dp - dq), 0.0, 1.0) : 0.0;
        const dvec3 x = p + (q - p) * s;
        d = std::min(d, glm::length(x - closest_on_triangle(x, t[0], t[1], t[2])));
    }
    return d;
}

struct Box {
    dvec3 lo, hi;
};

double box_distance(const Box& a, const Aabb& b) {
    double s = 0.0;
    for (int k = 0; k < 3; ++k) {
        const double gap = std::max({0.0, double(b.lo[k]) - a.hi[k], a.lo[k] - double(b.hi[k])});
        s += gap * gap;
    }
    return std::sqrt(s);
}

// Every vertex of triangle t at most tol in front of the plane through p with unit normal n
// (in the plane, or behind it).
bool behind(const dvec3 t[3], const dvec3& p, const dvec3& n, double tol) {
    return glm::dot(n, t[0] - p) <= tol && glm::dot(n, t[1] - p) <= tol && glm::dot(n, t[2] - p) <= tol;
}

// Every point of box b at most tol in front of that plane.
bool behind(const Aabb& b, const dvec3& p, const dvec3& n, double tol) {
    double s = 0.0;
    for (int k = 0; k < 3; ++k) s += n[k] * ((n[k] > 0.0 ? double(b.hi[k]) : double(b.lo[k])) - p[k]);
    return s <= tol;
}

std::uint64_t position_key(const glm::vec3& p) {
    const std::uint64_t x = std::bit_cast<std::uint32_t>(p.x), y = std::bit_cast<std::uint32_t>(p.y),
                        z = std::bit_cast<std::uint32_t>(p.z);
    return (x * 0x9E3779B97F4A7C15ull) ^ (y * 0xC2B2AE3D27D4EB4Full) ^ (z * 0x165667B19E3779F9ull);
}

}  // namespace

double triangle_distance(const dvec3 a[3], const dvec3 b[3]) {
    const double wa = thin_width(a), wb = thin_width(b);
    double d = std::numeric_limits<double>::infinity();
    if (wa < 0.0 && wb < 0.0) {
        // Each edge of one against the other triangle covers every closest pair: vertex
        // against face (the edge's ends), edge against edge, and crossing.
        for (int k = 0; k < 3; ++k) {
            d = std::min(d, segment_triangle_distance(a[k], a[(k + 1) % 3], b));
            d = std::min(d, segment_triangle_distance(b[k], b[(k + 1) % 3], a));
        }
        return d;
    }
    // A thin triangle as its edges, less its width (never above the true distance).
    for (int i = 0; i < 3; ++i) {
        if (wa >= 0.0 && wb >= 0.0) {
            for (int j = 0; j < 3; ++j)
                d = std::min(d, segment_distance(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3]));
        } else if (wa >= 0.0) {
            d = std::min(d, segment_triangle_distance(a[i], a[(i + 1) % 3], b));
        } else {
            d = std::min(d, segment_triangle_distance(b[i], b[(i + 1) % 3], a));
        }
    }
    return std::max(0.0, d - std::max(wa, 0.0) - std::max(wb, 0.0));
}

std::vector<float> light_clearances(const Scene& scene, const bvh::Bvh& bvh, std::span<const int> lights) {
    std::vector<float> out(scene.triangles.size(), 0.0f);
    if (bvh.nodes.empty()) return out;
    auto corners = [&](std::size_t i, dvec3 t[3]) {
        const glm::uvec3 v = scene.triangles[i];
        for (int k = 0; k < 3; ++k) t[k] = dvec3(scene.positions[v[k]]);
    };
    // The light triangles at each vertex position: a light that shares a corner with one
    // reaching in front of its plane (a concave emitter's fold) has clearance 0 without a
    // search.
    std::unordered_multimap<std::uint64_t, int> at_corner;
    at_corner.reserve(lights.size() * 3);
    for (const int light : lights)
        for (int k = 0; k < 3; ++k)
            at_corner.emplace(position_key(scene.positions[scene.triangles[static_cast<std::size_t>(light)][k]]), light);
    auto clearance = [&](const int light, std::vector<int>& stack) -> float {
        dvec3 l[3];
        corners(static_cast<std::size_t>(light), l);
        const double edge = longest_edge(l);
        const dvec3 cr = glm::cross(l[1] - l[0], l[2] - l[0]);
        const double len = glm::length(cr);
        if (!(len > 0.0) || !std::isfinite(edge)) return 0.0f;  // no plane: clearance 0
        const dvec3 n = cr / len;  // the front: the emitting side
        const double plane_tol = 1e-7 * edge;
        Box box{glm::min(l[0], glm::min(l[1], l[2])), glm::max(l[0], glm::max(l[1], l[2]))};
        for (int k = 0; k < 3; ++k) {
            const glm::vec3 corner = scene.positions[scene.triangles[static_cast<std::size_t>(light)][k]];
            const auto range = at_corner.equal_range(position_key(corner));
            for (auto it = range.first; it != range.second; ++it) {
                if (it->second == light) continue;
                dvec3 t[3];
                corners(static_cast<std::size_t>(it->second), t);
                if (!behind(t, l[0], n, plane_tol) &&
                    (t[0] == dvec3(corner) || t[1] == dvec3(corner) || t[2] == dvec3(corner)))
                    return 0.0f;
            }
        }
        double best = kClearanceCapEdges * edge;  // the cap (light_clearance.h)
        stack.assign(1, 0);
        while (!stack.empty() && best > 0.0) {
            const bvh::Node& node = bvh.nodes[static_cast<std::size_t>(stack.back())];
            stack.pop_back();
            // A box wholly behind L's plane holds nothing the segment can meet.
            if (box_distance(box, node.box) >= best || behind(node.box, l[0], n, plane_tol)) continue;
            if (!node.leaf()) {
                // The nearer child on top: neighbours are found first, and prune the rest.
                const double dl = box_distance(box, bvh.nodes[static_cast<std::size_t>(node.left)].box);
                const double dr = box_distance(box, bvh.nodes[static_cast<std::size_t>(node.right)].box);
                stack.push_back(dl <= dr ? node.right : node.left);
                stack.push_back(dl <= dr ? node.left : node.right);
                continue;
            }
            for (int k = node.first; k < node.first + node.count; ++k) {
                const std::size_t j = bvh.prim_order[static_cast<std::size_t>(k)];
                if (j == static_cast<std::size_t>(light)) continue;
                dvec3 t[3];
                corners(j, t);
                // Triangles in L's plane or behind it cannot be met by a segment that ends
                // before that plane on its front side.
                if (behind(t, l[0], n, plane_tol)) continue;
                best = std::min(best, triangle_distance(l, t));
            }
        }
        // Margins: 1 % and 1e-5 of the edge for the rounding above (each term is within
        // ~1e-6 of the edge of the true distance), then a float no larger than that.
        const double c = 0.99 * best - 1e-5 * edge;
        if (!(c > 0.0)) return 0.0f;
        float f = static_cast<float>(c);
        if (double(f) > c) f = std::nextafter(f, 0.0f);
        return f;
    };
    // The lights are independent searches of a shared, read-only BVH: one interleaved share
    // of them per hardware thread.
    const std::size_t threads = lights.size() < 256 ? 1 : std::max(1u, std::thread::hardware_concurrency());
    auto share = [&](std::size_t first) {
        std::vector<int> stack;
        for (std::size_t i = first; i < lights.size(); i += threads)
            out[static_cast<std::size_t>(lights[i])] = clearance(lights[i], stack);
    };
    std::vector<std::future<void>> others;
    for (std::size_t t = 1; t < threads; ++t) others.push_back(std::async(std::launch::async, share, t));
    share(0);
    for (auto& f : others) f.get();
    return out;
}

}  // namespace wp
