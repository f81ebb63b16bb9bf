#include "render/loop.h"

#include "util/timer.h"

namespace wp::render {

LoopResult render_frames(Wavefront& wf, const LoopOptions& options, Progress* progress) {
    LoopResult res;
    Timer timer;
    double paused_s = 0.0;  // time spent in checkpoints
    auto render_s = [&] { return timer.seconds() - paused_s; };
    ::cl::Event previous;
    bool have_previous = false;
    int done = 0;
    for (int f = 0; f < options.spp; ++f) {
        ::cl::Event last = wf.enqueue_frame();
        if (have_previous) {
            previous.wait();
            ++done;
        }
        previous = last;
        have_previous = true;
        // Checkpoint (film reads, error metrics): its time is not render time.
        if (options.checkpoint && options.checkpoint_due &&
            options.checkpoint_due(wf.frames(), render_s())) {
            wf.device().queue.finish();
            done = wf.frames();
            double at = render_s();
            Timer pause;
            options.checkpoint(wf.frames(), at);
            paused_s += pause.seconds();
        }
        if (progress && progress->due()) progress->update(done, wf.rays_traced());
        // Stop at the time budget once the frame just enqueued is done.
        if (options.time_limit_s > 0.0 && render_s() >= options.time_limit_s &&
            f + 1 < options.spp) {
            res.stopped_by_time = true;
            break;
        }
        // Resolve profiling events now and then, so long renders keep few live events.
        if ((f + 1) % 64 == 0) {
            previous.wait();
            wf.profiler().resolve();
        }
    }
    wf.device().queue.finish();
    res.render_s = render_s();
    wf.profiler().resolve();
    res.frames = wf.frames();
    res.wall_s = timer.seconds();
    return res;
}

}  // namespace wp::render
