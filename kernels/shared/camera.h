// camera.h — the camera of the generate stage: a pinhole, or a thin lens (layout:
// CameraData in types.h).
//
// Image position (px, py) is measured in pixels from the top-left corner of the image;
// pixel (x, y) covers [x, x + 1) x [y, y + 1), its centre is (x + 0.5, y + 0.5).
//
// The image plane sits at distance 1 along forward and spans right * [-1, 1] by
// up * [-1, 1] (|up| = tan(vfov / 2)). Its point for (px, py) is
//   p = forward + sx right + sy up,  sx = 2 px / width - 1,  sy = 1 - 2 py / height,
// and the pinhole ray leaves the eye along p / |p|.
//
// Thin lens (pbrt-v4's PerspectiveCamera, Mitsuba 3's thinlens): the lens is the disk of
// radius lens.x around the eye perpendicular to forward; the ray for (px, py) and a point a
// on the lens starts at eye + a and passes through eye + lens.y p, the pinhole ray's point
// on the plane in focus (distance lens.y along forward; forward . p = 1). Points on that
// plane are sharp; a point at depth z along forward is imaged as a disk of radius
// lens.x |1/lens.y - 1/z| on the image plane (tests/test_camera_lens.cpp derives it).
#ifndef WP_CAMERA_H
#define WP_CAMERA_H

#include "sampling.h"
#include "types.h"

WP_NAMESPACE_BEGIN

// The image-plane point p of image position (px, py), relative to the eye (not unit length).
WP_FN float3 wp_camera_image_point(CameraData cam, float px, float py) {
    float sx = 2.0f * px / (float)cam.width - 1.0f;
    float sy = 1.0f - 2.0f * py / (float)cam.height;
    return wp_xyz(cam.forward) + wp_xyz(cam.right) * sx + wp_xyz(cam.up) * sy;
}

// Unit direction of the pinhole ray through image position (px, py).
WP_FN float3 wp_camera_direction(CameraData cam, float px, float py) {
    return normalize(wp_camera_image_point(cam, px, py));
}

// The thin-lens ray through image position (px, py) for the lens sample (u1, u2) in
// [0, 1)^2 (uniform over the lens disk by the concentric map): its origin on the lens in
// *org, its unit direction returned. cam.lens.x > 0, cam.lens.y > 0.
WP_FN float3 wp_camera_lens_ray(CameraData cam, float px, float py, float u1, float u2,
                                float3* org) {
    float2 disk = wp_sample_concentric_disk(u1, u2);
    float3 a = normalize(wp_xyz(cam.right)) * (cam.lens.x * disk.x) +
               normalize(wp_xyz(cam.up)) * (cam.lens.x * disk.y);
    float3 focus = wp_camera_image_point(cam, px, py) * cam.lens.y;  // on the plane in focus
    *org = wp_xyz(cam.origin) + a;
    return normalize(focus - a);
}

WP_NAMESPACE_END

#endif  // WP_CAMERA_H
