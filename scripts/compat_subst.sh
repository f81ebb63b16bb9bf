#!/bin/sh
# compat_subst.sh FILE.cl... — rewrites OpenCL keywords and work-item functions in stage
# files as kernels/shared/compat.h's vocabulary, in place, so the file also compiles as
# CUDA and as host C++ (ctest -L cuda-compile checks it). Purely mechanical:
#   __kernel -> WP_KERNEL, __global -> WP_GLOBAL, __local -> WP_LOCAL,
#   [(int)]get_global_id(0) -> wp_global_id(), [(int)]get_local_id(0) -> wp_local_id(),
#   barrier(CLK_LOCAL_MEM_FENCE) -> wp_barrier(), atomic_inc( -> wp_atomic_inc(,
#   atomic_add( -> wp_atomic_add(, and `static [inline]` at the start of a line (a file-scope
#   helper function) -> WP_FN (CUDA needs __device__ on every function a kernel calls).
# Running it twice changes nothing more.
set -eu
for f in "$@"; do
  sed -E -i \
    -e 's/\b__kernel\b/WP_KERNEL/g' -e 's/\b__global\b/WP_GLOBAL/g' -e 's/\b__local\b/WP_LOCAL/g' \
    -e 's/\(int\)get_global_id\(0\)/wp_global_id()/g' -e 's/\bget_global_id\(0\)/wp_global_id()/g' \
    -e 's/\(int\)get_local_id\(0\)/wp_local_id()/g' -e 's/\bget_local_id\(0\)/wp_local_id()/g' \
    -e 's/\bbarrier\(CLK_LOCAL_MEM_FENCE\)/wp_barrier()/g' \
    -e 's/\batomic_inc\(/wp_atomic_inc(/g' -e 's/\batomic_add\(/wp_atomic_add(/g' \
    -e 's/^static (inline )?/WP_FN /' \
    "$f"
done
