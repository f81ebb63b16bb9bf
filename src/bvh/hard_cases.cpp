#include "bvh/hard_cases.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "bvh/build.h"
#include "bvh/flatten.h"
#include "cl/profiler.h"
#include "shared/offset.h"
#include "util/splitmix.h"
#include "util/timer.h"

namespace wp::bvh {

namespace {

// A height field of n x n cells of size 2 whose vertices lie on integer coordinates far
// from the origin (x, y in 1024 + 2i, -2048 + 2j; z in {512, 513}), diagonals alternating.
Mesh height_field(int n, std::vector<bool>& interior) {
    Mesh m;
    auto idx = [n](int i, int j) { return static_cast<unsigned>(j * (n + 1) + i); };
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            float h = ((i * 7 + j * 13) % 3 == 0) ? 1.0f : 0.0f;
            m.positions.push_back({1024.0f + 2.0f * i, -2048.0f + 2.0f * j, 512.0f + h});
            interior.push_back(i > 0 && j > 0 && i < n && j < n);
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            unsigned a = idx(i, j), b = idx(i + 1, j), c = idx(i + 1, j + 1), d = idx(i, j + 1);
            if ((i + j) % 2 == 0) {
                m.triangles.push_back({a, b, c});
                m.triangles.push_back({a, c, d});
            } else {
                m.triangles.push_back({a, b, d});
                m.triangles.push_back({b, c, d});
            }
        }
    return m;
}

Ray make_ray(glm::vec3 o, glm::vec3 d) { return Ray{{o.x, o.y, o.z, 0.0f}, {d.x, d.y, d.z, FLT_MAX}}; }

}  // namespace

std::vector<glm::vec3> shared_segments(const Mesh& m, const std::vector<bool>* interior) {
    std::map<std::pair<unsigned, unsigned>, int> edges;
    for (const auto& t : m.triangles)
        for (int k = 0; k < 3; ++k) {
            unsigned a = t[k], b = t[(k + 1) % 3];
            edges[{std::min(a, b), std::max(a, b)}] += 1;
        }
    std::vector<glm::vec3> seg;
    auto inside = [&](unsigned v) { return !interior || (*interior)[v]; };
    for (const auto& [e, n] : edges)
        if (n >= 2 && inside(e.first) && inside(e.second)) {
            seg.push_back(m.positions[e.first]);
            seg.push_back(m.positions[e.second]);
        }
    for (unsigned v = 0; v < m.positions.size(); ++v)
        if (inside(v)) {
            seg.push_back(m.positions[v]);
            seg.push_back(m.positions[v]);
        }
    return seg;
}

std::vector<WatertightCase> watertight_cases(bool small) {
    std::vector<WatertightCase> cases;
    {
        WatertightCase c;
        c.name = "uv-sphere";
        c.center = {0.3f, -0.2f, 0.1f};
        c.mesh = small ? make_uv_sphere(c.center, 1.0f, 8, 12) : make_uv_sphere(c.center, 1.0f, 200, 300);
        c.segments = shared_segments(c.mesh);
        c.mode = 0;
        c.inner = 0.5f;
        cases.push_back(std::move(c));
    }
    {
        WatertightCase c;
        c.name = "split-quad-cube";
        glm::vec3 lo{-1.5f, -0.5f, -1.0f}, hi{0.5f, 1.5f, 1.0f};
        c.mesh = make_box(lo, hi, small ? 3 : 64);
        c.segments = shared_segments(c.mesh);
        c.center = 0.5f * (lo + hi);
        c.mode = 0;
        c.inner = 0.5f;
        cases.push_back(std::move(c));
    }
    {
        WatertightCase c;
        c.name = "integer-grid-height-field";
        std::vector<bool> interior;
        c.mesh = height_field(small ? 6 : 256, interior);
        c.segments = shared_segments(c.mesh, &interior);
        c.mode = 1;
        c.radius = 10.0f;
        cases.push_back(std::move(c));
    }
    {
        WatertightCase c;
        c.name = "two-triangle-square";
        c.mesh.positions = {{-5, -5, 0}, {5, -5, 0}, {5, 5, 0}, {-5, 5, 0}};
        c.mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
        c.segments = {{-5, -5, 0}, {5, 5, 0}};  // the shared diagonal
        c.mode = 1;
        c.radius = 11.0f;
        c.smin = 0.02f;
        c.smax = 0.98f;
        cases.push_back(std::move(c));
    }
    return cases;
}

HardProbe::HardProbe(const ocl::Device& dev, BatchTracer& tracer)
    : dev_(dev), tracer_(tracer), program_(ocl::Program::build(dev, "test_hard.cl")) {
    gen_ = ocl::Kernel(program_, "hard_edge_rays", "hard.edge_rays");
    count_ = ocl::Kernel(program_, "hard_count", "hard.count");
}

