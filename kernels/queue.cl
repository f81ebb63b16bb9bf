// queue.cl — queue upkeep of the path pool (render/frame_state.h).
//
// queue_reset — between intersect and shade of a bounce, one work-item.
// reads   count_in[0] (rays traced by this bounce's intersect), shadow_count[0] (the shadow
//         rays the previous bounce's shade made: queued for the shadow stage, or traced by
//         shade itself; 0 at bounce 0, where the wave's generate follows the last reset)
// writes  ray_total[0] += count_in[0] and shadow_ray_total[0] += shadow_count[0] (64-bit
//         totals of rays traced, for Mrays/s), count_out[0] = 0 and shadow_count[0] = 0 (the
//         queues shade is about to fill are empty)
// The last shade of a wave makes no shadow rays (no light sampling at the last bounce, and
// a wave ends early only where a bounce read an empty queue), so every shadow ray is
// counted by the next reset.
#include "shared/types.h"

WP_KERNEL void queue_reset(WP_GLOBAL const int* count_in, WP_GLOBAL int* count_out,
                           WP_GLOBAL int* shadow_count, WP_GLOBAL ulong* ray_total,
                           WP_GLOBAL ulong* shadow_ray_total) {
    if (wp_global_id() != 0) return;
    ray_total[0] += (ulong)count_in[0];
    shadow_ray_total[0] += (ulong)shadow_count[0];
    count_out[0] = 0;
    shadow_count[0] = 0;
}
