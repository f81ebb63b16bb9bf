// test_generate.cpp — the generate stage alone: camera rays against a host camera model.
//
// The model below is written from the camera definition (Scene::Camera: position, target,
// up, vertical fov; image y downwards from the top-left corner) in double precision,
// independently of scene/upload and kernels/shared/camera.h.
#include <catch2/catch.hpp>

#include <cmath>
#include <map>
#include <tuple>
#include <vector>

#include <glm/glm.hpp>

#include "render/stages/generate.h"
#include "scene/upload.h"
#include "shared/types.h"
#include "support.h"

using namespace wp;

namespace {

struct GenerateOut {
    std::vector<Ray> rays;
    std::vector<PathState> paths;
    std::vector<float4> radiance;
    int count = 0;
    std::vector<int> counters;
};

// The stage with one item per work-item (GPUs, the CUDA port) or eight (lanes: CPUs), with or
// without the thin-lens program (WP_HAVE_LENS) and non-temporal stores (WP_STREAM_STORES).
render::GenerateStage& generate_stage(bool lanes, bool lens = false, bool stream = false) {
    static std::map<std::tuple<bool, bool, bool>, render::GenerateStage> stages;
    const auto key = std::make_tuple(lanes, lens, stream);
    auto it = stages.find(key);
    if (it == stages.end()) {
        render::KernelConfig c;
        c.generate_lanes = lanes;
        c.lens = lens;
        c.stream_stores = stream;
        it = stages.emplace(key, render::GenerateStage(test::device(), c)).first;
    }
    return it->second;
}

// Runs the generate stage through its launcher: a wave of `count` samples from
// (first_pixel, sample); count = 0 means one whole pass. With `active`: generate_camera_active
// over that pixel list from entry first_pixel on.
GenerateOut run_generate(const CameraData& cam, cl_uint seed, cl_uint sample, int first_pixel = 0,
                         int count = 0, bool lanes = false, const std::vector<int>* active = nullptr,
                         bool lens_program = false, bool stream = false) {
    auto& dev = test::device();
    render::GenerateStage& stage = generate_stage(lanes, lens_program, stream);
    const int n = cam.width * cam.height;
    if (count == 0) count = n;
    const auto items = static_cast<std::size_t>(count);
    render::PathQueue q;
    q.rays = ocl::Array<Ray>::allocate(dev, items, "rays");
    q.paths = ocl::Array<PathState>::allocate(dev, items, "paths");
    q.count = ocl::Array<int>::zeros(dev, 1, "count");
    auto radiance = ocl::Array<float4>::upload(dev, std::vector<float4>(items, float4{7, 7, 7, 7}),
                                               "radiance");  // generate must clear it
    auto counters = ocl::Array<int>::zeros(dev, WP_COUNTER_COUNT, "counters");
    if (active) {
        auto list = ocl::Array<int>::upload(dev, *active, "active pixels");
        stage.enqueue_active(cam, seed, list, first_pixel, static_cast<int>(active->size()), sample, count, q,
                             radiance, counters);
    } else {
        stage.enqueue(cam, seed, first_pixel, sample, count, q, radiance, counters);
    }
    GenerateOut out;
    out.rays = q.rays.read(dev);
    out.paths = q.paths.read(dev);
    out.radiance = radiance.read(dev);
    out.count = q.count.read(dev)[0];
    out.counters = counters.read(dev);
    return out;
}

// Host pinhole model: the unit direction through image position (px, py) in pixels.
glm::dvec3 model_direction(const Camera& c, int w, int h, double px, double py) {
    glm::dvec3 pos(c.position), target(c.target), up(c.up);
    glm::dvec3 f = glm::normalize(target - pos);
    glm::dvec3 r = glm::normalize(glm::cross(f, up));
    glm::dvec3 u = glm::cross(r, f);
    double th = std::tan(c.vfov_deg * 0.5 * M_PI / 180.0);
    double aspect = double(w) / double(h);
    double sx = (2.0 * px / w - 1.0) * th * aspect;
    double sy = (1.0 - 2.0 * py / h) * th;
    return glm::normalize(f + sx * r + sy * u);
}

// Image position (px, py) a direction points at, by projecting onto the image plane.
glm::dvec2 model_project(const Camera& c, int w, int h, glm::dvec3 d) {
    glm::dvec3 pos(c.position), target(c.target), up(c.up);
    glm::dvec3 f = glm::normalize(target - pos);
    glm::dvec3 r = glm::normalize(glm::cross(f, up));
    glm::dvec3 u = glm::cross(r, f);
    double th = std::tan(c.vfov_deg * 0.5 * M_PI / 180.0);
    double aspect = double(w) / double(h);
    d /= glm::dot(d, f);
    double sx = glm::dot(d, r) / (th * aspect), sy = glm::dot(d, u) / th;
    return {(sx + 1.0) * 0.5 * w, (1.0 - sy) * 0.5 * h};
}

Camera test_camera() {
    Camera c;
    c.position = {0.3f, 1.1f, 3.7f};
    c.target = {-0.2f, 0.9f, 0.1f};
    c.up = {0.05f, 1.0f, 0.0f};  // not orthogonal to the view direction on purpose
    c.vfov_deg = 47.0f;
    return c;
}

}  // namespace

