// limits.h — the one definition of every limit and default of a render.
//
// The command line, every scene loader and the renderer read these; nothing else writes a
// cap or a default of its own. Plain constants (no OpenCL, no GLM), so every room may
// include it.
#pragma once

#include <cstdint>

namespace wp::limits {

// Samples per pixel: at least 1; the film's double-float sums keep 1e-7 relative accuracy
// far beyond this (kernels/shared/film.h).
constexpr int kMinSpp = 1;
constexpr int kMaxSpp = 1 << 24;
constexpr int kDefaultSpp = 64;

// Adaptive sampling and --target-error (render/adaptive.h). The thresholds are estimated
// relMSE values (kernels/shared/adaptive.h): a pixel stops at e_p <= the threshold; a
// --target-error render stops when the image's mean e_p <= the target. No pixel stops and no
// estimate is trusted before kDefaultMinSpp samples (the sample variance of a few samples
// misses rare bright paths); at least 2 (a variance needs two samples).
constexpr double kDefaultAdaptiveThreshold = 1e-3;
constexpr double kMinErrorThreshold = 1e-12;
constexpr double kMaxErrorThreshold = 1e6;
constexpr int kMinMinSpp = 2;
constexpr int kDefaultMinSpp = 16;
// The active list is checked at min spp, then every max(kAdaptiveMinInterval, spp /
// kAdaptiveIntervalDivisor) passes (a pixel overshoots its stopping point by at most a
// quarter of its samples); --target-error estimates the image's error on the same schedule.
constexpr int kAdaptiveMinInterval = 4;
constexpr int kAdaptiveIntervalDivisor = 4;
// RQMC replicates (render --replicates, docs/adaptive.md): sample s of a pixel belongs to
// replicate s mod K, each replicate an independently scrambled Sobol sequence, and the
// variance of a pixel's mean is estimated from the spread of the K replicate means (for
// --target-error). K is a power of two in 1..kMaxReplicates; auto (0) is kDefaultReplicates
// with --target-error and the Sobol sampler, else 1 (1: the film and sampler of before).
constexpr int kMaxReplicates = 64;
constexpr int kDefaultReplicates = 4;

// Bounces (scattering events) per path: 0 shows emitters and background only. The path
// pool ends a wave when its queue is empty, so a deep cap costs nothing once Russian
// roulette has ended every path; the cap keeps the sample-key arithmetic (bounce * 16 +
// group, 32 bits) far from overflow.
constexpr int kMinDepth = 0;
constexpr int kMaxDepth = 1 << 20;
constexpr int kDefaultDepth = 3;  // the built-in scenes: the original program's workload
// A scene file (mesh, .json, .xml) that sets no depth of its own: enough bounces that the
// missing light is below the noise at 64 spp; Russian roulette from bounce 3 keeps the
// extra bounces cheap (measured in docs/sampling.md, "The default depth").
constexpr int kDefaultSceneDepth = 5;

// Image size: each side 1..kMaxImageSide pixels, at most kMaxPixels pixels (16384^2).
constexpr int kMaxImageSide = 16384;
constexpr std::int64_t kMaxPixels = std::int64_t(1) << 28;
constexpr int kDefaultWidth = 800;
constexpr int kDefaultHeight = 600;

// Texture images (scene/texture.h): each side 1..kMaxTextureSide texels, at most
// kMaxTexturePixels texels (a 16384 x 8192 environment map; 2 GiB as float RGBA), checked
// from the file's header before any pixel is read.
constexpr int kMaxTextureSide = 32768;
constexpr std::int64_t kMaxTexturePixels = std::int64_t(1) << 27;

// Paths in flight (--pool): 0 picks the size automatically (render/frame_state.cpp).
constexpr std::int64_t kMaxPool = std::int64_t(1) << 30;

// Seeds are 32-bit: 0..kMaxSeed.
constexpr std::int64_t kMaxSeed = 0xffffffffLL;

// Appearance edits on the command line (render --env-scale, --env-rotate, --smooth) and the
// crease angle of computed smooth normals (also JSON "smooth"): a radiance scale 0..1e6, a
// rotation of the environment map about +y of at most one turn either way, a crease angle
// 0..180 degrees (180: no creases).
constexpr double kMaxEnvScale = 1e6;
constexpr double kMaxEnvRotateDeg = 360.0;
constexpr double kMaxCreaseDeg = 180.0;

// Scene files (scene/pbrt_loader.h; the other loaders keep their own local caps for now):
// each file read at most kMaxSceneFileBytes; Include/Import nested at most kMaxIncludeDepth
// deep and at most kMaxIncludes files in all (a file included twice counts twice, so a
// diamond of includes cannot grow exponentially); AttributeBegin/TransformBegin/ObjectBegin
// nested at most kMaxAttributeDepth deep; at most kMaxSceneTriangles triangles in all,
// instances flattened (a scene over it is an error naming the directive that passed it).
constexpr std::int64_t kMaxSceneFileBytes = std::int64_t(1) << 30;
constexpr int kMaxIncludeDepth = 32;
constexpr int kMaxIncludes = 4096;
constexpr int kMaxAttributeDepth = 4096;
constexpr std::int64_t kMaxSceneTriangles = std::int64_t(1) << 25;
// pbrt-v4's square equal-area environment maps are resampled to equirectangular maps of at
// most 2 x kMaxEnvResampleHeight by kMaxEnvResampleHeight texels.
constexpr int kMaxEnvResampleHeight = 4096;

// Microfacet roughness α of the rough material kinds (roughconductor, roughdielectric,
// roughplastic; not the glossy kind, which takes (0, 1]): [kMinMicrofacetAlpha,
// kMaxMicrofacetAlpha] (issue 14's contract). Loaders map a smaller α to the smooth kind and
// clamp a larger one, each with a note. Their default in JSON files is Mitsuba 3's.
constexpr float kMinMicrofacetAlpha = 1e-4f;
constexpr float kMaxMicrofacetAlpha = 2.0f;
constexpr float kDefaultMicrofacetAlpha = 0.1f;
// Index of refraction (inside / outside) of the kinds that read one (scene/validate.cpp,
// the loaders).
constexpr float kMinIor = 0.01f;
constexpr float kMaxIor = 100.0f;

// The viewer (`wavepath view`, scene/camera_control.h, docs/viewer.md).
constexpr float kViewerMaxPitchDeg = 89.0f;      // orbit stops this far from straight up/down
constexpr float kViewerMinDistance = 1e-4f;      // dolly keeps position this far from target
constexpr double kViewerOrbitRadPerPixel = 0.005;  // mouse drag
constexpr double kViewerDollyPerScroll = 0.9;    // distance factor per wheel step
constexpr double kViewerFlySpeed = 0.5;          // distances to target per second (WASD)
constexpr double kViewerExposureStep = 0.5;      // stops per key press
constexpr double kViewerMaxExposure = 20.0;      // |--exposure| in stops
constexpr double kViewerTitleInterval_s = 0.5;   // live numbers in the title
constexpr double kViewerProfileInterval_s = 3.0; // its per-stage split (waits for the queue)
constexpr double kViewerDisplayShare = 0.05;     // most of the render time spent showing frames
constexpr int kViewerMaxFrames = 1 << 24;        // --frames

// The denoise stage (render/denoise.h, kernels/denoise.cl; docs/denoise.md): à-trous
// iterations (step 1, 2, 4, ... pixels) and the edge-stopping parameters of SVGF (Schied et
// al. 2017): luminance against sqrt(variance) (σ_l), normals (cos^σ_n; σ_n a power of two,
// applied by squaring), depth against its screen-space gradient (σ_z); albedo (σ_a,
// wavepath's own: exp(-Σ|Δalbedo| / σ_a)). Albedo below kDenoiseMinAlbedo per channel is
// not divided out (misses, black surfaces).
constexpr int kDenoiseIterations = 5;
constexpr int kMaxDenoiseIterations = 12;
constexpr float kDenoiseSigmaLuminance = 4.0f;
constexpr int kDenoiseNormalPower = 128;
constexpr float kDenoiseSigmaDepth = 1.0f;
constexpr float kDenoiseSigmaAlbedo = 0.1f;
constexpr float kDenoiseMinAlbedo = 1e-3f;
// The energy restore's iterations over the filter's residual (0: off; docs/denoise.md).
constexpr int kDenoiseRestoreIterations = 0;

// The estimator's defaults (sampling, glossy model, sampler, Russian roulette) are
// kernels/shared/estimator.h's, read by the kernels and render::Estimator alike.

}  // namespace wp::limits
