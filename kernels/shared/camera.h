// camera.h — the pinhole camera of the generate stage (layout: CameraData in types.h).
//
// Image position (px, py) is measured in pixels from the top-left corner of the image;
// pixel (x, y) covers [x, x + 1) x [y, y + 1), its centre is (x + 0.5, y + 0.5).
#ifndef WP_CAMERA_H
#define WP_CAMERA_H

#include "types.h"

WP_NAMESPACE_BEGIN

// Unit direction of the ray through image position (px, py).
WP_FN float3 wp_camera_direction(CameraData cam, float px, float py) {
    float sx = 2.0f * px / (float)cam.width - 1.0f;
    float sy = 1.0f - 2.0f * py / (float)cam.height;
    float3 d = wp_xyz(cam.forward) + wp_xyz(cam.right) * sx + wp_xyz(cam.up) * sy;
    return normalize(d);
}

WP_NAMESPACE_END

#endif  // WP_CAMERA_H
