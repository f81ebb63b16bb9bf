#include "render/memory.h"

#include <algorithm>
#include <map>
#include <utility>

#include <fmt/format.h>

#include "cl/device.h"

namespace wp::render {

std::uint64_t MemoryReport::total() const {
    std::uint64_t t = 0;
    for (const auto& b : buffers) t += b.bytes;
    return t;
}

std::uint64_t MemoryReport::group(const std::string& name) const {
    std::uint64_t t = 0;
    for (const auto& b : buffers)
        if (b.group == name) t += b.bytes;
    return t;
}

std::uint64_t MemoryReport::largest() const {
    std::uint64_t m = 0;
    for (const auto& b : buffers) m = std::max(m, b.bytes);
    return m;
}

double MemoryReport::bytes_per_triangle() const {
    return triangles > 0 ? double(group(kMemoryBvh) + group(kMemoryScene)) / double(triangles) : 0.0;
}

double MemoryReport::bvh_bytes_per_triangle() const {
    return triangles > 0 ? double(group(kMemoryBvh)) / double(triangles) : 0.0;
}

namespace {

struct Summed {
    std::string group, name;
    int count = 0;
    std::uint64_t bytes = 0;
};

// Buffers of one (group, name) summed, in order of first allocation.
std::vector<Summed> summed(const MemoryReport& m) {
    std::vector<Summed> out;
    std::map<std::pair<std::string, std::string>, std::size_t> at;
    for (const auto& b : m.buffers) {
        auto key = std::make_pair(b.group, b.name);
        auto it = at.find(key);
        if (it == at.end()) {
            it = at.emplace(key, out.size()).first;
            out.push_back({b.group, b.name, 0, 0});
        }
        out[it->second].count += 1;
        out[it->second].bytes += b.bytes;
    }
    return out;
}

}  // namespace

nlohmann::json memory_json(const MemoryReport& m) {
    nlohmann::json j;
    j["total_bytes"] = m.total();
    j["device_capacity_bytes"] = m.capacity;
    j["device_max_alloc_bytes"] = m.max_alloc;
    j["largest_buffer_bytes"] = m.largest();
    j["groups"] = {{kMemoryBvh, m.group(kMemoryBvh)},
                   {kMemoryScene, m.group(kMemoryScene)},
                   {kMemoryPool, m.group(kMemoryPool)},
                   {kMemoryFilm, m.group(kMemoryFilm)}};
    auto& list = j["buffers"] = nlohmann::json::array();
    for (const auto& s : summed(m))
        list.push_back({{"group", s.group}, {"name", s.name}, {"count", s.count}, {"bytes", s.bytes}});
    j["triangles"] = m.triangles;
    j["bytes_per_triangle"] = m.bytes_per_triangle();
    j["bvh_bytes_per_triangle"] = m.bvh_bytes_per_triangle();
    j["pool_paths"] = m.pool_paths;
    j["bytes_per_path"] = m.bytes_per_path;
    j["film_pixels"] = m.pixels;
    j["film_bytes_per_pixel"] = m.bytes_per_pixel;
    return j;
}

std::string format_memory(const MemoryReport& m) {
    using ocl::format_bytes;
    std::string s = fmt::format(
        "device memory: {} of {} (largest buffer {} of at most {})\n", format_bytes(m.total()),
        format_bytes(m.capacity), format_bytes(m.largest()), format_bytes(m.max_alloc));
    s += fmt::format("  bvh {}, scene {} ({} triangles: {:.1f} B per triangle, {:.1f} of them BVH)\n",
                     format_bytes(m.group(kMemoryBvh)), format_bytes(m.group(kMemoryScene)), m.triangles,
                     m.bytes_per_triangle(), m.bvh_bytes_per_triangle());
    s += fmt::format("  pool {} ({} paths in flight x {} B), film {} ({} pixels x {} B)\n",
                     format_bytes(m.group(kMemoryPool)), m.pool_paths, m.bytes_per_path,
                     format_bytes(m.group(kMemoryFilm)), m.pixels, m.bytes_per_pixel);
    for (const auto& b : summed(m))
        s += fmt::format("    {:<6} {:<34} {:>10}{}\n", b.group, b.name, format_bytes(b.bytes),
                         b.count > 1 ? fmt::format(" ({} buffers)", b.count) : "");
    return s;
}

}  // namespace wp::render
