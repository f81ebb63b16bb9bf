// loop.h — runs frames of a Wavefront until the sample count or the time budget is reached.
//
// At most two frames are in flight: frame f is enqueued before the host waits for frame
// f - 1, so the device never idles while the host enqueues. No buffer is read inside the
// loop except the 8-byte ray total, and only when the progress line is due.
#pragma once

#include "render/progress.h"
#include "render/wavefront.h"

namespace wp::render {

struct LoopOptions {
    int spp = 64;               // samples per pixel (= frames)
    double time_limit_s = 0.0;  // stop after this wall time (checked per frame); 0 = none
};

struct LoopResult {
    int frames = 0;
    double wall_s = 0.0;
    bool stopped_by_time = false;
};

LoopResult render_frames(Wavefront& wf, const LoopOptions& options, Progress* progress);

}  // namespace wp::render