TEST_CASE("generate: pixel-centre rays match the host camera model", "[kernel][generate]") {
    Camera c = test_camera();
    const int w = 64, h = 48;
    GenerateOut g = run_generate(upload_camera(c, w, h, /*jitter=*/false), 3, 5);
    CHECK(g.count == w * h);
    CHECK(g.counters[WP_COUNTER_GENERATE_NONFINITE] == 0);
    const int picks[][2] = {{0, 0}, {w - 1, 0}, {0, h - 1}, {w - 1, h - 1}, {w / 2, h / 2}, {17, 31}};
    for (auto& pk : picks) {
        int x = pk[0], y = pk[1], p = y * w + x;
        INFO("pixel (" << x << ", " << y << ")");
        const Ray& r = g.rays[p];
        CHECK(r.org.x == c.position.x);
        CHECK(r.org.y == c.position.y);
        CHECK(r.org.z == c.position.z);
        CHECK(r.org.w == 0.0f);      // tmin
        CHECK(r.dir.w == FLT_MAX);   // tmax: FLT_MAX sentinel, never INFINITY
        glm::dvec3 d = model_direction(c, w, h, x + 0.5, y + 0.5);
        CHECK(std::abs(r.dir.x - d.x) < 1e-6);
        CHECK(std::abs(r.dir.y - d.y) < 1e-6);
        CHECK(std::abs(r.dir.z - d.z) < 1e-6);
    }
    // Every slot: its own pixel, sample and item, unit throughput, cleared radiance.
    for (int p = 0; p < w * h; ++p) {
        REQUIRE(g.paths[p].pixel == p);
        REQUIRE(g.paths[p].sample == 5u);
        REQUIRE(g.paths[p].item == p);
        REQUIRE(g.paths[p].cone == 0.0f);
        REQUIRE(g.paths[p].throughput.w == 0.0f);  // no BSDF density yet
        REQUIRE(g.paths[p].throughput.x == 1.0f);
        REQUIRE(g.paths[p].throughput.z == 1.0f);
        REQUIRE(g.radiance[p].x == 0.0f);
        REQUIRE(g.radiance[p].w == 0.0f);
    }
}

