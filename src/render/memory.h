// memory.h — the device memory of one render, by buffer and group, and per unit of work.
//
// Every buffer is counted where it is created (cl/memory.h: Device::create_buffer); the
// renderer tags its buffers with four groups: "bvh" (nodes, links, leaf-ordered triangles
// and their ids: bvh/device_bvh.h), "scene" (shading triangles, material ids, materials and
// their tables, the light table, appearance: normals, uvs, tangents, textures, the
// environment), "pool" (the path pool's queues, hits, radiance, shadow queue and queue
// lengths: render/frame_state.h) and "film" (the film's segments, the counters and the ray
// totals). Wavefront::memory() lists the buffers its construction created.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cl/memory.h"

namespace wp::render {

inline constexpr const char* kMemoryBvh = "bvh";
inline constexpr const char* kMemoryScene = "scene";
inline constexpr const char* kMemoryPool = "pool";
inline constexpr const char* kMemoryFilm = "film";

struct MemoryReport {
    std::vector<ocl::BufferRecord> buffers;  // in allocation order
    std::uint64_t capacity = 0;   // the device limits the buffers were checked against
    std::uint64_t max_alloc = 0;
    std::size_t triangles = 0;
    std::size_t pool_paths = 0;
    std::size_t bytes_per_path = 0;   // PathPool::bytes_per_path
    std::size_t pixels = 0;
    std::size_t bytes_per_pixel = 0;  // FilmBuffers::bytes_per_pixel

    std::uint64_t total() const;
    std::uint64_t group(const std::string& name) const;  // bytes of one group
    std::uint64_t largest() const;                        // the largest single buffer
    // (bvh + scene) / triangles and bvh / triangles (0 without triangles).
    double bytes_per_triangle() const;
    double bvh_bytes_per_triangle() const;
};

// {"total_bytes", "device_capacity_bytes", "device_max_alloc_bytes", "largest_buffer_bytes",
//  "groups": {"bvh", "scene", "pool", "film"}, "buffers": [{"group", "name", "count",
//  "bytes"}] (buffers of one group and name summed), "triangles", "bytes_per_triangle",
//  "bvh_bytes_per_triangle", "pool_paths", "bytes_per_path", "film_pixels",
//  "film_bytes_per_pixel"}
nlohmann::json memory_json(const MemoryReport& m);

// Lines for `render -v`: the totals per group with the figures per triangle, path and
// pixel, then one indented line per buffer name; ends in a newline.
std::string format_memory(const MemoryReport& m);

}  // namespace wp::render