void HardProbe::enqueue_edge_rays(const WatertightCase& c, const ::cl::Buffer& seg, std::uint32_t seed,
                                  int first_segment, std::uint32_t round, int count,
                                  const ::cl::Buffer& rays) {
    gen_.launch({&dev_.queue}, static_cast<std::size_t>(count), seg,
                static_cast<int>(c.segments.size() / 2), c.center.x, c.center.y, c.center.z, c.inner,
                c.radius, c.smin, c.smax, c.mode, static_cast<cl_uint>(seed), first_segment,
                static_cast<cl_uint>(round), count, rays);
}

namespace {
::cl::Buffer upload_segments(const ocl::Device& dev, const std::vector<glm::vec3>& s) {
    std::vector<float4> v;
    for (const auto& p : s) v.push_back(float4{p.x, p.y, p.z, 0.0f});
    return ocl::upload_buffer(dev, v, "the hard-case segments");
}
}  // namespace

std::vector<Ray> HardProbe::edge_rays(const WatertightCase& c, int count, std::uint32_t seed) {
    ::cl::Buffer seg = upload_segments(dev_, c.segments);
    ::cl::Buffer rays = dev_.create_buffer(CL_MEM_READ_WRITE, std::max(1, count) * sizeof(Ray), "the edge rays");
    enqueue_edge_rays(c, seg, seed, 0, 0, count, rays);
    std::vector<Ray> out(count);
    dev_.queue.enqueueReadBuffer(rays, CL_TRUE, 0, count * sizeof(Ray), out.data());
    return out;
}

HardCount HardProbe::watertight(const WatertightCase& c, std::uint64_t rays, TraceVariant v, std::uint32_t seed,
                                int batch) {
    auto flat = flatten(build(triangle_boxes(c.mesh.positions, c.mesh.triangles)), c.mesh.positions,
                        c.mesh.triangles);
    DeviceBvh bvh = DeviceBvh::upload(dev_, flat);
    ::cl::Buffer seg = upload_segments(dev_, c.segments);
    int cap = static_cast<int>(std::min<std::uint64_t>(rays, static_cast<std::uint64_t>(batch)));
    cap = std::max(cap, 1);
    dev_.check_alloc(static_cast<std::uint64_t>(cap) * (sizeof(Ray) + sizeof(Hit)), "the hard-case rays");
    ::cl::Buffer rb = dev_.create_buffer(CL_MEM_READ_WRITE, cap * sizeof(Ray), "the hard-case rays");
    ::cl::Buffer hb = dev_.create_buffer(CL_MEM_READ_WRITE, cap * sizeof(Hit), "the hard-case hits");
    ::cl::Buffer cnt = dev_.create_buffer(CL_MEM_READ_WRITE, 4 * sizeof(int), "the hard-case counts");
    HardCount r;
    Timer timer;
    for (std::uint64_t first = 0; first < rays; first += cap) {
        int n = static_cast<int>(std::min<std::uint64_t>(cap, rays - first));
        int zero[4] = {0, 0, 0, 0};
        dev_.queue.enqueueWriteBuffer(cnt, CL_FALSE, 0, sizeof(zero), zero);
        std::uint64_t nseg = c.segments.size() / 2;
        // (the round: only its low bits matter)
        enqueue_edge_rays(c, seg, seed, static_cast<int>(first % nseg),
                          static_cast<std::uint32_t>(first / nseg), n, rb);
        tracer_.enqueue(bvh, rb, n, hb, v);
        count_.launch({&dev_.queue}, static_cast<std::size_t>(n), hb, n, cnt);
        int out[4];
        dev_.queue.enqueueReadBuffer(cnt, CL_TRUE, 0, sizeof(out), out);
        r.misses += static_cast<std::uint64_t>(out[0]);
        r.nonfinite += static_cast<std::uint64_t>(out[1]);
        r.nonpositive += static_cast<std::uint64_t>(out[2]);
        r.rays += static_cast<std::uint64_t>(n);
    }
    r.seconds = timer.ms() * 1e-3;
    return r;
}

glm::vec3 leave_surface(glm::vec3 v0, glm::vec3 v1, glm::vec3 v2, float u, float v, glm::vec3 n) {
    auto f3 = [](glm::vec3 a) { return make_float3(a.x, a.y, a.z); };
    float3 err;
    float3 p = wp_hit_point(f3(v0), f3(v1), f3(v2), u, v, &err);
    float3 q = wp_offset_ray_origin(p, err, f3(n), wp_triangle_offset(f3(v0), f3(v1), f3(v2)));
    return {q.x, q.y, q.z};
}