TEST_CASE("generate: jittered rays stay inside their pixel and depend only on the key",
          "[kernel][generate]") {
    Camera c = test_camera();
    const int w = 64, h = 48;
    CameraData cam = upload_camera(c, w, h, /*jitter=*/true);
    GenerateOut a = run_generate(cam, 11, 0);
    GenerateOut b = run_generate(cam, 11, 0);
    GenerateOut other = run_generate(cam, 11, 1);
    int moved = 0;
    for (int p = 0; p < w * h; ++p) {
        int x = p % w, y = p / w;
        glm::dvec3 d(a.rays[p].dir.x, a.rays[p].dir.y, a.rays[p].dir.z);
        glm::dvec2 q = model_project(c, w, h, d);
        REQUIRE(q.x > x - 1e-4);
        REQUIRE(q.x < x + 1 + 1e-4);
        REQUIRE(q.y > y - 1e-4);
        REQUIRE(q.y < y + 1 + 1e-4);
        REQUIRE(std::memcmp(&a.rays[p], &b.rays[p], sizeof(Ray)) == 0);  // same key, same ray
        moved += a.rays[p].dir.x != other.rays[p].dir.x;
    }
    CHECK(moved > w * h * 9 / 10);  // another sample index gives other positions
}

TEST_CASE("generate: a wave of several passes or part of one gives each sample the rays of its "
          "own pass", "[kernel][generate]") {
    // The path pool cuts the sample sequence s = sample * pixels + pixel into waves; every
    // sample must get the same ray, pixel and sample number whatever wave it falls in.
    Camera c = test_camera();
    const int w = 16, h = 12, n = w * h;
    CameraData cam = upload_camera(c, w, h, /*jitter=*/true);
    const cl_uint seed = 9;
    std::vector<GenerateOut> single;  // one whole pass per call: the reference
    for (cl_uint s = 4; s < 7; ++s) single.push_back(run_generate(cam, seed, s));
    // Three passes in one wave.
    GenerateOut multi = run_generate(cam, seed, 4, 0, 3 * n);
    CHECK(multi.count == 3 * n);
    for (int i = 0; i < 3 * n; ++i) {
        int pass = i / n, p = i % n;
        REQUIRE(multi.paths[i].pixel == p);
        REQUIRE(multi.paths[i].sample == cl_uint(4 + pass));
        REQUIRE(multi.paths[i].item == i);
        REQUIRE(std::memcmp(&multi.rays[i], &single[pass].rays[p], sizeof(Ray)) == 0);
    }
    // A chunk of pass 5: pixels 50 .. 50 + 37.
    GenerateOut chunk = run_generate(cam, seed, 5, 50, 37);
    CHECK(chunk.count == 37);
    for (int i = 0; i < 37; ++i) {
        REQUIRE(chunk.paths[i].pixel == 50 + i);
        REQUIRE(chunk.paths[i].sample == 5u);
        REQUIRE(chunk.paths[i].item == i);
        REQUIRE(std::memcmp(&chunk.rays[i], &single[1].rays[50 + i], sizeof(Ray)) == 0);
    }
}

