// test_generate.cpp — the generate stage alone: camera rays against a host camera model.
//
// The model below is written from the camera definition (Scene::Camera: position, target,
// up, vertical fov; image y downwards from the top-left corner) in double precision,
// independently of scene/upload and kernels/shared/camera.h.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include <glm/glm.hpp>

#include "cl/profiler.h"
#include "cl/program.h"
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

GenerateOut run_generate(const CameraData& cam, cl_uint seed, cl_uint sample) {
    auto& dev = test::device();
    auto prog = ocl::Program::build(dev, "generate.cl");
    auto k = prog.kernel("generate_camera");
    std::size_t n = static_cast<std::size_t>(cam.width) * cam.height;
    cl::Buffer rays(dev.context, CL_MEM_READ_WRITE, n * sizeof(Ray));
    cl::Buffer paths(dev.context, CL_MEM_READ_WRITE, n * sizeof(PathState));
    std::vector<float4> junk(n, float4{7.0f, 7.0f, 7.0f, 7.0f});  // generate must clear it
    cl::Buffer radiance(dev.context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, n * sizeof(float4),
                        junk.data());
    int zero = 0;
    cl::Buffer count(dev.context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, sizeof(int), &zero);
    std::vector<int> cz(WP_COUNTER_COUNT, 0);
    cl::Buffer counters(dev.context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, cz.size() * sizeof(int),
                        cz.data());
    k.setArg(0, cam);
    k.setArg(1, seed);
    k.setArg(2, sample);
    k.setArg(3, rays);
    k.setArg(4, paths);
    k.setArg(5, radiance);
    k.setArg(6, count);
    k.setArg(7, counters);
    ocl::launch(dev.queue, k, "generate", n);
    GenerateOut out;
    out.rays.resize(n);
    out.paths.resize(n);
    out.radiance.resize(n);
    out.counters.resize(WP_COUNTER_COUNT);
    dev.queue.enqueueReadBuffer(rays, CL_TRUE, 0, n * sizeof(Ray), out.rays.data());
    dev.queue.enqueueReadBuffer(paths, CL_TRUE, 0, n * sizeof(PathState), out.paths.data());
    dev.queue.enqueueReadBuffer(radiance, CL_TRUE, 0, n * sizeof(float4), out.radiance.data());
    dev.queue.enqueueReadBuffer(count, CL_TRUE, 0, sizeof(int), &out.count);
    dev.queue.enqueueReadBuffer(counters, CL_TRUE, 0, cz.size() * sizeof(int), out.counters.data());
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
    // Every slot: its own pixel, unit throughput, cleared radiance.
    for (int p = 0; p < w * h; ++p) {
        REQUIRE(g.paths[p].pixel == p);
        REQUIRE(g.paths[p].bounce == 0);
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