std::vector<Ray> camera_rays(glm::vec3 eye, glm::vec3 target, glm::vec3 up_hint, float vfov_deg, int w, int h) {
    glm::vec3 fwd = glm::normalize(target - eye);
    glm::vec3 right = glm::normalize(glm::cross(fwd, up_hint));
    glm::vec3 up = glm::cross(right, fwd);
    float th = std::tan(glm::radians(vfov_deg) * 0.5f);
    float aspect = static_cast<float>(w) / static_cast<float>(h);
    std::vector<Ray> rays;
    rays.reserve(static_cast<std::size_t>(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float sx = (2.0f * (x + 0.5f) / w - 1.0f) * th * aspect;
            float sy = (1.0f - 2.0f * (y + 0.5f) / h) * th;
            rays.push_back(make_ray(eye, fwd + sx * right + sy * up));
        }
    return rays;
}

SelfHitCount self_intersections(const ocl::Device& dev, BatchTracer& tracer, const Mesh& mesh,
                                const std::vector<Ray>& primary, float scale, glm::vec3 shift, std::uint64_t seed) {
    Mesh m = mesh;
    for (auto& p : m.positions) p = p * scale + shift;
    auto flat = flatten(build(triangle_boxes(m.positions, m.triangles)), m.positions, m.triangles);
    DeviceBvh bvh = DeviceBvh::upload(dev, flat);
    SelfHitCount out;
    {
        glm::dvec3 lo(1e300), hi(-1e300);
        for (const auto& p : m.positions) {
            lo = glm::min(lo, glm::dvec3(p));
            hi = glm::max(hi, glm::dvec3(p));
        }
        out.extent = m.positions.empty() ? 0.0 : glm::length(hi - lo);
    }
    std::vector<Ray> prim = primary;
    for (auto& r : prim) {
        glm::vec3 o = glm::vec3(r.org.x, r.org.y, r.org.z) * scale + shift;
        r.org = float4{o.x, o.y, o.z, r.org.w};
    }
    auto hits = tracer.trace(bvh, prim, TraceVariant::Stackless);
    std::vector<Ray> second;
    std::vector<int> source;
    second.reserve(hits.size() * 3);
    SplitMix64 rng(seed);
    for (std::size_t i = 0; i < hits.size(); ++i) {
        const Hit& h = hits[i];
        if (h.prim < 0) continue;
        ++out.primary_hits;
        const auto& t = m.triangles[h.prim];
        glm::vec3 v0 = m.positions[t.x], v1 = m.positions[t.y], v2 = m.positions[t.z];
        glm::vec3 p = (v0 + (v1 - v0) * h.u) + (v2 - v0) * h.v;  // as wp_hit_point
        glm::dvec3 nd = glm::cross(glm::dvec3(v1) - glm::dvec3(v0), glm::dvec3(v2) - glm::dvec3(v0));
        glm::vec3 n = glm::vec3(glm::normalize(nd));
        glm::vec3 d = glm::normalize(glm::vec3(prim[i].dir.x, prim[i].dir.y, prim[i].dir.z));
        if (glm::dot(n, d) > 0.0f) n = -n;  // the side the ray came from
        glm::vec3 o = leave_surface(v0, v1, v2, h.u, h.v, n);
        out.max_offset = std::max(out.max_offset, glm::length(glm::dvec3(o) - glm::dvec3(p)));
        // Tangent frame.
        glm::vec3 a = std::fabs(n.x) > 0.5f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
        glm::vec3 tx = glm::normalize(glm::cross(a, n)), ty = glm::cross(n, tx);
        // Cosine-distributed (Malley) and uniform hemisphere directions.
        float u1 = rng.uniform(), u2 = rng.uniform();
        float r = std::sqrt(u1), phi = 6.2831853f * u2;
        glm::vec3 dc = r * std::cos(phi) * tx + r * std::sin(phi) * ty + std::sqrt(std::max(0.0f, 1.0f - u1)) * n;
        float z = rng.uniform(), phi2 = 6.2831853f * rng.uniform();
        float s = std::sqrt(std::max(0.0f, 1.0f - z * z));
        glm::vec3 du = s * std::cos(phi2) * tx + s * std::sin(phi2) * ty + z * n;
        glm::vec3 dm = d - 2.0f * glm::dot(d, n) * n;
        for (glm::vec3 dd : {dc, du, dm}) {
            second.push_back(make_ray(o, dd));
            source.push_back(h.prim);
        }
    }
    auto sh = tracer.trace(bvh, second, TraceVariant::Stackless);
    out.rays = second.size();
    for (std::size_t i = 0; i < sh.size(); ++i) {
        if (sh[i].prim == source[i]) ++out.same_triangle;
        if (sh[i].prim >= 0 && !std::isfinite(sh[i].t)) ++out.nonfinite;
    }
    return out;
}

}  // namespace wp::bvh