TEST_CASE("generate: eight items per work-item give each item the ray and path of one item per "
          "work-item", "[kernel][generate]") {
    // The lane kernel (CPUs) against the scalar one (GPUs, the CUDA port), and both against
    // the wave definition: item i is sample s = first + i of the pass sequence. Counts that
    // are not multiples of 8, images smaller than 8 pixels (a lane group spans passes), both
    // samplers' default (Sobol) with jitter, and the active-pixel list.
    Camera c = test_camera();
    struct Case {
        int w, h, first, count;
    };
    const Case cases[] = {{16, 12, 0, 16 * 12}, {16, 12, 50, 37}, {3, 2, 0, 3 * 6 + 5}, {1, 1, 0, 11},
                          {16, 12, 5, 2 * 16 * 12 + 3}};
    for (const Case& k : cases) {
        INFO(k.w << "x" << k.h << " first " << k.first << " count " << k.count);
        CameraData cam = upload_camera(c, k.w, k.h, /*jitter=*/true);
        const int n = k.w * k.h;
        GenerateOut a = run_generate(cam, 21, 3, k.first, k.count, false);
        GenerateOut b = run_generate(cam, 21, 3, k.first, k.count, true);
        // Non-temporal stores (both forms) write the same bits, radiance cleared too.
        GenerateOut as = run_generate(cam, 21, 3, k.first, k.count, false, nullptr, false, true);
        GenerateOut bs = run_generate(cam, 21, 3, k.first, k.count, true, nullptr, false, true);
        CHECK(b.count == k.count);
        CHECK(bs.count == k.count);
        CHECK(b.counters[WP_COUNTER_GENERATE_NONFINITE] == 0);
        for (int i = 0; i < k.count; ++i) {
            const int s = k.first + i;
            REQUIRE(b.paths[i].pixel == s % n);
            REQUIRE(b.paths[i].sample == cl_uint(3 + s / n));
            REQUIRE(b.paths[i].item == i);
            REQUIRE(b.radiance[i].x == 0.0f);
            REQUIRE(std::memcmp(&a.rays[i], &b.rays[i], sizeof(Ray)) == 0);
            REQUIRE(std::memcmp(&a.paths[i], &b.paths[i], sizeof(PathState)) == 0);
            for (const GenerateOut* st : {&as, &bs}) {
                REQUIRE(std::memcmp(&a.rays[i], &st->rays[i], sizeof(Ray)) == 0);
                REQUIRE(std::memcmp(&a.paths[i], &st->paths[i], sizeof(PathState)) == 0);
                REQUIRE(std::memcmp(&b.radiance[i], &st->radiance[i], sizeof(float4)) == 0);
            }
        }
    }
    // The lens program: a thin lens (the lanes take the item path) and a lens of radius 0 (the
    // lanes' pinhole), each against the scalar kernel; without jitter too (pixel centres).
    for (float radius : {0.0f, 0.05f})
        for (bool jitter : {true, false}) {
            INFO("lens radius " << radius << " jitter " << jitter);
            Camera lc = c;
            lc.lens_radius = radius;
            lc.focus_distance = 2.5f;
            CameraData cam = upload_camera(lc, 16, 12, jitter);
            const int count = 2 * 16 * 12 + 5;
            GenerateOut a = run_generate(cam, 21, 3, 7, count, false, nullptr, true);
            GenerateOut b = run_generate(cam, 21, 3, 7, count, true, nullptr, true);
            GenerateOut pinhole = run_generate(cam, 21, 3, 7, count, true);
            for (int i = 0; i < count; ++i) {
                REQUIRE(std::memcmp(&a.rays[i], &b.rays[i], sizeof(Ray)) == 0);
                REQUIRE(std::memcmp(&a.paths[i], &b.paths[i], sizeof(PathState)) == 0);
                // Radius 0 is the pinhole bit for bit; a lens moves the origins.
                REQUIRE((std::memcmp(&b.rays[i], &pinhole.rays[i], sizeof(Ray)) == 0) == (radius == 0.0f));
            }
        }
    // generate_camera_active: item i is list entry (first + i) mod size of pass (first + i) /
    // size, with the ray of a whole pass at that pixel and sample.
    CameraData cam = upload_camera(c, 16, 12, /*jitter=*/true);
    const std::vector<int> active = {3, 4, 17, 90, 91, 92, 150, 151, 191, 0, 64};
    const int first = 4, count = 3 * 11 + 2, m = static_cast<int>(active.size());
    std::vector<GenerateOut> passes;
    for (cl_uint s = 7; s < 11; ++s) passes.push_back(run_generate(cam, 21, s));
    for (bool lanes : {false, true}) {
        INFO("lanes " << lanes);
        GenerateOut g = run_generate(cam, 21, 7, first, count, lanes, &active);
        CHECK(g.count == count);
        for (int i = 0; i < count; ++i) {
            const int e = first + i, p = active[e % m], pass = e / m;
            REQUIRE(g.paths[i].pixel == p);
            REQUIRE(g.paths[i].sample == cl_uint(7 + pass));
            REQUIRE(g.paths[i].item == i);
            REQUIRE(std::memcmp(&g.rays[i], &passes[pass].rays[p], sizeof(Ray)) == 0);
        }
    }
}
