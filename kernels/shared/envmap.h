// envmap.h — PROVISIONAL (uniform sphere sampling, nearest texel) until the envmap branch
// lands with the same functions: EnvLight, wp_env_radiance, wp_env_sample, wp_env_pdf.
#ifndef WP_ENVMAP_H
#define WP_ENVMAP_H

#include "sampling.h"
#include "types.h"

WP_NAMESPACE_BEGIN

typedef struct EnvLight {
    EnvData data;
    WP_GLOBAL const float4* texels;
    WP_GLOBAL const float* marginal;
    WP_GLOBAL const float* conditional;
} EnvLight;

WP_FN float3 wp_env_radiance(EnvLight env, float3 dir) {
    float3 l = make_float3(dot(wp_xyz(env.data.to_local0), dir), dot(wp_xyz(env.data.to_local1), dir),
                           dot(wp_xyz(env.data.to_local2), dir));
    float u = atan2(l.x, -l.z) * WP_INV_2PI;
    u = u - floor(u);
    float v = acos(clamp(l.y, -1.0f, 1.0f)) * WP_INV_PI;
    int x = min((int)(u * (float)env.data.width), env.data.width - 1);
    int y = min((int)(v * (float)env.data.height), env.data.height - 1);
    return wp_xyz(env.texels[y * env.data.width + x]) * wp_xyz(env.data.scale);
}

WP_FN float3 wp_env_sample(EnvLight env, float u1, float u2, float* pdf) {
    (void)env;
    float z = 1.0f - 2.0f * u1;
    float r = sqrt(max(0.0f, 1.0f - z * z));
    float phi = 2.0f * WP_PI * u2;
    *pdf = 0.25f * WP_INV_PI;
    return make_float3(r * cos(phi), r * sin(phi), z);
}

WP_FN float wp_env_pdf(EnvLight env, float3 dir) {
    (void)env, (void)dir;
    return 0.25f * WP_INV_PI;
}

WP_NAMESPACE_END

#endif  // WP_ENVMAP_H
