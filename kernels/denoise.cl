// denoise.cl — the denoise stage: an edge-avoiding à-trous wavelet filter (Dammertz,
// Sewtz, Hanika & Lensch, "Edge-Avoiding À-Trous Wavelet Transform for fast Global
// Illumination Filtering", HPG 2010) guided by the feature buffers (render/aov.h) and by
// the per-pixel variance of the film, with the edge-stopping functions and the variance
// guidance of SVGF (Schied et al., "Spatiotemporal Variance-Guided Filtering", HPG 2017),
// spatial part only. Images are w x h, row-major from the top-left, one float4 per pixel.
//
// denoise_prepare
// reads   color[p] (xyz: the noisy mean), variance[p] (xyz: its variance of the mean per
//         channel), albedo_depth[p] (xyz: albedo AOV, w: depth AOV, +inf for a miss),
//         normal[p] (xyz: normal AOV, not unit)
// writes  illum[p] = (colour / albedo per channel — the albedo is divided out where it is
//         at least min_albedo, so texture and albedo edges need no smoothing —, variance of
//         its luminance); guide[p] = (unit normal or 0 for a miss, the depth's screen-space
//         gradient: the smaller one-sided difference per axis, their length)
// denoise_atrous (one iteration, taps `step` pixels apart)
// reads   in[q] (demodulated colour, variance) for the 5 x 5 taps q = p + step (i, j),
//         albedo_depth, guide
// writes  out[p] = (Σ w_q c_q / Σ w_q, Σ w_q² var_q / (Σ w_q)²) with w_q = h(i) h(j) (the
//         B3 spline 1/16, 1/4, 3/8, 1/4, 1/16) times the edge-stopping weights:
//           luminance  exp(-|l_p - l_q| / (σ_l sqrt(g(var_p)) + ε)), g: 3x3 Gaussian of the
//                      variance (SVGF eq. 3-5);
//           normal     max(0, n_p · n_q)^σ_n (σ_n a power of two: 2^normal_squarings);
//                      1 between two misses, 0 between a miss and a hit;
//           depth      exp(-|z_p - z_q| / (σ_z |∇z_p| |p - q| + ε)); misses as above;
//           albedo     exp(-Σ_c |a_p - a_q| / σ_a).
//         sigma_l <= 0 leaves the luminance term out (the residual pass below).
// denoise_combine
// reads   a[p], b[p]
// writes  out[p] = (a + k b, 0): with k = -1 the residual of the filter (the input less the
//         filtered image), with k = 1 the filtered image plus the filtered residual.
//         Energy restore: the luminance weight is asymmetric (a pixel's tolerance is its
//         own variance), so a pixel that drew a rare bright sample is averaged down while
//         its neighbours reject it, and the filtered image is darker than the input on
//         skewed (path-traced) noise. The residual, filtered by the guides alone
//         (sigma_l <= 0: normals, depth, albedo; render/denoise.h restore_iterations), puts
//         that energy back spread over the surface it came from.
// denoise_finish
// reads   illum[p], albedo_depth[p]
// writes  out[p] = (illum × albedo where it was divided out, 0)
// Every kernel is launched over w * h work-items; none pushes anything.
#include "shared/types.h"

