// shade.cl — the shade stage: emission, scattering, next-event estimation, Russian roulette
// and compaction of the surviving paths.
//
// shade_surface
// reads   rays_in[i], paths_in[i], hits[i] for i < count_in[0] (the queue of this bounce);
//         the scene in original triangle order: tris (vertices), tri_frames (each
//         triangle's unit face normal and offset share, shared/offset.h; written once per
//         scene by shade_triangle_frames, below), material_ids, materials;
//         material_tables (the per-material tables some kinds read at MaterialData.table,
//         scene/material_tables.h; a one-float placeholder when no material has any);
//         background radiance; with WP_HAVE_NEE the light table (lights.h): light_cdf,
//         light_guide, light_guide_size, light_prims, light_pdf_area, light_count, and
//         with WP_HAVE_LIGHT_CLEARANCE light_clearance (per triangle: where a shadow segment
//         towards it may end, scene/light_clearance.h; else a placeholder); the
//         appearance arrays of the features the scene has (else one-element placeholders):
//         tri_normals (WP_HAVE_NORMALS), tri_uvs, material_textures and the texture pool (WP_HAVE_TEXTURES), tri_tangents
//         (WP_HAVE_NORMAL_MAPS), the environment env, env_texels, env_marginal,
//         env_conditional and env_distance (WP_HAVE_ENV); cone_spread (the camera's spread
//         angle per pixel, for ray cones), seed, bounce (this bounce's index, the same for
//         every path of the queue), max_depth
// writes  radiance[item] += throughput * MIS weight * (emission of a front face hit), or
//         throughput * background on a miss (item: the path's sample in its wave);
//         counters[WP_COUNTER_SHADE_NONFINITE] on NaN/Inf
// pushes  every path that scatters (bounce < max_depth, not absorbed, throughput > 0, and
//         surviving Russian roulette) into rays_out / paths_out at a slot reserved from
//         count_out; with WP_HAVE_NEE a shadow ray per light sample into shadow_rays, with
//         its item and unoccluded contribution in shadow_items / shadow_contrib, at a slot
//         reserved from shadow_count (shadow.cl traces them). Both queues were emptied by
//         queue.reset; one global atomic per work-group and queue (see shade_surface).
// Each path owns its sample's radiance slot, so the radiance updates need no atomics and
// do not depend on the queue order.
//
// Compile options (KernelConfig): WP_HAVE_<KIND> (material_kinds.h) select the material
// code and WP_SAMPLING / WP_GLOSSY_MODEL the strategies (bsdf.h); WP_HAVE_EMISSION the
// emission term; WP_HAVE_NEE (scene has emitters or an environment and WP_SAMPLING is NEE
// or MIS) the light sampling; WP_RR_DEPTH the first bounce at which Russian roulette may
// end a path (< 0: off); WP_HAVE_NORMALS, WP_HAVE_TEXTURES, WP_HAVE_NORMAL_MAPS and
// WP_HAVE_ENV the appearance features (all 0 without options: a scene without them
// compiles none of their code). WP_SHADE_TRACES_SHADOWS (shade_surface8 only;
// KernelConfig::shade_traces_shadows: the lane kernel with light sampling and no cut-outs)
// makes the kernel trace its own shadow rays (below, at shade_surface8) through the BVH
// passed after its other arguments (bvh_nodes, bvh_links, bvh_tris, bvh_prim_ids: the
// intersect stage's), so nothing goes into the shadow queue but the count in shadow_count.
// WP_SHADE_FINAL (KernelConfig::shade_final) adds shade_final, the last bounce's tracing
// and emission in one launch where escaped rays carry no light (below, before
// shade_triangle_frames).
// Emission is one-sided: only the front face (counter-clockwise winding normal) emits.
// Shading normals shape the BSDF only; geometric normals decide sides, ray offsets and
// which directions are reflections (shading.h lists the failure modes and their guards).
#include "shared/bsdf.h"
#include "shared/envmap.h"
#include "shared/film.h"
#include "shared/lights.h"
#include "shared/offset.h"
#include "shared/queue_store.h"
#include "shared/rng.h"
#include "shared/shading.h"
#include "shared/texture.h"

// Without options: the generic program of the shipped estimator (estimator.h).
#ifndef WP_HAVE_EMISSION
#define WP_HAVE_EMISSION 1
#endif
#ifndef WP_HAVE_NEE
#define WP_HAVE_NEE (WP_SAMPLING == WP_SAMPLING_NEE || WP_SAMPLING == WP_SAMPLING_MIS)
#endif
#ifndef WP_RR_DEPTH
#define WP_RR_DEPTH WP_DEFAULT_RR_DEPTH
#endif
#ifndef WP_HAVE_NORMALS
#define WP_HAVE_NORMALS 0
#endif
#ifndef WP_HAVE_TEXTURES
#define WP_HAVE_TEXTURES 0
#endif
#ifndef WP_HAVE_NORMAL_MAPS
#define WP_HAVE_NORMAL_MAPS 0
#endif
#ifndef WP_HAVE_ENV
#define WP_HAVE_ENV 0
#endif
// Shadow segments end where the light's clearance begins (light_clearance; offset.h,
// wp_shadow_end_clear): compiled with light sampling unless --light-clearance off.
#ifndef WP_HAVE_LIGHT_CLEARANCE
#define WP_HAVE_LIGHT_CLEARANCE 0
#endif
#ifndef WP_HAVE_ANISOTROPY
#define WP_HAVE_ANISOTROPY 0
#endif

// The light arrays of shade_surface, bundled for the helpers.
typedef struct LightTable {
    WP_GLOBAL const float* cdf;
    WP_GLOBAL const int* guide;  // guide_size + 1 entries (wp_light_pick)
    WP_GLOBAL const int* prims;
    WP_GLOBAL const float* pdf_area;
    WP_GLOBAL const LightPair* pairs;  // with WP_HAVE_LIGHT_PAIRS (lights.h)
    WP_GLOBAL const float* clearance;  // with WP_HAVE_LIGHT_CLEARANCE
    int count;
    int guide_size;
} LightTable;

// The appearance arrays of shade_surface (placeholders for features the scene lacks).
typedef struct Appearance {
    WP_GLOBAL const TriNormals* normals;
    WP_GLOBAL const TriUVs* uvs;
    WP_GLOBAL const TriTangents* tangents;
    WP_GLOBAL const MaterialTextures* material_textures;
    TexturePool pool;
    EnvLight env;
    float env_distance;  // length of a shadow ray towards the environment (beyond the scene)
    float cone_spread;   // growth of the ray cone's width per unit length
} Appearance;

// Probability that next-event estimation samples the environment rather than a triangle:
// none for a black environment (scale 0: an --env-scale 0, or the generic kernels' stand-in
// for a scene without one) when there are triangles to sample.
WP_FN float wp_env_choice(int light_count, EnvData env) {
#if WP_HAVE_ENV
    if (light_count == 0) return 1.0f;
    return env.scale.x > 0.0f || env.scale.y > 0.0f || env.scale.z > 0.0f ? 0.5f : 0.0f;
#else
    (void)light_count;
    (void)env;
    return 0.0f;
#endif
}

#if WP_HAVE_TEXTURES
// The texture coordinates at barycentrics (u, v) of triangle `prim`.
WP_FN float2 wp_hit_uv(Appearance a, int prim, float u, float v) {
    return wp_interpolate_uv(a.uvs[prim], u, v);
}

// log2 of the ray cone's footprint in uv units on triangle `prim` (Akenine-Möller et al.,
// "Improved Shader and Texture Level of Detail Using Ray Cones", JCGT 10(1), 2021, eq. 34
// without the texture's size, which wp_texture_view adds): the cone's width over the
// cosine, scaled by sqrt(uv area / world area).
WP_FN float wp_footprint_lod(Appearance a, int prim, float3 e1, float3 e2, float width, float cos_abs) {
    TriUVs t = a.uvs[prim];
    float du1 = t.uv01.z - t.uv01.x, dv1 = t.uv01.w - t.uv01.y;
    float du2 = t.uv2.x - t.uv01.x, dv2 = t.uv2.y - t.uv01.y;
    float uv_area = fabs(du1 * dv2 - du2 * dv1);
    float world_area = length(cross(e1, e2));
    float lod = 0.5f * log2(uv_area / world_area) + log2(width / max(cos_abs, 1e-6f));
    return isnan(lod) ? -FLT_MAX : lod;  // 0/0 (degenerate uvs): level 0
}

// The material at a hit with its textures applied (albedo, roughness, emission).
WP_FN MaterialData wp_textured_material(MaterialData m, MaterialTextures mt, TexturePool pool,
                                        float2 uv, float lod) {
    if (mt.albedo >= 0) {
        float4 c = wp_texture_view(pool, mt.albedo, uv, lod);
        m.albedo = make_float4(m.albedo.x * c.x, m.albedo.y * c.y, m.albedo.z * c.z, 0.0f);
    }
    if (mt.roughness >= 0) {
        float g = wp_texture_view(pool, mt.roughness, uv, lod).y;
        m.alpha = max(m.alpha * g * g, 1e-4f);
        m.alpha_v = max(m.alpha_v * g * g, 1e-4f);  // (= alpha when isotropic)
    }
    if (mt.emission >= 0) {
        float4 c = wp_texture_view(pool, mt.emission, uv, lod);
        m.emission = make_float4(m.emission.x * c.x, m.emission.y * c.y, m.emission.z * c.z, 0.0f);
    }
    return m;
}
#endif

#if WP_HAVE_ANISOTROPY
// dp/du of a triangle with edges e1 = p1 − p0, e2 = p2 − p0 and uvs t; e1 (dp/du of the
// uvs (0, 0), (1, 0), (0, 1)) where the uvs are degenerate.
WP_FN float3 wp_triangle_dpdu(float3 e1, float3 e2, TriUVs t) {
    float du1 = t.uv01.z - t.uv01.x, dv1 = t.uv01.w - t.uv01.y;
    float du2 = t.uv2.x - t.uv01.x, dv2 = t.uv2.y - t.uv01.y;
    float det = du1 * dv2 - dv1 * du2;
    if (!(fabs(det) > 0.0f)) return e1;
    float3 d = (e1 * dv2 - e2 * dv1) * (1.0f / det);
    return wp_all_finite3(d) ? d : e1;
}
#endif

