// camera_control.h — moving the scene's Camera (scene.h) interactively: orbit, pan, dolly and
// fly, as the viewer (`wavepath view`) does with the mouse and WASD; and the camera as a JSON
// scene snippet. The moved Camera goes to the generate stage through upload_camera
// (scene/upload.h) like the scene file's: one camera definition.
//
// Frame: forward f = normalize(target - position), right r = normalize(f x up), true up
// u = r x f. `up` itself is kept, so the horizon stays level.
#pragma once

#include <string>

#include "scene/scene.h"

namespace wp {

// Turns position about target: yaw radians about `up` (positive: the camera moves to its
// right), then pitch radians about the right axis (positive: it moves up), the pitch
// stopping limits::kViewerMaxPitchDeg short of `up` and of -up. The distance to target is kept.
Camera orbit_camera(const Camera& c, float yaw, float pitch);

// Moves position and target together by dx right and dy up, in units of the distance to
// target (the view's scale at the target).
Camera pan_camera(const Camera& c, float dx, float dy);

// Multiplies the distance from position to target by factor (> 0; < 1 moves closer), kept at
// least limits::kViewerMinDistance.
Camera dolly_camera(const Camera& c, float factor);

// Moves position and target together by (right, up, forward) world units along the frame.
Camera fly_camera(const Camera& c, float right, float up, float forward);

// {"camera": {"position": [...], "look_at": [...], "up": [...], "fov": deg, "width": w,
// "height": h[, "lens_radius": r, "focus_distance": d]}} — the JSON scene format's keys
// (docs/scene-format.md), pretty-printed, ending in a newline.
std::string camera_json_snippet(const Camera& c);

}  // namespace wp
