// support.h — shared helpers for the tests: the test device, random numbers, ray sets
// and the brute-force intersection oracle.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "cl/device.h"
#include "shared/types.h"

namespace wp::test {

// The device the kernel tests run on: $WP_TEST_DEVICE (a selector), else the default.
ocl::Device& device();

// splitmix64: a small, fully specified generator (same numbers on every platform).
struct Rng {
    std::uint64_t state;
    explicit Rng(std::uint64_t seed) : state(seed) {}
    std::uint64_t next() {
        std::uint64_t z = (state += 0x9e3779b97f4a7c15ull);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return z ^ (z >> 31);
    }
    float uniform() { return static_cast<float>(next() >> 40) * 0x1p-24f; }  // [0, 1)
    float uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }
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

}  // namespace wp::test
