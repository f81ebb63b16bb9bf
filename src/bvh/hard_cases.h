// hard_cases.h — the numerical hard cases of issue 5, shared by tests/test_hard*.cpp and
// `wavepath bench hard` (the tests run small counts, the benchmark the large ones).
//
// Watertightness: a closed or open mesh, a list of its shared edges and vertices
// ("segments"), and rays made on the device (kernels/test_hard.cl: hard_edge_rays) that aim
// exactly at points of those segments from both sides; the real intersect kernels trace
// them and hard_count counts misses. Every ray crosses the surface in exact arithmetic, so
// the expected number of misses is 0 (an independent answer: geometry, not the code).
//
// Self-intersection: primary rays of a camera hit a mesh; from each hit point a secondary
// ray leaves from the robustly offset origin (kernels/shared/offset.h, Wächter & Binder
// 2019) in a cosine, a uniform and the mirror direction; a secondary ray whose closest hit
// is the triangle it left is a self-intersection (expected count 0: a flat triangle cannot
// be met again by a ray leaving it on the normal's side).
//
// (This file uses scene/procedural.h for the test meshes: geometry only, no OpenCL.)
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "bvh/device_bvh.h"
#include "cl/kernel.h"
#include "scene/procedural.h"

namespace wp::bvh {

struct WatertightCase {
    std::string name;
    Mesh mesh;
    std::vector<glm::vec3> segments;  // pairs (a, b); a == b: a vertex
    int mode = 0;                     // 0: closed convex around center; 1: sheet with normal ~ +z
    glm::vec3 center{0.0f};
    float inner = 0.0f;   // convex: radius of the inside origins
    float radius = 1.0f;  // sheet: distance of the origins from the target
    float smin = 0.0f, smax = 1.0f;
};

// The four meshes of issue 5 case 1: a fine UV sphere, a cube of split quads, a height
// field on a coarse float grid (integer coordinates far from the origin), the two-triangle
// square of the issue (the targets on its diagonal include the ray).
std::vector<WatertightCase> watertight_cases(bool small = false);

// Every undirected edge used by two triangles, and every vertex (interior ones only when
// `interior` says which vertices are inside the open border).
std::vector<glm::vec3> shared_segments(const Mesh& m, const std::vector<bool>* interior = nullptr);

struct HardCount {
    std::uint64_t rays = 0;
    std::uint64_t misses = 0;
    std::uint64_t nonfinite = 0;  // hits with a NaN/Inf t
    std::uint64_t nonpositive = 0;  // hits with t <= 0
    double seconds = 0.0;
};

class HardProbe {
  public:
    HardProbe(const ocl::Device& dev, BatchTracer& tracer);
    // Traces `rays` rays (in batches of `batch`) at the case's segments with the variant.
    HardCount watertight(const WatertightCase& c, std::uint64_t rays, TraceVariant v, std::uint32_t seed = 1,
                         int batch = 1 << 20);
    // The rays of the first `count` of them, for host checks (oracles, tiny runs).
    std::vector<Ray> edge_rays(const WatertightCase& c, int count, std::uint32_t seed = 1);

  private:
    const ocl::Device& dev_;
    BatchTracer& tracer_;
    ocl::Program program_;
    ocl::Kernel gen_, count_;
    // hard_edge_rays over `count` rays from segment `first_segment`, round `round`.
    void enqueue_edge_rays(const WatertightCase& c, const ::cl::Buffer& seg, std::uint32_t seed,
                           int first_segment, std::uint32_t round, int count, const ::cl::Buffer& rays);
};

struct SelfHitCount {
    std::uint64_t rays = 0;        // secondary rays traced
    std::uint64_t same_triangle = 0;  // closest hit = the triangle the ray left
    std::uint64_t nonfinite = 0;   // NaN/Inf t on a hit
    std::uint64_t primary_hits = 0;
    double max_offset = 0.0;        // largest |offset origin - hit point| (world units)
    double extent = 0.0;            // diagonal of the transformed mesh's box (world units)
};

// Pinhole primary rays through pixel centres (y up in the image, as the generate stage).
// The origin of a secondary ray leaving triangle (v0, v1, v2) at barycentrics (u, v) on the
// side of the unit normal n, exactly as the shade kernel computes it (shared/offset.h).
glm::vec3 leave_surface(glm::vec3 v0, glm::vec3 v1, glm::vec3 v2, float u, float v, glm::vec3 n);

std::vector<Ray> camera_rays(glm::vec3 eye, glm::vec3 target, glm::vec3 up, float vfov_deg, int w, int h);

// The self-intersection count for `mesh` transformed by p -> scale * p + shift, with the
// primary rays transformed the same way.
SelfHitCount self_intersections(const ocl::Device& dev, BatchTracer& tracer, const Mesh& mesh,
                                const std::vector<Ray>& primary, float scale, glm::vec3 shift,
                                std::uint64_t seed = 1);

}  // namespace wp::bvh