// Adds v to radiance[item] when finite; counts it otherwise. A zero v (a miss in a scene
// with a black background) skips the read-modify-write: radiance[item] + 0 is radiance[item],
// and the load of a random item in the wave is a cache miss (10 % of shade_surface8's time on
// the built-in box before this test).
WP_FN void wp_add_radiance(WP_GLOBAL float4* radiance, int item, float3 v, WP_GLOBAL int* counters) {
    if (v.x == 0.0f && v.y == 0.0f && v.z == 0.0f) return;
    if (wp_all_finite3(v))
        radiance[item] += wp_float4(v, 0.0f);
    else
        wp_atomic_inc(&counters[WP_COUNTER_SHADE_NONFINITE]);
}

// Shades one path. Returns 1 and fills *next_ray / *next_path when the path continues, and
// sets *shadow = 1 with *shadow_ray and its unoccluded contribution *contrib when it pushes
// a shadow ray.
WP_FN int wp_shade_path(Ray ray, PathState path, Hit hit, WP_GLOBAL const Triangle* tris,
                        WP_GLOBAL const float4* tri_frames, WP_GLOBAL const int* material_ids, WP_GLOBAL const MaterialData* materials,
                        WP_GLOBAL const float* material_tables, float4 background,
                        LightTable lights, Appearance app, uint seed, int bounce, int max_depth,
                        WP_GLOBAL float4* radiance,
                        WP_GLOBAL int* counters, Ray* next_ray, PathState* next_path,
                        int* shadow, Ray* shadow_ray, float4* contrib) {
    float3 beta = wp_xyz(path.throughput);
    float3 d = wp_xyz(ray.dir);
    const uint pixel = (uint)path.pixel, sample = path.sample;
    // The last bounce was a Dirac lobe (camera rays, bounce 0, count as not specular).
    const int arrived_specular = bounce > 0 && path.throughput.w == 0.0f;
    *shadow = 0;
#if WP_INJECT_NAN
    if (bounce == 0 && wp_inject_here(WP_INJECT_SHADE, path.pixel)) beta.x = wp_quiet_nan();
#endif
    // Entry guard: a path whose throughput is not finite ends here, counted.
    if (!wp_all_finite3(beta)) {
        wp_atomic_inc(&counters[WP_COUNTER_SHADE_NONFINITE]);
        return 0;
    }

    // Escaped: the constant background, and the environment weighted against light
    // sampling where that could have drawn this direction too.
    if (hit.prim < 0) {
        float3 le = wp_xyz(background);
#if WP_HAVE_ENV
        {
            float3 dn_miss = normalize(d);
            float w = 1.0f;
#if WP_HAVE_NEE
            if (bounce > 0 && !arrived_specular) {
#if WP_SAMPLING == WP_SAMPLING_MIS
                float p_env = wp_env_choice(lights.count, app.env.data) * wp_env_pdf(app.env, dn_miss);
                w = wp_power_heuristic(path.throughput.w, p_env);
#else
                w = 0.0f;  // NEE only: light sampling alone counts the environment
#endif
            }
#endif
            if (w > 0.0f) le = le + wp_env_radiance(app.env, dn_miss) * w;
        }
#endif
        wp_add_radiance(radiance, path.item, beta * le, counters);
        return 0;
    }

    // Surface: geometric normal (counter-clockwise front) and the barycentric hit point,
    // which is more accurate than o + t d (Wächter & Binder 2019).
    Triangle tri = tris[hit.prim];
    const float4 frame = tri_frames[hit.prim];
    MaterialData m = materials[material_ids[hit.prim]];
    float3 v0 = wp_xyz(tri.v0), v1 = wp_xyz(tri.v1), v2 = wp_xyz(tri.v2);
    float3 n = wp_xyz(frame);
    int front = dot(d, n) < 0.0f;
    float3 dn = normalize(d);
#if WP_HAVE_TEXTURES
    // The ray cone's width here (Akenine-Möller et al. 2021, constant spread): the texture
    // footprint. Without textures the cone is not tracked (it stays 0).
    float cone = path.cone + app.cone_spread * hit.t * length(d);
    MaterialTextures mt = app.material_textures[material_ids[hit.prim]];
    float2 uv = wp_hit_uv(app, hit.prim, hit.u, hit.v);
    float lod = wp_footprint_lod(app, hit.prim, v1 - v0, v2 - v0, cone, fabs(dot(dn, n)));
    m = wp_textured_material(m, mt, app.pool, uv, lod);
#endif

#if WP_HAVE_EMISSION
    // Emission of the front face, weighted against light sampling where that could have
    // found this point too (non-specular previous bounce of a path that continued).
    if (front && wp_max_component(wp_xyz(m.emission)) > 0.0f) {
        float w = 1.0f;
#if WP_HAVE_NEE
        // Light sampling at the previous vertex could have drawn this point (not after a
        // Dirac lobe); it sees it from the ray's origin (lights.h).
        const int could_sample = bounce > 0 && !arrived_specular;
        float pdf_area = (could_sample ? wp_light_pdf_area(lights.pdf_area, lights.pairs, tris, tri_frames,
                                                           hit.prim, wp_xyz(ray.org))
                                       : lights.pdf_area[hit.prim]) *
                         (1.0f - wp_env_choice(lights.count, app.env.data));
        if (could_sample && pdf_area > 0.0f) {
#if WP_SAMPLING == WP_SAMPLING_MIS
            // Light density of this direction over solid angle at the previous vertex.
            float dist = hit.t * length(d);
            float p_light = wp_light_pdf_solid_angle(pdf_area, dist * dist, -dot(dn, n));
            w = wp_power_heuristic(path.throughput.w, p_light);
#else
            w = 0.0f;  // NEE only: light sampling alone counts this light
#endif
        }
#endif
        if (w > 0.0f) wp_add_radiance(radiance, path.item, beta * wp_xyz(m.emission) * w, counters);
    }
#endif
    if (bounce >= max_depth) return 0;

    // ng: the geometric normal on the side the ray arrived from; ns: the shading normal
    // on that side (ng itself without shading normals).
    float3 ng = front ? n : -n;
    float3 ns = ng;
#if WP_HAVE_NORMALS
    // Chiang et al.'s terminator factor is for interpolated normals on coarse meshes; a
    // normal map's own shading is kept as authored (as Mitsuba 3 and pbrt-v4 render it).
    int terminator = 0;
    {
        float3 nf = wp_interpolated_normal(app.normals[hit.prim], hit.u, hit.v, n);
        terminator = 1;
#if WP_HAVE_NORMAL_MAPS
        if (mt.normal >= 0) {
            TriTangents tt = app.tangents[hit.prim];
            float3 t3 = wp_interpolate3(tt.t0, tt.t1, tt.t2, hit.u, hit.v);
            float4 c = wp_texture_view(app.pool, mt.normal, uv, lod);
            float3 mv = make_float3((2.0f * c.x - 1.0f) * mt.normal_scale,
                                    (2.0f * c.y - 1.0f) * mt.normal_scale, 2.0f * c.z - 1.0f);
            nf = wp_apply_normal_map(nf, make_float4(t3.x, t3.y, t3.z, tt.t0.w), mv);
            terminator = 0;
        }
#endif
        ns = front ? nf : -nf;
        // A triangle without vertex normals (wp_interpolated_normal gave the face normal
        // itself) shades exactly as a build without the feature: the guards below are for
        // ns != ng, where the terminator factor would be 1 only up to rounding and the bend
        // would tilt the face normal seen within cos θ < WP_BEND_EPS of grazing.
        const int smooth = nf.x != n.x || nf.y != n.y || nf.z != n.z;
        if (!smooth) terminator = 0;
        // Failure mode 1 (shading.h): always where the viewer sees the back of ns; for
        // lobes around the mirror direction also where that direction falls below.
        if (smooth && (m.kind != WP_MATERIAL_DIFFUSE || dot(-dn, ns) <= 0.0f))
            ns = wp_bend_normal(ns, ng, -dn);
    }
#endif
#if WP_HAVE_ANISOTROPY
    // Anisotropic roughness runs along dp/du (from the uvs; p1 − p0 where they are
    // degenerate or absent, as Mitsuba 3 and pbrt-v4 do), given to the BSDF as its direction
    // in the local frame of ns (microfacet.h).
    if (m.alpha != m.alpha_v) {
        float3 t = wp_triangle_dpdu(v1 - v0, v2 - v0, app.uvs[hit.prim]);
        float3 tx, ty;
        wp_onb(ns, &tx, &ty);
        float c = dot(t, tx), s = dot(t, ty), l = sqrt(c * c + s * s);
        if (l > 0.0f) m.aniso_cos = c / l, m.aniso_sin = s / l;
    }
#endif
    float3 perr;
    float3 p = wp_hit_point(v0, v1, v2, hit.u, hit.v, &perr);
    float tri_offset = frame.w;
    float3 org = wp_offset_ray_origin(p, perr, ng, tri_offset);

#if WP_HAVE_NEE
    // Next-event estimation: a point on a light chosen by power, or a direction of the
    // environment; the shadow ray is traced by the shadow stage, which adds *contrib to the
    // radiance when it is unoccluded.
    if (!wp_material_is_specular(m) && (lights.count > 0 || WP_HAVE_ENV)) {
        float4 ul = wp_rng4(seed, pixel, sample, (uint)bounce, WP_RNG_LIGHT);
        float p_env = wp_env_choice(lights.count, app.env.data);
        float3 wi;
        int lp = -1;  // the light triangle (-1: the environment)
        // The light point (triangle lights): the shadow ray's end is computed only for a
        // contribution that is pushed.
        float3 l0 = make_float3(0.0f, 0.0f, 0.0f), l1 = l0, l2 = l0, ln = l0, y = l0, yerr = l0;
        float l_offset = 0.0f;  // the light triangle's offset share
        int env_sample = 0;
#if WP_HAVE_TEXTURES
        float2 lbl = make_float2(0.0f, 0.0f);  // the light point's barycentrics
#endif
        float p_light = 0.0f;
#if WP_HAVE_ENV
        if (ul.w < p_env) {
            float pdf_dir;
            wi = wp_env_sample(app.env, ul.x, ul.y, &pdf_dir);
            p_light = p_env * pdf_dir;
            env_sample = 1;
        } else
#endif
        {
            int li = wp_light_pick(lights.cdf, lights.count, lights.guide, lights.guide_size, ul.z);
            lp = lights.prims[li];
            float lpdf;  // the light point's density per unit area
#if WP_HAVE_LIGHT_PAIRS
            // A triangle facing away gives its sample to its partner (lights.h).
            lp = wp_light_pair_choose(lights.pdf_area, lights.pairs, tris, tri_frames, lp, org, &lpdf);
#else
            lpdf = lights.pdf_area[lp];
#endif
            Triangle lt = tris[lp];
            l0 = wp_xyz(lt.v0), l1 = wp_xyz(lt.v1), l2 = wp_xyz(lt.v2);
            const float4 lframe = tri_frames[lp];
            ln = wp_xyz(lframe);
            l_offset = lframe.w;
            float2 bl = wp_sample_triangle_barycentric(ul.x, ul.y);
            y = wp_hit_point(l0, l1, l2, bl.x, bl.y, &yerr);
            float3 to = y - p;
            float dist2 = dot(to, to);
            wi = to * (1.0f / sqrt(dist2));
            p_light = wp_light_pdf_solid_angle(lpdf * (1.0f - p_env), dist2, -dot(wi, ln));
#if WP_HAVE_TEXTURES
            lbl = bl;
#endif
        }
        // Light on the geometric side the BSDF lobe is on only: above for a reflection,
        // below for a transmission (failure mode 2). The BSDF itself returns zero below the
        // surface unless the kind transmits. (Without shading normals ns = ng, and the
        // BSDF's own cosine test is that test.)
        float bsdf_pdf = 0.0f;
#if WP_HAVE_NORMALS
        float3 fcos = make_float3(0.0f, 0.0f, 0.0f);
        if (wp_same_side(wi, ns, ng))
            fcos = wp_bsdf_eval(m, material_tables, dn, ns, front, wi, &bsdf_pdf);
        if (terminator) fcos = fcos * wp_terminator_factor(ng, ns, wi);  // failure mode 3
#else
        float3 fcos = wp_bsdf_eval(m, material_tables, dn, ns, front, wi, &bsdf_pdf);
#endif
        if (p_light > 0.0f && wp_max_component(fcos) > 0.0f) {
            float w = 1.0f;
#if WP_SAMPLING == WP_SAMPLING_MIS
            w = wp_power_heuristic(p_light, bsdf_pdf);
#endif
            // The light's radiance towards the shading point (looked up only now).
            float3 le;
#if WP_HAVE_ENV
            if (env_sample) {
                le = wp_env_radiance(app.env, wi);
            } else
#endif
            {
                le = wp_xyz(materials[material_ids[lp]].emission);
#if WP_HAVE_TEXTURES
                MaterialTextures lmt = app.material_textures[material_ids[lp]];
                if (lmt.emission >= 0)
                    le = le * wp_xyz(wp_texture_view(app.pool, lmt.emission,
                                                     wp_hit_uv(app, lp, lbl.x, lbl.y), -FLT_MAX));
#endif
            }
            float3 c = beta * fcos * le * (w / p_light);
            if (!wp_all_finite3(c)) {
                wp_atomic_inc(&counters[WP_COUNTER_SHADE_NONFINITE]);
            } else if (wp_max_component(c) > 0.0f) {
                // From the origin offset to the geometric side the light is on (below the
                // surface: a transmission). Towards the environment: a segment beyond the
                // scene (hits need 0 < t < 1); to a triangle: towards the light point, ending
                // short of the light by the error of the segment's own triangle tests
                // (offset.h).
                float3 so = dot(wi, ng) > 0.0f ? org : wp_offset_ray_origin(p, perr, -ng, tri_offset);
                float3 sd = env_sample ? wi * app.env_distance : y - so;
                float tmax = env_sample ? 1.0f : wp_shadow_tmax(sd, yerr, ln, l_offset);
#if WP_HAVE_LIGHT_CLEARANCE
                if (!env_sample) tmax = wp_shadow_end_clear(tmax, sd, y, yerr, ln, lights.clearance[lp]);
#endif
                shadow_ray->org = make_float4(so.x, so.y, so.z, 0.0f);
                shadow_ray->dir = make_float4(sd.x, sd.y, sd.z, tmax);
                *contrib = wp_float4(c, 0.0f);
                *shadow = 1;
            }
        }
    }
#endif

    // Scatter: sample the material on the side the ray came from.
    float4 u = wp_rng4(seed, pixel, sample, (uint)bounce, WP_RNG_BSDF);
    float3 wo, weight;
    float pdf;
    int specular;
    if (!wp_bsdf_sample_pdf(m, material_tables, dn, ns, front, u, &wo, &weight, &pdf, &specular))
        return 0;
    if (!specular && !(pdf > 0.0f)) return 0;  // a zero-density draw (measure zero): absorbed
#if WP_HAVE_NORMALS
    // A reflection below the geometric surface or a transmission that stays above it is
    // absorbed (failure mode 2); non-specular reflections get the terminator factor (3).
    if (!wp_same_side(wo, ns, ng)) return 0;
    if (terminator && !specular && dot(wo, ng) > 0.0f) weight = weight * wp_terminator_factor(ng, ns, wo);
#endif
    beta = beta * weight;
    if (!wp_all_finite3(beta) || !wp_all_finite3(wo)) {
        wp_atomic_inc(&counters[WP_COUNTER_SHADE_NONFINITE]);
        return 0;
    }
    if (!(wp_max_component(beta) > 0.0f)) return 0;  // black: nothing more to gather

#if WP_RR_DEPTH >= 0
    // Russian roulette from bounce WP_RR_DEPTH on: survive with q = min(1, max component
    // of the throughput) and divide by q, so the estimate stays unbiased.
    if (bounce >= WP_RR_DEPTH) {
        float q = min(1.0f, wp_max_component(beta));
        float4 ur = wp_rng4(seed, pixel, sample, (uint)bounce, WP_RNG_RR);
        if (ur.x >= q) return 0;
        beta = beta * (1.0f / q);
    }
#endif

    // The continued path, from a robustly offset origin on the geometric side it leaves.
    float3 org_next = dot(wo, ng) > 0.0f ? org : wp_offset_ray_origin(p, perr, -ng, tri_offset);
    next_ray->org = make_float4(org_next.x, org_next.y, org_next.z, 0.0f);
    next_ray->dir = make_float4(wo.x, wo.y, wo.z, FLT_MAX);
    *next_path = path;
    // w: the density of wo; 0 marks a specular bounce (PathState).
    next_path->throughput = wp_float4(beta, specular ? 0.0f : pdf);
#if WP_HAVE_TEXTURES
    next_path->cone = cone;
#endif
    return 1;
}

