// utility.cl — small kernels that check the device side of the shared definitions.
//
// probe_layout: writes the sizeof/offsetof list of types.h (WP_LAYOUT_FIELDS) as the
// device compiler sees it into out[0..n); tests/test_layout.cpp compares it with the host.
#include "shared/types.h"

#define WP_PROBE_WRITE(expr) out[n++] = (int)(expr);

WP_KERNEL void probe_layout(WP_GLOBAL int* out) {
    if (wp_global_id() != 0) return;
    int n = 0;
    WP_LAYOUT_FIELDS(WP_PROBE_WRITE)
    out[n] = -1;  // terminator: tells the host how many entries were written
}
