// offset.h — robust origins for rays that leave a surface.
//
// Wächter & Binder, "A Fast and Robust Method for Avoiding Self-Intersection", Ray Tracing
// Gems (2019), chapter 6, listing 6-1: the hit point is moved along the geometric normal
// by a fixed number of ulps of each coordinate (integer arithmetic on the float bits), and
// by a small absolute amount near the origin where ulps become tiny. The offset scales with
// the position's magnitude, so it needs no scene-dependent epsilon.
#ifndef WP_OFFSET_H
#define WP_OFFSET_H

#include "compat.h"

WP_NAMESPACE_BEGIN

#define WP_OFFSET_ORIGIN (1.0f / 32.0f)        // below this |coordinate|, use float_scale
#define WP_OFFSET_FLOAT_SCALE (1.0f / 65536.0f)
#define WP_OFFSET_INT_SCALE 256.0f

WP_FN float wp_offset_component(float p, float n) {
    int of = (int)(WP_OFFSET_INT_SCALE * n);
    float pi = as_float(as_int(p) + (p < 0.0f ? -of : of));
    return fabs(p) < WP_OFFSET_ORIGIN ? p + WP_OFFSET_FLOAT_SCALE * n : pi;
}

// p: a point on the surface; n: the geometric normal on the side the new ray leaves
// (need not be unit length, but must be of order 1).
WP_FN float3 wp_offset_ray_origin(float3 p, float3 n) {
    return make_float3(wp_offset_component(p.x, n.x), wp_offset_component(p.y, n.y),
                       wp_offset_component(p.z, n.z));
}

WP_NAMESPACE_END

#endif  // WP_OFFSET_H
