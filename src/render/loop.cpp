#include "render/loop.h"

#include "util/timer.h"

namespace wp::render {

LoopResult render_frames(Wavefront& wf, const LoopOptions& options, Progress* progress) {
    LoopResult res;
    Timer timer;
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
        if (progress && progress->due()) progress->update(done, wf.rays_traced());
        // Stop at the time budget once the frame just enqueued is done.
        if (options.time_limit_s > 0.0 && timer.seconds() >= options.time_limit_s &&
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
    wf.profiler().resolve();
    res.frames = wf.frames();
    res.wall_s = timer.seconds();
    return res;
}

}  // namespace wp::render
