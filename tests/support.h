// support.h — shared helpers for the tests: the test device, random numbers, ray sets
// and the brute-force intersection oracle.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "cl/device.h"
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

}  // namespace wp::test
