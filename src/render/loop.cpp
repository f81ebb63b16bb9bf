#include "render/loop.h"

#include <algorithm>

#include "util/host_trace.h"
#include "util/timer.h"

namespace wp::render {

namespace {

// Device time of every launch the profiler has folded in so far.
double kernel_ms(const ocl::Profiler& p) {
    double ms = 0.0;
    for (const auto& t : p.totals()) ms += t.total_ms;
    return ms;
}

}  // namespace

LoopResult render_frames(Wavefront& wf, const LoopOptions& options, Progress* progress) {
    LoopResult res;
    Timer timer;
    double paused_s = 0.0;  // time spent in checkpoints
    auto render_s = [&] { return timer.seconds() - paused_s; };
    const int start = wf.frames();
    const double kernel_ms_before = kernel_ms(wf.profiler());
    const bool target = options.target_error > 0.0;
    const int replicates = wf.settings().replicates;  // estimates on multiples of it
    int next_estimate = next_error_check(start + 1, options.min_spp, replicates);
    int estimated_at = -1;
    while (wf.frames() - start < options.spp) {
        if (wf.converged()) {
            res.converged = true;
            break;
        }
        const int done = wf.frames() - start;  // before this step
        // (Per step: with adaptive sampling a wave holds more passes as pixels stop.)
        const int per_wave = std::max(1, wf.passes_per_wave());
        int k = std::min({per_wave, std::max(1, done), options.spp - done});
        // With a target, steps end on the passes where the estimate is due.
        if (target) k = std::max(1, std::min(k, next_estimate - wf.frames()));
        // Progress within the step: after each wave (several per pass when the image is
        // larger than the pool), so the line moves at least once a second.
        const double step_start = render_s();
        wf.render_passes(k, [&](double part) {
            if (progress && progress->due()) progress->update(wf.frames() + part, wf.rays_traced());  // frames(): before this step
        });
        // Checkpoint (film reads, error metrics): its time is not render time.
        if (options.checkpoint && options.checkpoint_due &&
            options.checkpoint_due(wf.frames(), render_s())) {
            wf.device().queue.finish();
            double at = render_s();
            Timer pause;
            options.checkpoint(wf.frames(), at);
            paused_s += pause.seconds();
        }
        // The profile keeps a bounded summary: fold the finished launches into it (this waits
        // for the step, so its time below is the step's).
        wf.profiler().resolve();
        if (res.first_frame_done_ns == 0) {  // the first step: one sample per pixel
            res.first_frame_done_ns = steady_ns();
            res.first_frame_ms = timer.ms();
            res.first_frame_kernel_ms = kernel_ms(wf.profiler()) - kernel_ms_before;
        }
        if (options.after_step) options.after_step();
        if (target && wf.frames() >= next_estimate) {
            res.estimated_error = wf.estimate_error();
            estimated_at = wf.frames();
            next_estimate = next_error_check(wf.frames() + 1, options.min_spp, replicates);
            if (options.on_estimate) options.on_estimate(res.estimated_error);
            if (res.estimated_error <= options.target_error) {
                res.stopped_by_target = true;
                if (progress) progress->step(k, render_s() - step_start);
                break;
            }
        }
        if (progress) progress->step(k, render_s() - step_start);
        if (progress && progress->due()) progress->update(wf.frames(), wf.rays_traced());
        // A stop request (Ctrl-C): the step just enqueued completes, so the film holds whole
        // passes.
        if (options.should_stop && wf.frames() - start < options.spp && options.should_stop()) {
            res.interrupted = true;
            break;
        }
        // Stop at the time budget once the samples just enqueued are done.
        if (options.time_limit_s > 0.0 && render_s() >= options.time_limit_s &&
            wf.frames() - start < options.spp) {
            res.stopped_by_time = true;
            break;
        }
    }
    if (wf.converged() && !res.stopped_by_target) res.converged = true;
    // The estimate of the image as it ends (another after a limit stopped it).
    if (target && estimated_at != wf.frames() && wf.frames() >= 2) {
        res.estimated_error = wf.estimate_error();
        if (options.on_estimate) options.on_estimate(res.estimated_error);
    }
    wf.device().queue.finish();
    res.render_s = render_s();
    wf.profiler().resolve();
    res.frames = wf.frames();
    res.wall_s = timer.seconds();
    return res;
}

}  // namespace wp::render