// The pushes of shade_surface and shade_surface8: a ray and a path state into the next
// bounce's queue (wp_store_path, queue_store.h), and an entry into the shadow queue (below),
// each field one 16- or 4-byte store (WP_STORE_STREAM: non-temporal where the kernel is
// built with WP_STREAM_STORES).
WP_FN void wp_push_shadow(WP_GLOBAL Ray* ray_q, WP_GLOBAL int* item_q, WP_GLOBAL float4* contrib_q, Ray r,
                          int item, float4 contrib) {
    WP_STORE_STREAM(&ray_q->org, r.org);
    WP_STORE_STREAM(&ray_q->dir, r.dir);
    WP_STORE_STREAM(item_q, item);
    WP_STORE_STREAM(contrib_q, contrib);
}

#ifndef WP_SHADE_TRACES_SHADOWS
#define WP_SHADE_TRACES_SHADOWS 0
#endif
#ifndef WP_SHADE_FINAL
#define WP_SHADE_FINAL 0
#endif
// (One include for both: the program loader inlines a header at its first #include only,
// whatever the conditions around it: cl/program.cpp.)
#if WP_SHADE_TRACES_SHADOWS || WP_SHADE_FINAL
#include "shared/bvh_traverse.h"
#endif
#if WP_SHADE_TRACES_SHADOWS
#define WP_SHADE_BVH_PARAMS \
    , WP_GLOBAL const BvhNode *bvh_nodes, WP_GLOBAL const BvhLinks *bvh_links, \
        WP_GLOBAL const TriBlock *bvh_tris, WP_GLOBAL const int *bvh_prim_ids
#else
#define WP_SHADE_BVH_PARAMS
#endif
// The parameters of shade_surface and shade_surface8 (the host passes the same arguments
// to either: render/stages/shade.cpp).
#define WP_SHADE_SURFACE_PARAMS \
    WP_GLOBAL const Ray* rays_in, WP_GLOBAL const PathState* paths_in, \
    WP_GLOBAL const int* count_in, WP_GLOBAL const Hit* hits, \
    WP_GLOBAL const Triangle* tris, WP_GLOBAL const float4* tri_frames, \
    WP_GLOBAL const int* material_ids, WP_GLOBAL const MaterialData* materials, \
    WP_GLOBAL const float* material_tables, float4 background, \
    WP_GLOBAL const float* light_cdf, WP_GLOBAL const int* light_guide, \
    int light_guide_size, WP_GLOBAL const int* light_prims, \
    WP_GLOBAL const float* light_pdf_area, WP_GLOBAL const LightPair* light_pairs, \
    WP_GLOBAL const float* light_clearance, \
    int light_count, \
    WP_GLOBAL const TriNormals* tri_normals, WP_GLOBAL const TriUVs* tri_uvs, \
    WP_GLOBAL const TriTangents* tri_tangents, \
    WP_GLOBAL const MaterialTextures* material_textures, \
    WP_GLOBAL const TextureData* textures, WP_GLOBAL const TextureView* texture_views, \
    WP_GLOBAL const uint* texels8, WP_GLOBAL const float4* texelsf, EnvData env, \
    WP_GLOBAL const float4* env_texels, WP_GLOBAL const float* env_marginal, \
    WP_GLOBAL const float* env_conditional, float env_distance, float cone_spread, \
    uint seed, int bounce, int max_depth, WP_GLOBAL float4* radiance, \
    WP_GLOBAL int* counters, WP_GLOBAL Ray* rays_out, WP_GLOBAL PathState* paths_out, \
    WP_GLOBAL int* count_out, WP_GLOBAL Ray* shadow_rays, WP_GLOBAL int* shadow_items, \
    WP_GLOBAL float4* shadow_contrib, WP_GLOBAL int* shadow_count WP_SHADE_BVH_PARAMS

