// bench_rays.h — the benchmark's deterministic ray sets.
//
// primary: one ray through the centre of every pixel of the scene camera (800x600 by
// default); diffuse: from every primary hit, a cosine-distributed direction about the
// geometric normal on the side the camera sees (a first diffuse bounce); shadow: from
// every primary hit to a uniformly chosen point on an emissive triangle (chosen by area),
// tmax just short of the light. Origins of secondary rays are offset robustly (offset.h).
#pragma once

#include <string>
#include <vector>

#include "scene/scene.h"
#include "shared/types.h"

namespace wp::app {

struct RaySets {
    std::vector<Ray> primary, diffuse, shadow;
};

// Primary rays of the scene camera at its film size.
std::vector<Ray> primary_rays(const Camera& cam);

// Secondary rays from the closest hits of the primary rays.
RaySets make_ray_sets(const Scene& scene, const std::vector<Ray>& primary, const std::vector<Hit>& hits,
                      std::uint64_t seed = 1);

}  // namespace wp::app
