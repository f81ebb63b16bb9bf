// queue_store.h — the stores that fill a path queue (generate's camera rays, shade's
// pushes): a ray and a path state into their slots, each field one 16-byte store.
// WP_STORE_STREAM (compat.h) makes them non-temporal where the kernel is built with
// WP_STREAM_STORES (KernelConfig::stream_stores: a CPU device whose cores' share of the cache
// the pool's queues outgrow; render/wavefront.h), so no line is read for ownership before it
// is written. The same bits either way.
#ifndef WP_QUEUE_STORE_H
#define WP_QUEUE_STORE_H

#include "types.h"

WP_NAMESPACE_BEGIN

WP_FN void wp_store_path(WP_GLOBAL Ray* ray_q, WP_GLOBAL PathState* path_q, Ray r, PathState p) {
    WP_STORE_STREAM(&ray_q->org, r.org);
    WP_STORE_STREAM(&ray_q->dir, r.dir);
    WP_STORE_STREAM(&path_q->throughput, p.throughput);
#if WP_STREAM_STORES && defined(WP_OPENCL)
    // pixel, sample, item, cone: 16 contiguous bytes (types.h; tests/test_layout.cpp)
    WP_STORE_STREAM((WP_GLOBAL int4*)&path_q->pixel, (int4)(p.pixel, (int)p.sample, p.item, as_int(p.cone)));
#else
    path_q->pixel = p.pixel, path_q->sample = p.sample, path_q->item = p.item, path_q->cone = p.cone;
#endif
}

WP_NAMESPACE_END

#endif  // WP_QUEUE_STORE_H
