// aabb.h — axis-aligned bounding boxes on the host.
#pragma once

#include <glm/glm.hpp>

#include <limits>

namespace wp {

struct Aabb {
    glm::vec3 lo{std::numeric_limits<float>::max()};
    glm::vec3 hi{-std::numeric_limits<float>::max()};

    bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
    void grow(const glm::vec3& p) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    void grow(const Aabb& b) {
        lo = glm::min(lo, b.lo);
        hi = glm::max(hi, b.hi);
    }
    glm::vec3 extent() const { return empty() ? glm::vec3(0.0f) : hi - lo; }
    glm::vec3 center() const { return 0.5f * (lo + hi); }
    // Half the surface area (the SAH only needs ratios).
    float half_area() const {
        glm::vec3 e = extent();
        return e.x * e.y + e.y * e.z + e.z * e.x;
    }
    bool contains(const Aabb& b) const {
        return glm::all(glm::lessThanEqual(lo, b.lo)) && glm::all(glm::greaterThanEqual(hi, b.hi));
    }
};

}  // namespace wp
