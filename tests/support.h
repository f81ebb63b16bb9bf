// support.h — shared helpers for the tests: the test device, random numbers, ray sets
// and the brute-force intersection oracle.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "cl/device.h"
#include "image/image.h"
#include "scene/scene.h"
#include "shared/types.h"
#include "util/splitmix.h"

namespace wp::test {

// The device the kernel tests run on: $WP_TEST_DEVICE (a selector), else the default.
ocl::Device& device();

// Test data generator: splitmix64 (util/splitmix.h) plus unit vectors.
struct Rng : SplitMix64 {
    explicit Rng(std::uint64_t seed) : SplitMix64(seed) {}
    glm::vec3 unit_vector();
};

Ray make_ray(glm::vec3 o, glm::vec3 d, float tmin = 0.0f, float tmax = FLT_MAX);

// Random rays for intersection tests: origins inside the box `lo..hi` (half of them) or on a
// sphere around it aimed at points inside (the other half); every 8th ray has one or two
// direction components set to +0 or -0 (axis-parallel rays).
std::vector<Ray> random_rays(std::size_t n, std::uint64_t seed, glm::vec3 lo, glm::vec3 hi);

// Brute force over every triangle in scene order with the shared watertight test and the
// documented tie rule (smallest index at equal t). Runs on all cores.
std::vector<Hit> brute_force(std::span<const glm::vec3> positions, std::span<const glm::uvec3> tris,
                             const std::vector<Ray>& rays, bool any_hit = false);


// Area, area-weighted winding normal, signed volume (positive when the winding is outward),
// count and bounds of the triangles of `s` with material `mat` (all when mat < 0), in
// double: what loader tests compare between two files of one scene.
struct Measure {
    double area = 0, volume = 0;
    glm::dvec3 normal_sum{0.0};  // sum of area-weighted winding normals
    std::size_t triangles = 0;
    glm::dvec3 lo{1e300}, hi{-1e300};
};
Measure measure(const Scene& s, long mat = -1);

// The shared scenes' README table: scene folder -> expected triangles, with the table's
// "(+N ...)" extras added ("126,048 (+2 floor)" -> 126,050).
std::map<std::string, long> readme_counts(const std::filesystem::path& readme);
// Every `root/<scene>/<file>` that exists, sorted.
std::vector<std::filesystem::path> shared_scene_files(const std::filesystem::path& root,
                                                      const std::string& file);

// A small render of a loaded scene (32 pixels wide, the scene's aspect, seed 1): how many
// values of the image are not finite, the renderer's non-finite counters summed, and the
// sum of the image (> 0 when light reaches the camera).
struct SmokeRender {
    int nonfinite = 0;
    long counters = 0;
    double sum = 0.0;
};
SmokeRender smoke_render(const Scene& s, int spp, int depth);

// Standard base64 with padding (RFC 4648), for data URIs in glTF tests.
std::string base64(const std::string& in);
// Appends the bytes of v to s (binary buffers of glTF tests).
template <typename T>
void put(std::string& s, T v) {
    s.append(reinterpret_cast<const char*>(&v), sizeof(T));
}

// Channel c of texel (x, y) of a texture as stored (8-bit values / 255, not decoded).
float texel_at(const Texture& t, int x, int y, int c);

// Writes a w x h linear float image whose pixel (x, y) (row 0 at the top) is f(x, y).
template <class F>
void write_exr(const std::filesystem::path& p, int w, int h, F f) {
    Image img(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const glm::vec3 c = f(x, y);
            float* px = img.pixel(x, y);
            px[0] = c.x, px[1] = c.y, px[2] = c.z;
        }
    write_image(p, img);
}

}  // namespace wp::test
