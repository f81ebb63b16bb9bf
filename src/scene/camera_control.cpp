#include "scene/camera_control.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "util/limits.h"

namespace wp {

namespace {

struct Frame {
    glm::vec3 f, r, u;
    float distance;
};

Frame frame_of(const Camera& c) {
    glm::vec3 d = c.target - c.position;
    Frame fr;
    fr.distance = glm::length(d);
    fr.f = d / fr.distance;
    fr.r = glm::normalize(glm::cross(fr.f, c.up));
    fr.u = glm::cross(fr.r, fr.f);
    return fr;
}

// Rodrigues' rotation of v about the unit axis k by angle a.
glm::vec3 rotate(glm::vec3 v, glm::vec3 k, float a) {
    const float cs = std::cos(a), sn = std::sin(a);
    return v * cs + glm::cross(k, v) * sn + k * glm::dot(k, v) * (1.0f - cs);
}

}  // namespace

Camera orbit_camera(const Camera& c, float yaw, float pitch) {
    Camera out = c;
    const Frame fr = frame_of(c);
    const glm::vec3 up = glm::normalize(c.up);
    glm::vec3 back = -fr.f;  // from target to position, unit
    // Yaw about up: positive moves the camera to its right (the view turns left).
    back = rotate(back, up, yaw);
    // Pitch about the (new) right axis, limited so the view never reaches +-up.
    const float elevation = std::asin(std::clamp(glm::dot(back, up), -1.0f, 1.0f));
    const float limit = glm::radians(limits::kViewerMaxPitchDeg);
    const float target_elev = std::clamp(elevation + pitch, -limit, limit);
    const glm::vec3 right = glm::normalize(glm::cross(-back, up));
    back = rotate(back, right, -(target_elev - elevation));
    out.position = c.target + glm::normalize(back) * fr.distance;
    return out;
}

Camera pan_camera(const Camera& c, float dx, float dy) {
    Camera out = c;
    const Frame fr = frame_of(c);
    const glm::vec3 move = (fr.r * dx + fr.u * dy) * fr.distance;
    out.position += move;
    out.target += move;
    return out;
}

Camera dolly_camera(const Camera& c, float factor) {
    Camera out = c;
    const Frame fr = frame_of(c);
    const float d = std::max(fr.distance * factor, limits::kViewerMinDistance);
    out.position = c.target - fr.f * d;
    return out;
}

Camera fly_camera(const Camera& c, float right, float up, float forward) {
    Camera out = c;
    const Frame fr = frame_of(c);
    const glm::vec3 move = fr.r * right + fr.u * up + fr.f * forward;
    out.position += move;
    out.target += move;
    return out;
}

std::string camera_json_snippet(const Camera& c) {
    auto v = [](glm::vec3 x) { return nlohmann::json::array({x.x, x.y, x.z}); };
    nlohmann::json cam = {{"position", v(c.position)}, {"look_at", v(c.target)}, {"up", v(c.up)},
                          {"fov", c.vfov_deg},         {"width", c.width},      {"height", c.height}};
    if (c.lens_radius > 0.0f) {
        cam["lens_radius"] = c.lens_radius;
        cam["focus_distance"] = c.focus_distance;
    }
    return nlohmann::json{{"camera", cam}}.dump(2) + "\n";
}

}  // namespace wp
