// embree_ref.h — Embree 3 as the benchmark's industry reference (optional).
//
// Compiled with real content only when CMake finds libembree-dev (WP_HAVE_EMBREE); traces
// the same rays as wavepath with rtcIntersect1 / rtcOccluded1, one ray per call, split
// across N threads, so the benchmark can print wavepath/Embree ratios from one run.
#pragma once

#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "shared/types.h"

namespace wp::app {

bool embree_available();
std::string embree_version();

class EmbreeScene {
  public:
    EmbreeScene(std::span<const glm::vec3> positions, std::span<const glm::uvec3> triangles);
    ~EmbreeScene();
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    double build_ms() const { return build_ms_; }
    // Traces every ray with `threads` threads; returns the wall time in ms. Closest hits
    // fill `hits` (prim = triangle index, -1 = miss); any-hit fills prim with 0 / -1.
    double trace(const std::vector<Ray>& rays, bool any_hit, int threads, std::vector<Hit>& hits) const;

  private:
    void* device_ = nullptr;
    void* scene_ = nullptr;
    double build_ms_ = 0.0;
};

}  // namespace wp::app
