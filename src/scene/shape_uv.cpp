#include "scene/shape_uv.h"

#include <algorithm>
#include <cstdint>
#include <unordered_map>

namespace wp {

void wrap_uvs(std::vector<glm::vec3>& positions, std::vector<glm::uvec3>& triangles,
              std::vector<glm::vec3>& normals, std::vector<glm::vec2>& uvs,
              const std::function<glm::vec2(glm::vec3)>& uv_of,
              const std::function<bool(glm::vec3)>& on_axis) {
    const std::size_t n0 = positions.size();
    uvs.resize(n0);
    std::vector<char> axis(n0);
    for (std::size_t i = 0; i < n0; ++i) {
        uvs[i] = uv_of(positions[i]);
        axis[i] = on_axis(positions[i]) ? 1 : 0;
    }
    const bool with_normals = !normals.empty();
    auto copy = [&](std::uint32_t v, glm::vec2 uv) {
        const glm::vec3 p = positions[v];
        positions.push_back(p);
        if (with_normals) {
            const glm::vec3 n = normals[v];
            normals.push_back(n);
        }
        uvs.push_back(uv);
        return static_cast<std::uint32_t>(positions.size() - 1);
    };
    std::unordered_map<std::uint32_t, std::uint32_t> shifted;  // vertex -> its copy at u + 1
    for (glm::uvec3& t : triangles) {
        const glm::uvec3 orig = t;
        float lo = 2.0f, hi = -1.0f;
        for (int k = 0; k < 3; ++k)
            if (!axis[orig[k]]) {
                lo = std::min(lo, uvs[orig[k]].x);
                hi = std::max(hi, uvs[orig[k]].x);
            }
        const bool wraps = hi - lo > 0.5f;
        float sum = 0.0f;
        int count = 0;
        for (int k = 0; k < 3; ++k) {
            if (axis[orig[k]]) continue;
            if (wraps && uvs[orig[k]].x < 0.5f) {
                auto [it, fresh] = shifted.try_emplace(orig[k], 0u);
                if (fresh) it->second = copy(orig[k], uvs[orig[k]] + glm::vec2(1.0f, 0.0f));
                t[k] = it->second;
            }
            sum += uvs[t[k]].x;
            ++count;
        }
        for (int k = 0; k < 3; ++k)
            if (axis[orig[k]])
                t[k] = copy(orig[k], glm::vec2(count > 0 ? sum / float(count) : 0.5f,
                                               uvs[orig[k]].y));
    }
}

}  // namespace wp
