// queue.cl — queue upkeep of the path pool (render/frame_state.h).
//
// queue_reset — between intersect and shade of a bounce, one work-item.
// reads   count_in[0] (rays traced by this bounce's intersect)
// writes  ray_total[0] += count_in[0] (64-bit total of rays traced, for Mrays/s; the shadow
//         stage adds its own), count_out[0] = 0 and shadow_count[0] = 0 (the queues shade
//         is about to fill are empty)
#include "shared/types.h"

WP_KERNEL void queue_reset(WP_GLOBAL const int* count_in, WP_GLOBAL int* count_out,
                           WP_GLOBAL int* shadow_count, WP_GLOBAL ulong* ray_total) {
    if (wp_global_id() != 0) return;
    ray_total[0] += (ulong)count_in[0];
    count_out[0] = 0;
    shadow_count[0] = 0;
}
