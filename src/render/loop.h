// loop.h — runs sample passes of a Wavefront until the sample count or the time budget is
// reached.
//
// Each step renders k more samples per pixel (Wavefront::render_passes): k = 1, 1, 2, 4, ...
// doubling up to the passes one wave of the path pool holds, so the samples done after each
// step are 1, 2, 4, 8, ... (then multiples of the wave), and short renders, progress lines
// and checkpoints keep a fine grain while long ones fill the pool. The image does not
// depend on the steps (render/wavefront.h). No buffer is read inside the loop except the
// 8-byte ray total, and only when the progress line is due: after each step and after each
// wave inside it (Wavefront::render_passes' callback), so an image larger than the pool,
// whose one pass is many waves, still shows fractional progress. Each step's time goes to
// Progress::step for the ETA.
//
// Checkpoints: when LoopOptions::checkpoint_due(frames, seconds) says so (after a step is
// enqueued; `frames` = samples per pixel so far), the loop calls checkpoint(frames,
// seconds); a blocking film read there sees exactly `frames` samples (the queue is in order). The time spent inside checkpoints is
// not render time: it is left out of `seconds`, of the time limit and of render_s, so
// error-against-time curves are not bent by their own measurement.
//
// Target error (render --target-error): with LoopOptions::target_error > 0 the loop asks the
// Wavefront for the image's estimated relMSE (Wavefront::estimate_error, render/adaptive.h) at
// the passes next_error_check gives (min spp, then every max(4, spp / 4) passes; the steps
// are cut to land on them) and stops once it is <= the target. Its time is render time (it
// is part of the strategy). Adaptive sampling that has stopped every pixel ends the loop too
// (LoopResult::converged).
#pragma once

#include <cstdint>
#include <functional>

#include "render/progress.h"
#include "render/wavefront.h"
#include "util/limits.h"

namespace wp::render {

struct LoopOptions {
    int spp = limits::kDefaultSpp;  // samples per pixel
    double time_limit_s = 0.0;  // stop after this render time (checked per step); 0 = none
    // Optional checkpoint hook; `seconds` is render time so far (checkpoints excluded).
    std::function<bool(int frames, double seconds)> checkpoint_due;
    std::function<void(int frames, double seconds)> checkpoint;
    // Optional stop request (e.g. the first Ctrl-C), asked after each step: the loop then ends
    // with the film holding whole passes (LoopResult::interrupted).
    std::function<bool()> should_stop;
    // Stop when the estimated relMSE is <= this (needs RenderSettings::error_estimate); 0 =
    // no target. Not before min_spp samples.
    double target_error = 0.0;
    int min_spp = limits::kDefaultMinSpp;
    // Called with each new estimate (the progress line's note).
    std::function<void(double estimate)> on_estimate;
    // Called after each step (e.g. a progress note); reads nothing from the device.
    std::function<void()> after_step;
};

struct LoopResult {
    int frames = 0;
    double wall_s = 0.0;    // wall time of the whole loop
    double render_s = 0.0;  // wall time less the time spent in checkpoints
    bool stopped_by_time = false;
    bool interrupted = false;  // should_stop said so before --spp was reached
    bool stopped_by_target = false;  // the estimate reached LoopOptions::target_error
    bool converged = false;          // adaptive sampling stopped every pixel
    // The latest estimated relMSE (with a target: refreshed at the end); < 0: none.
    double estimated_error = -1.0;
    // The first step (1 sample per pixel: the first frame): its wall time from the loop's
    // start to its completion on the device, the device time of its launches, and when it
    // was done (steady_ns(), for the cold-start figures of render/startup.h).
    double first_frame_ms = 0.0;
    double first_frame_kernel_ms = 0.0;
    std::uint64_t first_frame_done_ns = 0;
};

LoopResult render_frames(Wavefront& wf, const LoopOptions& options, Progress* progress);

}  // namespace wp::render