// The light table and the appearance arrays of wp_shade_path from the kernel parameters
// (WP_SHADE_SURFACE_PARAMS): declares `lights` and `app`.
#define WP_SHADE_TABLES                           \
    LightTable lights;                            \
    lights.cdf = light_cdf;                       \
    lights.guide = light_guide;                   \
    lights.guide_size = light_guide_size;         \
    lights.prims = light_prims;                   \
    lights.pdf_area = light_pdf_area;             \
    lights.pairs = light_pairs;                   \
    lights.clearance = light_clearance;           \
    lights.count = light_count;                   \
    Appearance app;                               \
    app.normals = tri_normals;                    \
    app.uvs = tri_uvs;                            \
    app.tangents = tri_tangents;                  \
    app.material_textures = material_textures;    \
    app.pool.textures = textures;                 \
    app.pool.views = texture_views;               \
    app.pool.texels8 = texels8;                   \
    app.pool.texelsf = texelsf;                   \
    app.env.data = env;                           \
    app.env.texels = env_texels;                  \
    app.env.marginal = env_marginal;              \
    app.env.conditional = env_conditional;        \
    app.env_distance = env_distance;              \
    app.cone_spread = cone_spread;

// The pushes are aggregated per work-group: every work-item posts what it pushes in a
// local array, work-item 0 turns that into slots (a prefix sum in work-item order) and
// reserves the group's range with a single global atomic add per queue (1 global atomic
// per WP_GROUP_SIZE paths instead of one per path). No local atomics: on PoCL a work-group
// runs on one thread, where each local atomic_inc was a locked instruction per path (5.6 %
// of shade's samples under perf). Every work-item reaches the barriers.
#if !WP_SHADE_LANES  // (a program holds one of the two shade kernels: the lane one below)
WP_KERNEL void shade_surface(WP_SHADE_SURFACE_PARAMS) {
    // posts[lid]: bit 0 pushes a path, bit 1 a shadow ray; then (work-item 0) the path slot
    // in bits 0-15 and the shadow slot in bits 16-31, relative to the group's bases.
    WP_LOCAL int posts[WP_GROUP_SIZE];
    WP_LOCAL int group_base, shadow_group_base;
    int i = wp_global_id();
    int lid = wp_local_id();

    WP_SHADE_TABLES
    Ray next_ray, shadow_ray;
    PathState next_path;
    float4 contrib = make_float4(0.0f, 0.0f, 0.0f, 0.0f);
    int push = 0, shadow = 0, item = 0;
    if (i < count_in[0]) {
        PathState path = paths_in[i];
        item = path.item;
        push = wp_shade_path(rays_in[i], path, hits[i], tris, tri_frames, material_ids, materials,
                             material_tables, background, lights, app, seed, bounce, max_depth,
                             radiance, counters, &next_ray, &next_path, &shadow, &shadow_ray,
                             &contrib);
    }
    posts[lid] = (push ? 1 : 0) | (shadow ? 2 : 0);
    wp_barrier();
    if (lid == 0) {
        int paths = 0, shadows = 0;
        for (int j = 0; j < WP_GROUP_SIZE; ++j) {
            int post = posts[j];
            posts[j] = paths | (shadows << 16);
            paths += post & 1;
            shadows += post >> 1;
        }
        group_base = paths > 0 ? wp_atomic_add(count_out, paths) : 0;
        shadow_group_base = shadows > 0 ? wp_atomic_add(shadow_count, shadows) : 0;
    }
    wp_barrier();
    int local_slot = posts[lid] & 0xffff, shadow_local_slot = posts[lid] >> 16;
    if (push) {
        int slot = group_base + local_slot;
        wp_store_path(rays_out + slot, paths_out + slot, next_ray, next_path);
    }
    if (shadow) {
        int slot = shadow_group_base + shadow_local_slot;
        wp_push_shadow(shadow_rays + slot, shadow_items + slot, shadow_contrib + slot, shadow_ray, item, contrib);
    }
}
#endif

#if WP_SHADE_FINAL
// shade_final — the last bounce (bounce == max_depth) in one launch, where escaped rays carry
// no light (KernelConfig::shade_final: the renderer traces the last bounce through the
// emitters' BVH, render --final-rays; no cut-outs, no NaN injection). It replaces the
// intersect_final launch and the shade launch of that bounce: each queued ray is traced as
// intersect_final traces it (wp_trace_final: the emitters' BVH e_* first, then the scene,
// f_*, up to the emitter it meets), and only a ray that meets an emitter is shaded, by
// wp_shade_path as shade_surface shades it (at the last bounce: the MIS-weighted emission of
// a front face). Every other ray adds nothing there: an escaped ray the black background, a
// hit on a surface that does not emit nothing, and no path scatters at the last bounce; so
// no hit is written and no other entry read. Throughputs are finite at every bounce (shade
// pushes none that is not, generate starts at 1), so shade's entry guard would count none.
// The same image bit for bit (tests/test_render.cpp, against render --final-rays closest).
// One work-item per queue entry. The arguments: shade_surface's, then the scene's BVH and the
// emitters' BVH.
WP_KERNEL void shade_final(WP_SHADE_SURFACE_PARAMS, WP_GLOBAL const BvhNode* f_nodes,
                           WP_GLOBAL const BvhLinks* f_links, WP_GLOBAL const TriBlock* f_tris,
                           WP_GLOBAL const int* f_prim_ids, WP_GLOBAL const BvhNode* e_nodes,
                           WP_GLOBAL const BvhLinks* e_links, WP_GLOBAL const TriBlock* e_tris,
                           WP_GLOBAL const int* e_prim_ids) {
    (void)rays_out, (void)paths_out, (void)count_out, (void)shadow_rays, (void)shadow_items;
    (void)shadow_contrib, (void)shadow_count;
    const int i = wp_global_id();
    if (i >= count_in[0]) return;
    TraceStats st = {0, 0};
    const Ray ray = rays_in[i];
    Hit h;
    wp_trace_final(ray, f_nodes, f_links, f_tris, f_prim_ids, e_nodes, e_links, e_tris, e_prim_ids, &h, &st);
    if (h.prim < 0) return;  // no emitter on the ray
    WP_SHADE_TABLES
    Ray next_ray, shadow_ray;
    PathState next_path;
    float4 contrib;
    int shadow;
    wp_shade_path(ray, paths_in[i], h, tris, tri_frames, material_ids, materials, material_tables,
                  background, lights, app, seed, bounce, max_depth, radiance, counters, &next_ray,
                  &next_path, &shadow, &shadow_ray, &contrib);
}
#endif

// shade_triangle_frames — run once per scene before the first shade_surface (ShadeStage::
// prepare): tri_frames[t] = wp_triangle_frame of triangle t for t < count. Every hit on t and
// every light sample on it reads the frame instead of computing it again.
WP_KERNEL void shade_triangle_frames(WP_GLOBAL const Triangle* tris, int count,
                                     WP_GLOBAL float4* tri_frames) {
    int t = wp_global_id();
    if (t >= count) return;
    Triangle tri = tris[t];
    tri_frames[t] = wp_triangle_frame(wp_xyz(tri.v0), wp_xyz(tri.v1), wp_xyz(tri.v2));
}

#if WP_SHADE_LANES
// ---------------------------------------------------------------------------------------
// shade_surface8 — shade_surface eight paths at a time in vector lanes (shared/lanes.h
// explains why: PoCL runs shade_surface one path at a time). Same arguments, same contract
// and the same numbers per path; the host launches it with one work-item per
// WP_SHADE_LANE_ENTRIES queue entries (types.h; work-item w: entries 64 w .. 64 w + 63) and
// local size WP_SHADE_LANE_GROUP where KernelConfig::shade_lanes() says it models
// the scene: the features and debug switches it has no lane code for are refused here at
// compile time. Diffuse, mirror, glossy and rough-conductor lanes run lane code (lanes.h);
// the lanes of every other kind call that kind's scalar sample and eval (bsdf.h) one lane at
// a time, inside
// the same lane code for the rest of the vertex (emission, light sampling, the normals'
// guards, roulette, pushes).
#if WP_HAVE_TEXTURES || WP_HAVE_NORMAL_MAPS || WP_HAVE_ENV || WP_HAVE_ANISOTROPY || WP_INJECT_NAN
#error "shade_surface8 models shading normals and no other appearance feature (KernelConfig::shade_lanes)"
#endif
#if WP_SHADE_LANE_ENTRIES % 8 != 0 || WP_SHADE_LANE_ENTRIES > 64
#error "WP_SHADE_LANE_ENTRIES (types.h) must be a multiple of 8 and at most 64 (the bits of push_bits)"
#endif
// Kinds without lane code: their lanes take the scalar BSDF (WP_LANES_SCALAR_KINDS).
#define WP_LANES_SCALAR_KINDS                                                             \
    (WP_HAVE_GLASS || WP_HAVE_CONDUCTOR || WP_HAVE_ROUGH_DIELECTRIC || WP_HAVE_THIN_DIELECTRIC || \
     WP_HAVE_PLASTIC || WP_HAVE_ROUGH_PLASTIC)
#include "shared/lanes.h"
#include "shared/rng_lanes.h"

// Counts the lanes of mask m in counters[WP_COUNTER_SHADE_NONFINITE].
WP_FN void wp_count_nonfinite8(int8 m, WP_GLOBAL int* counters) {
    int n = popcount(wp_lane_bits(m));
    if (n > 0) wp_atomic_add(&counters[WP_COUNTER_SHADE_NONFINITE], n);
}

// Adds lane l of c to radiance[item[l]] for the lanes of mask m (wp_add_radiance).
WP_FN void wp_add_radiance8(WP_GLOBAL float4* radiance, const int* item, int8 m, L3 c,
                            WP_GLOBAL int* counters) {
    int bits = wp_lane_bits(m);
    if (bits == 0) return;
    float cx[8], cy[8], cz[8];
    vstore8(c.x, 0, cx);
    vstore8(c.y, 0, cy);
    vstore8(c.z, 0, cz);
#pragma unroll
    for (int l = 0; l < 8; ++l)
        if (bits & (1 << l)) wp_add_radiance(radiance, item[l], make_float3(cx[l], cy[l], cz[l]), counters);
}

