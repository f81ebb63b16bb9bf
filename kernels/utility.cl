// utility.cl — small kernels that check the device side of the shared definitions.
//
// probe_layout: writes the sizeof/offsetof list of types.h (WP_LAYOUT_FIELDS) as the
// device compiler sees it into out[0..n); tests/test_layout.cpp compares it with the host.
#include "shared/types.h"

#define WP_PROBE_WRITE(expr) out[n++] = (int)(expr);

__kernel void probe_layout(__global int* out) {
    if (get_global_id(0) != 0) return;
    int n = 0;
    WP_LAYOUT_FIELDS(WP_PROBE_WRITE)
    out[n] = -1;  // terminator: tells the host how many entries were written
}
