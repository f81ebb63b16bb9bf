#include "app/embree_ref.h"

#include <atomic>
#include <thread>

#include "util/error.h"
#include "util/timer.h"

#if defined(WP_HAVE_EMBREE)
#include <embree3/rtcore.h>
#endif

namespace wp::app {

#if defined(WP_HAVE_EMBREE)

bool embree_available() { return true; }
std::string embree_version() { return RTC_VERSION_STRING; }

EmbreeScene::EmbreeScene(std::span<const glm::vec3> positions, std::span<const glm::uvec3> triangles) {
    RTCDevice dev = rtcNewDevice(nullptr);
    if (!dev) fail("Embree: rtcNewDevice failed (error {})", static_cast<int>(rtcGetDeviceError(nullptr)));
    device_ = dev;
    Timer timer;
    RTCScene scene = rtcNewScene(dev);
    RTCGeometry geom = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), positions.size()));
    for (std::size_t i = 0; i < positions.size(); ++i) {
        v[3 * i] = positions[i].x;
        v[3 * i + 1] = positions[i].y;
        v[3 * i + 2] = positions[i].z;
    }
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               3 * sizeof(unsigned), triangles.size()));
    for (std::size_t i = 0; i < triangles.size(); ++i) {
        idx[3 * i] = triangles[i].x;
        idx[3 * i + 1] = triangles[i].y;
        idx[3 * i + 2] = triangles[i].z;
    }
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(scene);
    build_ms_ = timer.ms();
    scene_ = scene;
}

EmbreeScene::~EmbreeScene() {
    if (scene_) rtcReleaseScene(static_cast<RTCScene>(scene_));
    if (device_) rtcReleaseDevice(static_cast<RTCDevice>(device_));
}

double EmbreeScene::trace(const std::vector<Ray>& rays, bool any_hit, int threads, std::vector<Hit>& hits) const {
    hits.assign(rays.size(), Hit{0.0f, -1, 0.0f, 0.0f});
    auto scene = static_cast<RTCScene>(scene_);
    auto work = [&](std::size_t begin, std::size_t end) {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        for (std::size_t i = begin; i < end; ++i) {
            const Ray& r = rays[i];
            if (any_hit) {
                RTCRay ray{};
                ray.org_x = r.org.x, ray.org_y = r.org.y, ray.org_z = r.org.z, ray.tnear = r.org.w;
                ray.dir_x = r.dir.x, ray.dir_y = r.dir.y, ray.dir_z = r.dir.z, ray.tfar = r.dir.w;
                ray.mask = 0xffffffffu;
                rtcOccluded1(scene, &ctx, &ray);
                hits[i].prim = ray.tfar < 0.0f ? 0 : -1;  // Embree sets tfar = -inf when occluded
            } else {
                RTCRayHit rh{};
                rh.ray.org_x = r.org.x, rh.ray.org_y = r.org.y, rh.ray.org_z = r.org.z, rh.ray.tnear = r.org.w;
                rh.ray.dir_x = r.dir.x, rh.ray.dir_y = r.dir.y, rh.ray.dir_z = r.dir.z, rh.ray.tfar = r.dir.w;
                rh.ray.mask = 0xffffffffu;
                rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                rtcIntersect1(scene, &ctx, &rh);
                if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
                    hits[i] = Hit{rh.ray.tfar, static_cast<int>(rh.hit.primID), rh.hit.u, rh.hit.v};
                }
            }
        }
    };
    // Dynamic scheduling in blocks of 256 rays, as a work-group scheduler would do.
    std::atomic<std::size_t> next{0};
    auto worker = [&] {
        for (;;) {
            std::size_t b = next.fetch_add(256);
            if (b >= rays.size()) return;
            work(b, std::min(rays.size(), b + 256));
        }
    };
    Timer timer;
    std::vector<std::thread> pool;
    for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
    worker();
    for (auto& th : pool) th.join();
    return timer.ms();
}

#else

bool embree_available() { return false; }
std::string embree_version() { return ""; }
EmbreeScene::EmbreeScene(std::span<const glm::vec3>, std::span<const glm::uvec3>) {
    fail("this build has no Embree (install libembree-dev and reconfigure)");
}
EmbreeScene::~EmbreeScene() = default;
double EmbreeScene::trace(const std::vector<Ray>&, bool, int, std::vector<Hit>&) const { return 0.0; }

#endif

}  // namespace wp::app
