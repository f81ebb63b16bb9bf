#include "support.h"

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <thread>

#include "render/loop.h"
#include "render/wavefront.h"
#include "shared/triangle.h"

namespace wp::test {

ocl::Device& device() {
    // Never destroyed: the context is not released at exit. Oclgrind 21.10 corrupts its
    // heap when a context that built two or more programs is released (abort in
    // clReleaseContext, after every test has passed); the OS frees everything anyway.
    static ocl::Device* dev = [] {
        const char* sel = std::getenv("WP_TEST_DEVICE");
        return new ocl::Device(ocl::Device::open(sel ? sel : ""));
    }();
    return *dev;
}

glm::vec3 Rng::unit_vector() {
    float z = uniform(-1.0f, 1.0f);
    float phi = uniform(0.0f, 6.2831853f);
    float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    return {r * std::cos(phi), r * std::sin(phi), z};
}

Ray make_ray(glm::vec3 o, glm::vec3 d, float tmin, float tmax) {
    return Ray{{o.x, o.y, o.z, tmin}, {d.x, d.y, d.z, tmax}};
}

std::vector<Ray> random_rays(std::size_t n, std::uint64_t seed, glm::vec3 lo, glm::vec3 hi) {
    Rng rng(seed);
    std::vector<Ray> rays(n);
    glm::vec3 c = 0.5f * (lo + hi);
    float radius = 0.75f * glm::length(hi - lo) + 1e-3f;
    for (std::size_t i = 0; i < n; ++i) {
        glm::vec3 inside{rng.uniform(lo.x, hi.x), rng.uniform(lo.y, hi.y), rng.uniform(lo.z, hi.z)};
        glm::vec3 o, d;
        if (i % 2 == 0) {
            o = inside;
            d = rng.unit_vector();
        } else {
            o = c + radius * rng.unit_vector();
            d = inside - o;
        }
        if (i % 8 == 1 || i % 8 == 4) {
            // Axis-parallel: zero one or two components, with either sign of zero.
            int a = static_cast<int>(rng.next() % 3);
            d[a] = (rng.next() & 1) ? 0.0f : -0.0f;
            if (i % 8 == 4) d[(a + 1) % 3] = (rng.next() & 1) ? 0.0f : -0.0f;
            if (glm::length(d) == 0.0f) d[(a + 2) % 3] = 1.0f;
        }
        rays[i] = make_ray(o, d);
    }
    return rays;
}

std::vector<Hit> brute_force(std::span<const glm::vec3> positions, std::span<const glm::uvec3> tris,
                             const std::vector<Ray>& rays, bool any_hit) {
    std::vector<Hit> hits(rays.size());
    auto work = [&](std::size_t begin, std::size_t end) {
        for (std::size_t r = begin; r < end; ++r) {
            const Ray& ray = rays[r];
            TriRay tr = wp_tri_ray(ray);
            Hit h{ray.dir.w, -1, 0.0f, 0.0f};
            for (std::size_t i = 0; i < tris.size(); ++i) {
                auto v = [&](int k) {
                    glm::vec3 p = positions[tris[i][k]];
                    return float4{p.x, p.y, p.z, 0.0f};
                };
                float t, u, v2;
                if (!wp_intersect_triangle(&tr, v(0), v(1), v(2), &t, &u, &v2)) continue;
                if (t < h.t) {  // scene order: at equal t the earlier (smaller) index stays
                    h = Hit{t, static_cast<int>(i), u, v2};
                    if (any_hit) break;
                }
            }
            hits[r] = h;
        }
    };
    unsigned nt = std::max(1u, std::thread::hardware_concurrency());
    std::vector<std::thread> threads;
    std::size_t chunk = (rays.size() + nt - 1) / nt;
    for (unsigned t = 0; t < nt; ++t) {
        std::size_t b = t * chunk, e = std::min(rays.size(), b + chunk);
        if (b < e) threads.emplace_back(work, b, e);
    }
    for (auto& t : threads) t.join();
    return hits;
}


Measure measure(const Scene& s, long mat) {
    Measure m;
    for (std::size_t i = 0; i < s.triangles.size(); ++i) {
        if (mat >= 0 && s.material_ids[i] != std::uint32_t(mat)) continue;
        const auto& t = s.triangles[i];
        glm::dvec3 a(s.positions[t.x]), b(s.positions[t.y]), c(s.positions[t.z]);
        glm::dvec3 n = glm::cross(b - a, c - a);
        m.area += 0.5 * glm::length(n);
        m.normal_sum += 0.5 * n;
        m.volume += glm::dot(a, glm::cross(b, c)) / 6.0;
        ++m.triangles;
        for (const auto& p : {a, b, c}) {
            m.lo = glm::min(m.lo, p);
            m.hi = glm::max(m.hi, p);
        }
    }
    return m;
}


std::map<std::string, long> readme_counts(const std::filesystem::path& readme) {
    std::ifstream in(readme);
    std::map<std::string, long> out;
    std::string line;
    const std::regex row(R"(^\| \[([a-z0-9-]+)\]\([^)]*\) \| ([0-9,]+)( \(\+([0-9,]+)[^)]*\))?)");
    auto num = [](std::string s) {
        s.erase(std::remove(s.begin(), s.end(), ','), s.end());
        return std::stol(s);
    };
    std::smatch m;
    while (std::getline(in, line))
        if (std::regex_search(line, m, row))
            out[m[1]] = num(m[2]) + (m[4].matched ? num(m[4]) : 0);
    return out;
}

std::vector<std::filesystem::path> shared_scene_files(const std::filesystem::path& root,
                                                      const std::string& file) {
    std::vector<std::filesystem::path> out;
    for (const auto& e : std::filesystem::directory_iterator(root))
        if (e.is_directory() && std::filesystem::exists(e.path() / file)) out.push_back(e.path() / file);
    std::sort(out.begin(), out.end());
    return out;
}

float texel_at(const Texture& t, int x, int y, int c) {
    const std::size_t i = (std::size_t(y) * std::size_t(t.width) + std::size_t(x)) * 4 + std::size_t(c);
    return t.is_float() ? t.texelsf.at(i) : float(t.texels8.at(i)) / 255.0f;
}


std::string base64(const std::string& in) {
    static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    std::size_t i = 0;
    for (; i + 2 < in.size(); i += 3) {
        std::uint32_t v = (std::uint8_t(in[i]) << 16) | (std::uint8_t(in[i + 1]) << 8) | std::uint8_t(in[i + 2]);
        for (int k = 3; k >= 0; --k) out.push_back(t[(v >> (6 * k)) & 63]);
    }
    if (i + 1 == in.size()) {
        std::uint32_t v = std::uint8_t(in[i]) << 16;
        out += {t[(v >> 18) & 63], t[(v >> 12) & 63], '=', '='};
    } else if (i + 2 == in.size()) {
        std::uint32_t v = (std::uint8_t(in[i]) << 16) | (std::uint8_t(in[i + 1]) << 8);
        out += {t[(v >> 18) & 63], t[(v >> 12) & 63], t[(v >> 6) & 63], '='};
    }
    return out;
}

SmokeRender smoke_render(const Scene& s, int spp, int depth) {
    render::RenderSettings rs;
    rs.width = 32;
    rs.height = std::max(1, 32 * s.camera.height / s.camera.width);
    rs.depth = depth;
    rs.seed = 1;
    render::Wavefront wf(device(), s, rs);
    render::LoopOptions lo;
    lo.spp = spp;
    render::render_frames(wf, lo, nullptr);
    SmokeRender r;
    for (float x : wf.resolve().rgb) {
        r.nonfinite += !std::isfinite(x);
        r.sum += x;
    }
    for (int c : wf.counters()) r.counters += c;
    return r;
}

}  // namespace wp::test