#if WP_HAVE_NEE
// The light sample's triangle in every lane: its vertices, frame (unit normal and offset
// share, tri_frames), density per unit area (with the pair's share: lights.h), emission and
// shadow clearance (0 without WP_HAVE_LIGHT_CLEARANCE).
typedef struct LightLanes8 {
    L3 v0, v1, v2, n, le;
    float8 offset, pdf_area, clearance;
} LightLanes8;

#define WP_LIGHT_LANES_ARGS                                                                     \
    light_cdf, light_guide, light_guide_size, light_prims, light_pdf_area, light_pairs, light_clearance, \
        light_count, tris, tri_frames, material_ids, materials

// The lanes' lights, lane by lane: the light table's pick for u (lights.h's wp_light_pick;
// light 0 in the lanes outside `sampled`: no search, no miss on a random light), with light
// pairs the pair's choice from origin org (shade_surface's, wp_light_pair_choose's tests
// and answer), and the light triangle's data.
WP_FN LightLanes8 wp_light_lanes_gather8(WP_GLOBAL const float* light_cdf, WP_GLOBAL const int* light_guide,
                                         int light_guide_size, WP_GLOBAL const int* light_prims,
                                         WP_GLOBAL const float* light_pdf_area,
                                         WP_GLOBAL const LightPair* light_pairs,
                                         WP_GLOBAL const float* light_clearance, int light_count,
                                         WP_GLOBAL const Triangle* tris, WP_GLOBAL const float4* tri_frames,
                                         WP_GLOBAL const int* material_ids,
                                         WP_GLOBAL const MaterialData* materials, float8 u, int8 sampled,
                                         L3 org) {
    float ua[8];
    vstore8(u, 0, ua);
    float l0x[8], l0y[8], l0z[8], l1x[8], l1y[8], l1z[8], l2x[8], l2y[8], l2z[8];
    float lnx[8], lny[8], lnz[8], loff[8], lpa[8], lex[8], ley[8], lez[8], lcl[8];
    const int sampled_bits = wp_lane_bits(sampled);
#if WP_HAVE_LIGHT_PAIRS
    float orx[8], ory[8], orz[8];
    vstore8(org.x, 0, orx), vstore8(org.y, 0, ory), vstore8(org.z, 0, orz);
#else
    (void)light_pairs, (void)org;
#endif
    // In phases over the eight lanes, each phase's loads independent of one another, so that
    // the lanes' cache misses overlap (one lane's chain of dependent loads after another's
    // cost veach-mis' shade 8 %, measured): the picks, with pairs the pairs' entries, both
    // facing tests and the choice, then the chosen triangles' data.
    int lp_a[8];
#pragma unroll
    for (int l = 0; l < 8; ++l) {
        const int li = (sampled_bits >> l) & 1 ? wp_light_pick(light_cdf, light_count, light_guide, light_guide_size, ua[l]) : 0;
        lp_a[l] = light_prims[li];
    }
#if WP_HAVE_LIGHT_PAIRS
    {
        LightPair pt[8];
        int q_away[8], t_away[8];
#pragma unroll
        for (int l = 0; l < 8; ++l) pt[l] = light_pairs[lp_a[l]];
#pragma unroll
        for (int l = 0; l < 8; ++l) {
            const float3 x = make_float3(orx[l], ory[l], orz[l]);
            q_away[l] = wp_light_faces_away(tris, tri_frames, pt[l].partner >= 0 ? pt[l].partner : lp_a[l], x);
            t_away[l] = wp_light_faces_away(tris, tri_frames, lp_a[l], x);
        }
#pragma unroll
        for (int l = 0; l < 8; ++l) {
            if ((sampled_bits >> l) & 1)
                lp_a[l] = wp_light_pair_decide(light_pdf_area, light_pairs, lp_a[l], pt[l], q_away[l], t_away[l], &lpa[l]);
            else
                lpa[l] = light_pdf_area[lp_a[l]];
        }
    }
#endif
#pragma unroll
    for (int l = 0; l < 8; ++l) {
        const int lp = lp_a[l];
#if !WP_HAVE_LIGHT_PAIRS
        lpa[l] = light_pdf_area[lp];
#endif
        Triangle lt = tris[lp];
        float4 lf = tri_frames[lp];
        float4 le = materials[material_ids[lp]].emission;
        l0x[l] = lt.v0.x, l0y[l] = lt.v0.y, l0z[l] = lt.v0.z;
        l1x[l] = lt.v1.x, l1y[l] = lt.v1.y, l1z[l] = lt.v1.z;
        l2x[l] = lt.v2.x, l2y[l] = lt.v2.y, l2z[l] = lt.v2.z;
        lnx[l] = lf.x, lny[l] = lf.y, lnz[l] = lf.z, loff[l] = lf.w;
        lex[l] = le.x, ley[l] = le.y, lez[l] = le.z;
#if WP_HAVE_LIGHT_CLEARANCE
        lcl[l] = light_clearance[lp];
#else
        lcl[l] = 0.0f;
#endif
    }
    LightLanes8 L;
    L.v0 = l3(vload8(0, l0x), vload8(0, l0y), vload8(0, l0z));
    L.v1 = l3(vload8(0, l1x), vload8(0, l1y), vload8(0, l1z));
    L.v2 = l3(vload8(0, l2x), vload8(0, l2y), vload8(0, l2z));
    L.n = l3(vload8(0, lnx), vload8(0, lny), vload8(0, lnz));
    L.le = l3(vload8(0, lex), vload8(0, ley), vload8(0, lez));
    L.offset = vload8(0, loff);
    L.pdf_area = vload8(0, lpa);
    L.clearance = vload8(0, lcl);
    return L;
}

#if !WP_HAVE_LIGHT_PAIRS
// Light tables of at most this many lights take wp_light_lanes_few8.
#define WP_FEW_LIGHTS 4
// wp_light_lanes_gather8 without pairs for a table of n <= WP_FEW_LIGHTS lights, as vector
// operations: the pick as the count of CDF entries at or below u among the first n − 1
// (wp_cdf_pick's index for a non-decreasing CDF: the first k with u < cdf[k], else n − 1),
// each field a select among the lights' values. The same data in every lane, without eight
// scalar searches and gathers (the built-in box and Bitterli's have two light triangles).
WP_FN LightLanes8 wp_light_lanes_few8(WP_GLOBAL const float* light_cdf, WP_GLOBAL const int* light_prims,
                                      WP_GLOBAL const float* light_pdf_area,
                                      WP_GLOBAL const float* light_clearance, int n,
                                      WP_GLOBAL const Triangle* tris, WP_GLOBAL const float4* tri_frames,
                                      WP_GLOBAL const int* material_ids,
                                      WP_GLOBAL const MaterialData* materials, float8 u, int8 sampled) {
    int8 li = (int8)(0);
    for (int k = 0; k + 1 < n; ++k) li -= u >= light_cdf[k];  // a true compare is -1
    li = select((int8)(0), li, sampled);
    float8 f[18];
    for (int k = 0; k < n; ++k) {
        const int lp = light_prims[k];
        const Triangle lt = tris[lp];
        const float4 lf = tri_frames[lp];
        const float4 le = materials[material_ids[lp]].emission;
#if WP_HAVE_LIGHT_CLEARANCE
        const float cl = light_clearance[lp];
#else
        const float cl = 0.0f;
        (void)light_clearance;
#endif
        const float v[18] = {lt.v0.x, lt.v0.y, lt.v0.z, lt.v1.x, lt.v1.y, lt.v1.z, lt.v2.x, lt.v2.y, lt.v2.z,
                             lf.x,    lf.y,    lf.z,    lf.w,    light_pdf_area[lp], le.x, le.y, le.z, cl};
        const int8 m = li == k;
#pragma unroll
        for (int j = 0; j < 18; ++j) f[j] = k == 0 ? (float8)(v[j]) : select(f[j], (float8)(v[j]), m);
    }
    LightLanes8 L;
    L.v0 = l3(f[0], f[1], f[2]);
    L.v1 = l3(f[3], f[4], f[5]);
    L.v2 = l3(f[6], f[7], f[8]);
    L.n = l3(f[9], f[10], f[11]);
    L.offset = f[12];
    L.pdf_area = f[13];
    L.le = l3(f[14], f[15], f[16]);
    L.clearance = f[17];
    return L;
}
#endif
#endif

#if WP_LANES_SCALAR_KINDS
// The lanes of mask m, one at a time, through the scalar BSDF of their material (bsdf.h),
// each with exactly the scalar kernel's arguments: f cos and the density of wi into the
// lanes of *fcos and *pdf (zero and 0 where the scalar eval gives them).
WP_FN void wp_scalar_eval8(WP_GLOBAL const MaterialData* materials, WP_GLOBAL const float* tables,
                           const int* mid, int8 m, L3 dn, L3 ns, int8 front, L3 wi, L3* fcos, float8* pdf) {
    float dx[8], dy[8], dz[8], nx[8], ny[8], nz[8], wx[8], wy[8], wz[8], fx[8], fy[8], fz[8], pa[8];
    int fr[8];
    vstore8(dn.x, 0, dx), vstore8(dn.y, 0, dy), vstore8(dn.z, 0, dz);
    vstore8(ns.x, 0, nx), vstore8(ns.y, 0, ny), vstore8(ns.z, 0, nz);
    vstore8(wi.x, 0, wx), vstore8(wi.y, 0, wy), vstore8(wi.z, 0, wz);
    vstore8(fcos->x, 0, fx), vstore8(fcos->y, 0, fy), vstore8(fcos->z, 0, fz);
    vstore8(*pdf, 0, pa);
    vstore8(front, 0, fr);
    const int bits = wp_lane_bits(m);
    for (int l = 0; l < 8; ++l) {
        if (!(bits & (1 << l))) continue;
        float p = 0.0f;
        const float3 f = wp_bsdf_eval(materials[mid[l]], tables, make_float3(dx[l], dy[l], dz[l]),
                                      make_float3(nx[l], ny[l], nz[l]), fr[l] != 0,
                                      make_float3(wx[l], wy[l], wz[l]), &p);
        fx[l] = f.x, fy[l] = f.y, fz[l] = f.z, pa[l] = p;
    }
    *fcos = l3(vload8(0, fx), vload8(0, fy), vload8(0, fz));
    *pdf = vload8(0, pa);
}

