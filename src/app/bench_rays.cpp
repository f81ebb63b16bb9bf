#include "app/bench_rays.h"

#include <cmath>

#include "bvh/hard_cases.h"
#include "util/splitmix.h"

namespace wp::app {

namespace {

Ray ray(glm::vec3 o, glm::vec3 d, float tmax = FLT_MAX) {
    return Ray{{o.x, o.y, o.z, 0.0f}, {d.x, d.y, d.z, tmax}};
}

}  // namespace

std::vector<Ray> primary_rays(const Camera& cam) {
    glm::vec3 fwd = glm::normalize(cam.target - cam.position);
    glm::vec3 right = glm::normalize(glm::cross(fwd, cam.up));
    glm::vec3 up = glm::cross(right, fwd);
    float th = std::tan(glm::radians(cam.vfov_deg) * 0.5f);
    float aspect = static_cast<float>(cam.width) / static_cast<float>(cam.height);
    std::vector<Ray> rays;
    rays.reserve(static_cast<std::size_t>(cam.width) * cam.height);
    for (int y = 0; y < cam.height; ++y) {
        for (int x = 0; x < cam.width; ++x) {
            float sx = (2.0f * (x + 0.5f) / cam.width - 1.0f) * th * aspect;
            float sy = (1.0f - 2.0f * (y + 0.5f) / cam.height) * th;
            rays.push_back(ray(cam.position, fwd + sx * right + sy * up));
        }
    }
    return rays;
}

RaySets make_ray_sets(const Scene& scene, const std::vector<Ray>& primary, const std::vector<Hit>& hits,
                      std::uint64_t seed) {
    RaySets out;
    out.primary = primary;
    // Emissive triangles with their areas, for light sampling by area.
    std::vector<std::size_t> lights;
    std::vector<double> cdf;
    double total = 0.0;
    for (std::size_t i = 0; i < scene.triangles.size(); ++i) {
        if (!scene.triangle_emits(i)) continue;
        const auto& t = scene.triangles[i];
        glm::vec3 a = scene.positions[t.x], b = scene.positions[t.y], c = scene.positions[t.z];
        total += 0.5 * glm::length(glm::cross(b - a, c - a));
        lights.push_back(i);
        cdf.push_back(total);
    }
    SplitMix64 rng(seed);
    for (std::size_t i = 0; i < primary.size(); ++i) {
        const Hit& h = hits[i];
        if (h.prim < 0) continue;
        const Ray& r = primary[i];
        glm::vec3 o{r.org.x, r.org.y, r.org.z}, d{r.dir.x, r.dir.y, r.dir.z};
        const auto& t = scene.triangles[h.prim];
        glm::vec3 a = scene.positions[t.x], b = scene.positions[t.y], c = scene.positions[t.z];
        glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
        if (glm::dot(n, d) > 0.0f) n = -n;  // the side the ray came from
        glm::vec3 origin = bvh::leave_surface(a, b, c, h.u, h.v, n);
        // Cosine-weighted direction about n (Malley's method).
        float u1 = rng.uniform(), u2 = rng.uniform();
        float rad = std::sqrt(u1), phi = 6.2831853f * u2;
        glm::vec3 tx = glm::normalize(std::fabs(n.x) > 0.5f ? glm::cross(n, glm::vec3(0, 1, 0))
                                                            : glm::cross(n, glm::vec3(1, 0, 0)));
        glm::vec3 ty = glm::cross(n, tx);
        glm::vec3 dir = rad * std::cos(phi) * tx + rad * std::sin(phi) * ty + std::sqrt(std::max(0.0f, 1.0f - u1)) * n;
        out.diffuse.push_back(ray(origin, dir));
        if (!lights.empty()) {
            double x = rng.uniform() * total;
            std::size_t k = std::lower_bound(cdf.begin(), cdf.end(), x) - cdf.begin();
            const auto& lt = scene.triangles[lights[std::min(k, lights.size() - 1)]];
            float s1 = rng.uniform(), s2 = rng.uniform();
            float su = std::sqrt(s1);
            glm::vec3 q = (1.0f - su) * scene.positions[lt.x] + su * (1.0f - s2) * scene.positions[lt.y] +
                          su * s2 * scene.positions[lt.z];
            out.shadow.push_back(ray(origin, q - origin, 0.9999f));
        }
    }
    return out;
}

}  // namespace wp::app