WP_FN float wp_dn_luminance(float3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

// The factor divided out of channel value a (1 where the albedo is too small).
WP_FN float wp_dn_factor(float a, float min_albedo) { return a >= min_albedo ? a : 1.0f; }

WP_KERNEL void denoise_prepare(WP_GLOBAL const float4* color, WP_GLOBAL const float4* variance,
                               WP_GLOBAL const float4* albedo_depth, WP_GLOBAL const float4* normal,
                               int w, int h, float min_albedo, WP_GLOBAL float4* illum,
                               WP_GLOBAL float4* guide) {
    int p = wp_global_id();
    if (p >= w * h) return;
    int y = p / w, x = p - y * w;
    float4 c = color[p], v = variance[p], a = albedo_depth[p];
    float fx = wp_dn_factor(a.x, min_albedo), fy = wp_dn_factor(a.y, min_albedo),
          fz = wp_dn_factor(a.z, min_albedo);
    // The channels of a path-traced pixel are strongly correlated: the luminance's standard
    // deviation is taken as the weighted sum of the channels' (exact for full correlation).
    float sd = 0.2126f * sqrt(max(v.x, 0.0f)) / fx + 0.7152f * sqrt(max(v.y, 0.0f)) / fy +
               0.0722f * sqrt(max(v.z, 0.0f)) / fz;
    illum[p] = make_float4(c.x / fx, c.y / fy, c.z / fz, sd * sd);
    // Unit normal (0 for a miss or normals that cancel).
    float3 n = wp_xyz(normal[p]);
    float l2 = dot(n, n);
    n = l2 > 1e-12f ? n * (1.0f / sqrt(l2)) : make_float3(0.0f, 0.0f, 0.0f);
    // Depth gradient: per axis the smaller one-sided difference (a silhouette on one side
    // does not widen the tolerance), FLT_MAX where no finite neighbour exists.
    float z = a.w, gx = FLT_MAX, gy = FLT_MAX;
    if (isfinite(z)) {
        if (x > 0 && isfinite(albedo_depth[p - 1].w)) gx = fabs(z - albedo_depth[p - 1].w);
        if (x + 1 < w && isfinite(albedo_depth[p + 1].w)) gx = min(gx, fabs(albedo_depth[p + 1].w - z));
        if (y > 0 && isfinite(albedo_depth[p - w].w)) gy = fabs(z - albedo_depth[p - w].w);
        if (y + 1 < h && isfinite(albedo_depth[p + w].w)) gy = min(gy, fabs(albedo_depth[p + w].w - z));
    }
    float g = (gx == FLT_MAX || gy == FLT_MAX) ? FLT_MAX : sqrt(gx * gx + gy * gy);
    guide[p] = wp_float4(n, g);
}

// The 3x3 Gaussian (1/4, 1/2, 1/4)² of the variance around (x, y) (SVGF's prefilter),
// renormalised at the image border.
WP_FN float wp_dn_variance3(WP_GLOBAL const float4* in, int x, int y, int w, int h) {
    float sum = 0.0f, wsum = 0.0f;
    for (int j = -1; j <= 1; ++j)
        for (int i = -1; i <= 1; ++i) {
            int qx = x + i, qy = y + j;
            if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
            float k = (i == 0 ? 0.5f : 0.25f) * (j == 0 ? 0.5f : 0.25f);
            sum += k * in[qy * w + qx].w;
            wsum += k;
        }
    return sum / wsum;
}

WP_FN float wp_dn_b3(int i) { return i == 0 ? 0.375f : (i == 1 || i == -1 ? 0.25f : 0.0625f); }

WP_KERNEL void denoise_atrous(WP_GLOBAL const float4* in, WP_GLOBAL const float4* albedo_depth,
                              WP_GLOBAL const float4* guide, int w, int h, int step, float sigma_l,
                              float sigma_z, float sigma_a, int normal_squarings,
                              WP_GLOBAL float4* out) {
    int p = wp_global_id();
    if (p >= w * h) return;
    int y = p / w, x = p - y * w;
    float4 cp = in[p], ap = albedo_depth[p], gp = guide[p];
    float3 np = wp_xyz(gp);
    const int miss_p = !isfinite(ap.w);
    const float lp = wp_dn_luminance(wp_xyz(cp));
    // Luminance tolerance from the prefiltered variance (SVGF eq. 5); none with sigma_l <= 0.
    const int luminance = sigma_l > 0.0f;
    const float l_scale =
        luminance ? sigma_l * sqrt(max(wp_dn_variance3(in, x, y, w, h), 0.0f)) + 1e-10f : 1.0f;
    float3 sum = make_float3(0.0f, 0.0f, 0.0f);
    float wsum = 0.0f, vsum = 0.0f;
    for (int j = -2; j <= 2; ++j)
        for (int i = -2; i <= 2; ++i) {
            int qx = x + i * step, qy = y + j * step;
            if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
            int q = qy * w + qx;
            float4 cq = in[q], aq = albedo_depth[q], gq = guide[q];
            float wt = wp_dn_b3(i) * wp_dn_b3(j);
            if (q != p) {
                const int miss_q = !isfinite(aq.w);
                if (miss_p != miss_q) continue;  // a miss next to a hit: an edge
                // Normal: max(0, cos)^(2^k) by squaring.
                float3 nq = wp_xyz(gq);
                float wn = max(0.0f, dot(np, nq));
                if (dot(np, np) == 0.0f && dot(nq, nq) == 0.0f) wn = 1.0f;
                for (int k = 0; k < normal_squarings; ++k) wn = wn * wn;
                // Depth against its own gradient over the tap's distance, luminance and
                // albedo: their exponents summed, one exp.
                float e = (fabs(ap.x - aq.x) + fabs(ap.y - aq.y) + fabs(ap.z - aq.z)) / sigma_a;
                if (luminance) e += fabs(lp - wp_dn_luminance(wp_xyz(cq))) / l_scale;
                if (!miss_p) {
                    float dist = (float)step * sqrt((float)(i * i + j * j));
                    float tol = gp.w == FLT_MAX ? FLT_MAX : sigma_z * gp.w * dist + 1e-4f * fabs(ap.w);
                    e += fabs(ap.w - aq.w) / tol;
                }
                wt = wt * wn * exp(-e);
            }
            sum = sum + wp_xyz(cq) * wt;
            vsum += wt * wt * cq.w;
            wsum += wt;
        }
    // The centre tap always counts, so wsum > 0.
    out[p] = wp_float4(sum * (1.0f / wsum), vsum / (wsum * wsum));
}

WP_KERNEL void denoise_combine(WP_GLOBAL const float4* a, WP_GLOBAL const float4* b, int w, int h,
                               float k, WP_GLOBAL float4* out) {
    int p = wp_global_id();
    if (p >= w * h) return;
    float4 x = a[p], y = b[p];
    out[p] = make_float4(x.x + k * y.x, x.y + k * y.y, x.z + k * y.z, 0.0f);
}

WP_KERNEL void denoise_finish(WP_GLOBAL const float4* illum, WP_GLOBAL const float4* albedo_depth,
                              int w, int h, float min_albedo, WP_GLOBAL float4* out) {
    int p = wp_global_id();
    if (p >= w * h) return;
    float4 c = illum[p], a = albedo_depth[p];
    out[p] = make_float4(c.x * wp_dn_factor(a.x, min_albedo), c.y * wp_dn_factor(a.y, min_albedo),
                         c.z * wp_dn_factor(a.z, min_albedo), 0.0f);
}