// The lanes of mask m, one at a time, through their material's scalar sample (bsdf.h):
// direction, weight, density and the Dirac flag into their lanes; returns the mask of the
// lanes whose sample did not absorb the path.
WP_FN int8 wp_scalar_sample8(WP_GLOBAL const MaterialData* materials, WP_GLOBAL const float* tables,
                             const int* mid, int8 m, L3 dn, L3 ns, int8 front, float8 ux, float8 uy,
                             float8 uz, float8 uw, L3* wo, L3* weight, float8* pdf, int8* specular) {
    float dx[8], dy[8], dz[8], nx[8], ny[8], nz[8], u0[8], u1[8], u2[8], u3[8];
    float ox[8], oy[8], oz[8], gx[8], gy[8], gz[8], pa[8];
    int fr[8], sp[8], ok[8];
    vstore8(dn.x, 0, dx), vstore8(dn.y, 0, dy), vstore8(dn.z, 0, dz);
    vstore8(ns.x, 0, nx), vstore8(ns.y, 0, ny), vstore8(ns.z, 0, nz);
    vstore8(ux, 0, u0), vstore8(uy, 0, u1), vstore8(uz, 0, u2), vstore8(uw, 0, u3);
    vstore8(wo->x, 0, ox), vstore8(wo->y, 0, oy), vstore8(wo->z, 0, oz);
    vstore8(weight->x, 0, gx), vstore8(weight->y, 0, gy), vstore8(weight->z, 0, gz);
    vstore8(*pdf, 0, pa);
    vstore8(*specular, 0, sp);
    vstore8(front, 0, fr);
    const int bits = wp_lane_bits(m);
    for (int l = 0; l < 8; ++l) {
        ok[l] = 0;
        if (!(bits & (1 << l))) continue;
        float3 w, g;
        float p;
        int s;
        ok[l] = wp_bsdf_sample_pdf(materials[mid[l]], tables, make_float3(dx[l], dy[l], dz[l]),
                                   make_float3(nx[l], ny[l], nz[l]), fr[l] != 0,
                                   make_float4(u0[l], u1[l], u2[l], u3[l]), &w, &g, &p, &s) ? -1 : 0;
        if (!ok[l]) continue;
        ox[l] = w.x, oy[l] = w.y, oz[l] = w.z;
        gx[l] = g.x, gy[l] = g.y, gz[l] = g.z;
        pa[l] = p, sp[l] = s ? -1 : 0;
    }
    *wo = l3(vload8(0, ox), vload8(0, oy), vload8(0, oz));
    *weight = l3(vload8(0, gx), vload8(0, gy), vload8(0, gz));
    *pdf = vload8(0, pa);
    *specular = vload8(0, sp);
    return vload8(0, ok);
}
#endif

WP_KERNEL void shade_surface8(WP_SHADE_SURFACE_PARAMS) {
    (void)material_tables, (void)tri_normals, (void)tri_uvs, (void)tri_tangents;
    (void)material_textures, (void)textures, (void)texture_views, (void)texels8, (void)texelsf;
    (void)env_texels, (void)env_marginal, (void)env_conditional, (void)env_distance, (void)light_pairs;
    (void)light_clearance;
    (void)cone_spread;
    const int base = WP_SHADE_LANE_ENTRIES * wp_global_id();
    const int count = count_in[0];

    // What each packed lane pushes, lane by lane (filled below for the lanes of push / shadow).
    PathState ps[WP_SHADE_LANE_ENTRIES];
    int item[WP_SHADE_LANE_ENTRIES];
    float nox[WP_SHADE_LANE_ENTRIES], noy[WP_SHADE_LANE_ENTRIES], noz[WP_SHADE_LANE_ENTRIES];
    float ndx[WP_SHADE_LANE_ENTRIES], ndy[WP_SHADE_LANE_ENTRIES], ndz[WP_SHADE_LANE_ENTRIES];
    float nbx[WP_SHADE_LANE_ENTRIES], nby[WP_SHADE_LANE_ENTRIES], nbz[WP_SHADE_LANE_ENTRIES];
    float npdf[WP_SHADE_LANE_ENTRIES];
    float sox[WP_SHADE_LANE_ENTRIES], soy[WP_SHADE_LANE_ENTRIES], soz[WP_SHADE_LANE_ENTRIES];
    float sdx[WP_SHADE_LANE_ENTRIES], sdy[WP_SHADE_LANE_ENTRIES], sdz[WP_SHADE_LANE_ENTRIES];
    float stm[WP_SHADE_LANE_ENTRIES];
    float scx[WP_SHADE_LANE_ENTRIES], scy[WP_SHADE_LANE_ENTRIES], scz[WP_SHADE_LANE_ENTRIES];
    ulong push_bits = 0, shadow_bits = 0;  // bit e: packed lane e pushes (WP_SHADE_LANE_ENTRIES <= 64)

    // The work-item's queue entries one at a time: the entry guard and the escaped rays
    // (shade_surface's own code: a path whose throughput is not finite ends, counted; a miss
    // adds the constant background, no environment in this kernel), and the surface hits
    // packed into hit_e[0, nh), so that the lanes below shade surface hits only (in an open
    // scene the escaped rays would idle half of them).
    int hit_e[WP_SHADE_LANE_ENTRIES];
    int nh = 0, nonfinite = 0;
    for (int e = 0; e < WP_SHADE_LANE_ENTRIES && base + e < count; ++e) {
        const int i = base + e;
        const PathState p = paths_in[i];
        const int hprim = hits[i].prim;
        const float3 b = wp_xyz(p.throughput);
        if (!wp_all_finite3(b))
            ++nonfinite;
        else if (hprim < 0)
            wp_add_radiance(radiance, p.item, b * wp_xyz(background), counters);
        else
            hit_e[nh++] = i;
    }
    if (nonfinite > 0) wp_atomic_add(&counters[WP_COUNTER_SHADE_NONFINITE], nonfinite);

    // The packed hits, eight lanes at a time (lane l of group g: hit_e[g + l]).
    for (int g = 0; g < nh; g += 8) {
        // Gather the lanes' queue entries (lanes past the packed hits repeat the last one
        // and stay inactive).
        float dx[8], dy[8], dz[8], tx[8], ty[8], tz[8], tw[8], ht[8], hu[8], hv[8];
#if WP_HAVE_NEE && WP_HAVE_LIGHT_PAIRS
        float rox[8], roy[8], roz[8];  // the rays' origins: the previous vertices (light pairs)
#endif
        int prim_a[8], valid_a[8];
        uint pixel_a[8], sample_a[8];
#pragma unroll
        for (int l = 0; l < 8; ++l) {
            int i = hit_e[min(g + l, nh - 1)];
            valid_a[l] = g + l < nh ? -1 : 0;
            Ray r = rays_in[i];
            PathState p = paths_in[i];
            Hit h = hits[i];
            ps[g + l] = p;
            item[g + l] = p.item;
            pixel_a[l] = (uint)p.pixel;
            sample_a[l] = p.sample;
            dx[l] = r.dir.x, dy[l] = r.dir.y, dz[l] = r.dir.z;
#if WP_HAVE_NEE && WP_HAVE_LIGHT_PAIRS
            rox[l] = r.org.x, roy[l] = r.org.y, roz[l] = r.org.z;
#endif
            tx[l] = p.throughput.x, ty[l] = p.throughput.y, tz[l] = p.throughput.z;
            tw[l] = p.throughput.w;
            ht[l] = h.t, hu[l] = h.u, hv[l] = h.v;
            prim_a[l] = h.prim;
        }
        const int* const gitem = item + g;
        const uint8 pixel = vload8(0, pixel_a), sample = vload8(0, sample_a);
        const L3 d = l3(vload8(0, dx), vload8(0, dy), vload8(0, dz));
        const float8 thr_w = vload8(0, tw);
        L3 beta = l3(vload8(0, tx), vload8(0, ty), vload8(0, tz));
        const int8 arrived_specular = bounce > 0 ? thr_w == 0.0f : (int8)(0);
        int8 alive = vload8(0, valid_a);  // finite throughput, a surface hit (packed above)

        // Surface: the triangle, its frame and material (every packed lane is a hit).
        float v0x[8], v0y[8], v0z[8], v1x[8], v1y[8], v1z[8], v2x[8], v2y[8], v2z[8];
        float nx[8], ny[8], nz[8], toff[8], ax[8], ay[8], az[8], ex[8], ey[8], ez[8], pa[8];
        float alpha_a[8];
        int kind_a[8];
#if WP_LANES_SCALAR_KINDS
        int mid_a[8], dirac_a[8];  // the material; its kind is specular (wp_material_is_specular)
#endif
#if WP_HAVE_ROUGH_CONDUCTOR
        // A rough conductor's η, k and flags (isotropic here: alpha_a is its width).
        float etx[8], ety[8], etz[8], kx[8], ky[8], kz[8];
        int rflags[8];
#endif
#pragma unroll
        for (int l = 0; l < 8; ++l) {
            int t = prim_a[l];
            Triangle tri = tris[t];
            float4 f = tri_frames[t];
            int mid = material_ids[t];
            float4 alb = materials[mid].albedo, em = materials[mid].emission;
            kind_a[l] = materials[mid].kind;
#if WP_LANES_SCALAR_KINDS
            mid_a[l] = mid;
            dirac_a[l] = wp_material_is_specular(materials[mid]) ? -1 : 0;
#endif
            alpha_a[l] = materials[mid].alpha;
#if WP_HAVE_ROUGH_CONDUCTOR
            {
                const float4 eta = materials[mid].eta, k = materials[mid].k;
                etx[l] = eta.x, ety[l] = eta.y, etz[l] = eta.z;
                kx[l] = k.x, ky[l] = k.y, kz[l] = k.z;
                rflags[l] = materials[mid].flags;
            }
#endif
            v0x[l] = tri.v0.x, v0y[l] = tri.v0.y, v0z[l] = tri.v0.z;
            v1x[l] = tri.v1.x, v1y[l] = tri.v1.y, v1z[l] = tri.v1.z;
            v2x[l] = tri.v2.x, v2y[l] = tri.v2.y, v2z[l] = tri.v2.z;
            nx[l] = f.x, ny[l] = f.y, nz[l] = f.z, toff[l] = f.w;
            ax[l] = alb.x, ay[l] = alb.y, az[l] = alb.z;
            ex[l] = em.x, ey[l] = em.y, ez[l] = em.z;
#if WP_HAVE_NEE && WP_HAVE_LIGHT_PAIRS
            // As shade_surface: a light's density seen from the previous vertex, where MIS
            // weighs it (bounce > 0, not after a Dirac lobe).
            pa[l] = light_pdf_area[t];
            if (pa[l] > 0.0f && bounce > 0 && tw[l] != 0.0f)
                pa[l] = wp_light_pdf_area(light_pdf_area, light_pairs, tris, tri_frames, t,
                                          make_float3(rox[l], roy[l], roz[l]));
#elif WP_HAVE_NEE
            pa[l] = light_pdf_area[t];
#else
            pa[l] = 0.0f;
#endif
        }
        const L3 v0 = l3(vload8(0, v0x), vload8(0, v0y), vload8(0, v0z));
        const L3 v1 = l3(vload8(0, v1x), vload8(0, v1y), vload8(0, v1z));
        const L3 v2 = l3(vload8(0, v2x), vload8(0, v2y), vload8(0, v2z));
        const L3 n = l3(vload8(0, nx), vload8(0, ny), vload8(0, nz));
        const float8 tri_offset = vload8(0, toff);
        const L3 albedo = l3(vload8(0, ax), vload8(0, ay), vload8(0, az));
        const int8 kind = vload8(0, kind_a);
        const float8 alpha = vload8(0, alpha_a);
        // The lanes of each kind (kinds the scene lacks compile to no lanes).
        const int8 diffuse = WP_HAVE_DIFFUSE ? kind == WP_MATERIAL_DIFFUSE : (int8)(0);
        const int8 glossy = WP_HAVE_GLOSSY ? kind == WP_MATERIAL_GLOSSY : (int8)(0);
        const int8 mirror = WP_HAVE_MIRROR ? kind == WP_MATERIAL_MIRROR : (int8)(0);
#if WP_HAVE_ROUGH_CONDUCTOR
        const int8 rough = kind == WP_MATERIAL_ROUGH_CONDUCTOR;
        RoughConductor8 rc;
        rc.albedo = albedo;
        rc.eta = l3(vload8(0, etx), vload8(0, ety), vload8(0, etz));
        rc.k = l3(vload8(0, kx), vload8(0, ky), vload8(0, kz));
        rc.alpha = alpha;
        {
            const int8 fl = vload8(0, rflags);
            rc.bk = (fl & WP_MF_BECKMANN) != 0;
            rc.sep = (fl & WP_MF_SEPARABLE_G) != 0;
        }
#else
        const int8 rough = (int8)(0);
#endif
#if WP_LANES_SCALAR_KINDS
        // The lanes of the kinds without lane code, and those of them that are Dirac only.
        const int8 other = ~(diffuse | glossy | mirror | rough);
        const int8 other_dirac = other & vload8(0, dirac_a);
#else
        const int8 other_dirac = (int8)(0);
#endif
        const int8 front = l3_dot(d, n) < 0.0f;
        const L3 dn = l3_scale(d, 1.0f / sqrt(l3_dot(d, d)));  // normalize(d)
        const float p_env = wp_env_choice(light_count, env);

#if WP_HAVE_EMISSION
        // Emission of the front face, weighted against light sampling where that could have
        // found this point too.
        {
            const L3 e = l3(vload8(0, ex), vload8(0, ey), vload8(0, ez));
            const int8 emits = alive & front & (l3_max_component(e) > 0.0f);
            if (wp_lane_bits(emits)) {
                float8 w = 1.0f;
#if WP_HAVE_NEE
                float8 pdf_area = vload8(0, pa) * (1.0f - p_env);
                int8 weighed = (bounce > 0 ? (int8)(-1) : (int8)(0)) & ~arrived_specular & (pdf_area > 0.0f);
#if WP_SAMPLING == WP_SAMPLING_MIS
                float8 dist = vload8(0, ht) * sqrt(l3_dot(d, d));
                float8 p_light = wp_light_pdf_solid_angle8(pdf_area, dist * dist, -l3_dot(dn, n));
                w = select(w, wp_power_heuristic8(thr_w, p_light), weighed);
#else
                w = select(w, (float8)(0.0f), weighed);
#endif
#endif
                wp_add_radiance8(radiance, gitem, emits & (w > 0.0f), l3_scale(l3_mul(beta, e), w), counters);
            }
        }
#endif
        if (bounce >= max_depth) alive = (int8)(0);

        if (wp_lane_bits(alive)) {
            // ng: the geometric normal on the side the ray arrived from; ns: the shading
            // normal on that side (ng itself without shading normals).
            const L3 ng = l3_select(l3_neg(n), n, front);
            L3 ns = ng;
#if WP_HAVE_NORMALS
            // As shade_surface (no normal maps here): the terminator factor and the bend only
            // for smooth triangles, the bend always where the viewer sees the back of ns and
            // for non-diffuse lobes where the mirror direction falls below.
            int8 terminator;
            {
                float n0x[8], n0y[8], n0z[8], n1x[8], n1y[8], n1z[8], n2x[8], n2y[8], n2z[8];
#pragma unroll
                for (int l = 0; l < 8; ++l) {
                    TriNormals tn = tri_normals[prim_a[l]];
                    n0x[l] = tn.n0.x, n0y[l] = tn.n0.y, n0z[l] = tn.n0.z;
                    n1x[l] = tn.n1.x, n1y[l] = tn.n1.y, n1z[l] = tn.n1.z;
                    n2x[l] = tn.n2.x, n2y[l] = tn.n2.y, n2z[l] = tn.n2.z;
                }
                const L3 nf = wp_interpolated_normal8(l3(vload8(0, n0x), vload8(0, n0y), vload8(0, n0z)),
                                                      l3(vload8(0, n1x), vload8(0, n1y), vload8(0, n1z)),
                                                      l3(vload8(0, n2x), vload8(0, n2y), vload8(0, n2z)),
                                                      vload8(0, hu), vload8(0, hv), n);
                ns = l3_select(l3_neg(nf), nf, front);
                const int8 smooth = (nf.x != n.x) | (nf.y != n.y) | (nf.z != n.z);
                terminator = smooth;
                const int8 bend = smooth & (~diffuse | (l3_dot(l3_neg(dn), ns) <= 0.0f));
                if (wp_lane_bits(bend)) ns = l3_select(ns, wp_bend_normal8(ns, ng, l3_neg(dn)), bend);
            }
#endif
            L3 perr;
            const L3 p = wp_hit_point8(v0, v1, v2, vload8(0, hu), vload8(0, hv), &perr);
            const L3 org = wp_offset_ray_origin8(p, perr, ng, tri_offset);
            const L3 org_below = wp_offset_ray_origin8(p, perr, l3_neg(ng), tri_offset);

#if WP_HAVE_NEE
            // Next-event estimation at the non-specular lanes: a point on a light chosen by
            // power; the shadow stage adds the contribution when the segment is unoccluded.
            const int8 sampled = alive & ~mirror & ~other_dirac;
            if (light_count > 0 && wp_lane_bits(sampled)) {
                float8 ulx, uly, ulz, ulw;
                wp_rng4_lanes(seed, pixel, sample, (uint)bounce, WP_RNG_LIGHT, &ulx, &uly, &ulz, &ulw);
                // Lanes without a light sample (Dirac kinds, dead paths) take light 0.
#if !WP_HAVE_LIGHT_PAIRS
                const LightLanes8 L = light_count <= WP_FEW_LIGHTS
                                          ? wp_light_lanes_few8(light_cdf, light_prims, light_pdf_area,
                                                                light_clearance, light_count, tris, tri_frames,
                                                                material_ids, materials, ulz, sampled)
                                          : wp_light_lanes_gather8(WP_LIGHT_LANES_ARGS, ulz, sampled, org);
#else
                const LightLanes8 L = wp_light_lanes_gather8(WP_LIGHT_LANES_ARGS, ulz, sampled, org);
#endif
                const L3 ln = L.n;
                // wp_sample_triangle_barycentric
                const float8 s = sqrt(ulx);
                L3 yerr;
                const L3 y = wp_hit_point8(L.v0, L.v1, L.v2, uly * s, 1.0f - s, &yerr);
                const L3 to = l3_sub(y, p);
                const float8 dist2 = l3_dot(to, to);
                const L3 wi = l3_scale(to, 1.0f / sqrt(dist2));
                const float8 p_light = wp_light_pdf_solid_angle8(L.pdf_area * (1.0f - p_env), dist2, -l3_dot(wi, ln));
                // wp_bsdf_eval: diffuse, albedo cos / π above the surface; glossy (lanes.h).
                const float8 cos_i = l3_dot(wi, ns);
                const int8 above = cos_i > 0.0f;
#if WP_SAMPLING == WP_SAMPLING_UNIFORM
                float8 bsdf_pdf = select((float8)(0.0f), (float8)(WP_INV_2PI), above);
#else
                float8 bsdf_pdf = select((float8)(0.0f), wp_cosine_hemisphere_pdf8(cos_i), above);
#endif
                L3 fcos = l3_select(l3_splat(0.0f, 0.0f, 0.0f), l3_scale(albedo, cos_i * WP_INV_PI), above);
#if WP_HAVE_GLOSSY
                if (wp_lane_bits(glossy & sampled)) {
                    float8 gpdf;
                    const L3 gf = wp_glossy_eval8(albedo, alpha, dn, ns, wi, cos_i, &gpdf);
                    fcos = l3_select(fcos, gf, glossy);
                    bsdf_pdf = select(bsdf_pdf, gpdf, glossy);
                }
#endif
#if WP_HAVE_ROUGH_CONDUCTOR
                if (wp_lane_bits(rough & sampled)) {
                    float8 rpdf;
                    const L3 rf = wp_roughconductor_eval8(rc, dn, ns, wi, &rpdf);
                    fcos = l3_select(fcos, rf, rough);
                    bsdf_pdf = select(bsdf_pdf, rpdf, rough);
                }
#endif
#if WP_LANES_SCALAR_KINDS
                if (wp_lane_bits(other & sampled))
                    wp_scalar_eval8(materials, material_tables, mid_a, other & sampled, dn, ns, front, wi,
                                    &fcos, &bsdf_pdf);
#endif
#if WP_HAVE_NORMALS
                // Light on the geometric side of the lobe only (failure mode 2), and the
                // terminator factor (3).
                fcos = l3_select(l3_splat(0.0f, 0.0f, 0.0f), fcos, wp_same_side8(wi, ns, ng));
                bsdf_pdf = select((float8)(0.0f), bsdf_pdf, wp_same_side8(wi, ns, ng));
                if (wp_lane_bits(terminator & sampled))
                    fcos = l3_select(fcos, l3_scale(fcos, wp_terminator_factor8(ng, ns, wi)), terminator);
#endif
                const int8 lit = sampled & (p_light > 0.0f) & (l3_max_component(fcos) > 0.0f);
                if (wp_lane_bits(lit)) {
#if WP_SAMPLING == WP_SAMPLING_MIS
                    const float8 w = wp_power_heuristic8(p_light, bsdf_pdf);
#else
                    const float8 w = 1.0f;
#endif
                    const L3 le = L.le;
                    const L3 c = l3_scale(l3_mul(l3_mul(beta, fcos), le), w / p_light);
                    const int8 c_finite = l3_all_finite(c);
                    wp_count_nonfinite8(lit & ~c_finite, counters);
                    const int8 shadow = lit & c_finite & (l3_max_component(c) > 0.0f);
                    // From the origin offset to the side the light is on, towards the light
                    // point, ending short of it (offset.h).
                    const L3 so = l3_select(org_below, org, l3_dot(wi, ng) > 0.0f);
                    const L3 sd = l3_sub(y, so);
#if WP_HAVE_LIGHT_CLEARANCE
                    const float8 tmax = wp_shadow_end_clear8(wp_shadow_tmax8(sd, yerr, ln, L.offset), sd, y,
                                                             yerr, ln, L.clearance);
#else
                    const float8 tmax = wp_shadow_tmax8(sd, yerr, ln, L.offset);
#endif
                    shadow_bits |= (ulong)(uint)wp_lane_bits(shadow) << g;
                    vstore8(so.x, 0, sox + g), vstore8(so.y, 0, soy + g), vstore8(so.z, 0, soz + g);
                    vstore8(sd.x, 0, sdx + g), vstore8(sd.y, 0, sdy + g), vstore8(sd.z, 0, sdz + g);
                    vstore8(tmax, 0, stm + g);
                    vstore8(c.x, 0, scx + g), vstore8(c.y, 0, scy + g), vstore8(c.z, 0, scz + g);
                }
            }
#endif

            // Scatter: each lane samples its material (wp_bsdf_sample_pdf).
            // The lane kinds' samplers read two numbers; the scalar kinds' all four.
            float8 ux, uy;
#if WP_LANES_SCALAR_KINDS
            float8 uz, uw;
            wp_rng4_lanes(seed, pixel, sample, (uint)bounce, WP_RNG_BSDF, &ux, &uy, &uz, &uw);
#else
            wp_rng2_lanes(seed, pixel, sample, (uint)bounce, WP_RNG_BSDF, &ux, &uy);
#endif
#if WP_SAMPLING == WP_SAMPLING_UNIFORM
            const L3 lv = wp_sample_uniform_hemisphere8(ux, uy);
            L3 weight = l3_scale(albedo, 2.0f * lv.z);
            float8 pdf = WP_INV_2PI;
#else
            const L3 lv = wp_sample_cosine_hemisphere8(ux, uy);
            L3 weight = albedo;
            float8 pdf = wp_cosine_hemisphere_pdf8(lv.z);
#endif
            L3 wo = wp_to_world8(lv, ns);
#if WP_HAVE_GLOSSY
            if (wp_lane_bits(glossy & alive)) {
                L3 gwo, gweight;
                float8 gpdf;
                const int8 scattered = wp_glossy_sample8(albedo, alpha, dn, ns, ux, uy, &gwo, &gweight, &gpdf);
                alive &= ~glossy | scattered;  // a glossy draw below the surface: absorbed
                wo = l3_select(wo, gwo, glossy);
                weight = l3_select(weight, gweight, glossy);
                pdf = select(pdf, gpdf, glossy);
            }
#endif
#if WP_HAVE_ROUGH_CONDUCTOR
            if (wp_lane_bits(rough & alive)) {
                L3 rwo, rweight;
                float8 rpdf;
                const int8 drawn = wp_roughconductor_sample8(rc, dn, ns, ux, uy, &rwo, &rweight, &rpdf, rough & alive);
                alive &= ~rough | drawn;  // absorbed
                wo = l3_select(wo, rwo, rough);
                weight = l3_select(weight, rweight, rough);
                pdf = select(pdf, rpdf, rough);
            }
#endif
#if WP_HAVE_MIRROR
            if (wp_lane_bits(mirror & alive)) {
                wo = l3_select(wo, wp_reflect8(dn, ns), mirror);
                weight = l3_select(weight, albedo, mirror);
                pdf = select(pdf, (float8)(0.0f), mirror);
            }
            int8 specular = mirror;
#else
            int8 specular = (int8)(0);
#endif
#if WP_LANES_SCALAR_KINDS
            if (wp_lane_bits(other & alive)) {
                const int8 drawn = wp_scalar_sample8(materials, material_tables, mid_a, other & alive, dn, ns,
                                                     front, ux, uy, uz, uw, &wo, &weight, &pdf, &specular);
                alive &= ~other | drawn;  // the kind's sample absorbed the path
            }
#endif
            alive &= specular | (pdf > 0.0f);  // a zero-density draw (measure zero): absorbed
#if WP_HAVE_NORMALS
            // A reflection below the geometric surface is absorbed (failure mode 2);
            // non-specular reflections get the terminator factor (3).
            alive &= wp_same_side8(wo, ns, ng);
            const int8 shadowed = terminator & ~specular & (l3_dot(wo, ng) > 0.0f);
            if (wp_lane_bits(shadowed & alive))
                weight = l3_select(weight, l3_scale(weight, wp_terminator_factor8(ng, ns, wo)), shadowed);
#endif
            beta = l3_mul(beta, weight);
            const int8 scatter_finite = l3_all_finite(beta) & l3_all_finite(wo);
            wp_count_nonfinite8(alive & ~scatter_finite, counters);
            alive &= scatter_finite & (l3_max_component(beta) > 0.0f);
#if WP_RR_DEPTH >= 0
            // Russian roulette: survive with q = min(1, max component of the throughput).
            if (bounce >= WP_RR_DEPTH) {
                const float8 q = min(1.0f, l3_max_component(beta));
                const float8 rx = wp_rng1_lanes(seed, pixel, sample, (uint)bounce, WP_RNG_RR);
                alive &= rx < q;
                beta = l3_scale(beta, 1.0f / q);
            }
#endif
            // The continued path, from the origin on the geometric side it leaves; w: the
            // density of wo, 0 after a Dirac lobe (PathState).
            const L3 on = l3_select(org_below, org, l3_dot(wo, ng) > 0.0f);
            push_bits |= (ulong)(uint)wp_lane_bits(alive) << g;
            vstore8(on.x, 0, nox + g), vstore8(on.y, 0, noy + g), vstore8(on.z, 0, noz + g);
            vstore8(wo.x, 0, ndx + g), vstore8(wo.y, 0, ndy + g), vstore8(wo.z, 0, ndz + g);
            vstore8(beta.x, 0, nbx + g), vstore8(beta.y, 0, nby + g), vstore8(beta.z, 0, nbz + g);
            vstore8(select(pdf, (float8)(0.0f), specular), 0, npdf + g);
        }
    }

    // One global atomic per work-item and queue (per WP_SHADE_LANE_ENTRIES paths). No
    // work-group barrier: PoCL would keep every lane's outputs in per-work-item context arrays
    // across it (the copies cost a quarter of this kernel's time, measured).
    if (push_bits == 0 && shadow_bits == 0) return;
    int slot = push_bits ? wp_atomic_add(count_out, (int)popcount(push_bits)) : 0;
    int shadow_slot = shadow_bits ? wp_atomic_add(shadow_count, (int)popcount(shadow_bits)) : 0;
#if WP_SHADE_TRACES_SHADOWS
    // The shadow rays traced here, one after the other, with shadow_trace's any hit and its
    // update (shadow.cl): the same rays, the same occlusion and, as every emission this
    // kernel adds for a sample precedes its light sample, the same sums in the same order;
    // the image is the queued one bit for bit. What it saves (docs/performance.md, "Sixteenth
    // round"): the 52 bytes a shadow ray takes in the queue, written here and read back by
    // the shadow stage, and that stage's launch per bounce.
    (void)shadow_slot;
    for (ulong rest = shadow_bits; rest != 0; rest &= rest - 1) {
        const int l = wp_ctz64(rest);
        Ray r;
        r.org = make_float4(sox[l], soy[l], soz[l], 0.0f);
        r.dir = make_float4(sdx[l], sdy[l], sdz[l], stm[l]);
        TraceStats st = {0, 0};
        const Hit h = wp_trace_any(r, bvh_nodes, bvh_links, bvh_tris, bvh_prim_ids, &st);
        if (h.prim < 0) radiance[item[l]] += make_float4(scx[l], scy[l], scz[l], 0.0f);
    }
    shadow_bits = 0;
#endif
    for (int l = 0; l < WP_SHADE_LANE_ENTRIES; ++l) {
        if (push_bits & (1ul << l)) {
            Ray r;
            r.org = make_float4(nox[l], noy[l], noz[l], 0.0f);
            r.dir = make_float4(ndx[l], ndy[l], ndz[l], FLT_MAX);
            PathState np = ps[l];
            np.throughput = make_float4(nbx[l], nby[l], nbz[l], npdf[l]);
            wp_store_path(rays_out + slot, paths_out + slot, r, np);
            ++slot;
        }
        if (shadow_bits & (1ul << l)) {
            Ray r;
            r.org = make_float4(sox[l], soy[l], soz[l], 0.0f);
            r.dir = make_float4(sdx[l], sdy[l], sdz[l], stm[l]);
            wp_push_shadow(shadow_rays + shadow_slot, shadow_items + shadow_slot, shadow_contrib + shadow_slot, r,
                           item[l], make_float4(scx[l], scy[l], scz[l], 0.0f));
            ++shadow_slot;
        }
    }
}
#endif  // WP_SHADE_LANES
