#!/usr/bin/env bash
# gpu_parity.sh — the shared kernel code run on an NVIDIA GPU (CUDA) and compared with the
# same code compiled as host C++. Not part of CI (CI has no GPU).
# The BSDF code of every material kind (tests/cuda/gpu_parity.cu, parity_check.cpp):
#   scripts/gpu_parity.sh run OUT.bin     on the GPU machine: build and run the CUDA side
#   scripts/gpu_parity.sh check OUT.bin   anywhere: recompute on the host and compare
# The BVH traversals (tests/cuda/trace_parity.cu, trace_parity_host.cpp; BUILD is the CMake
# build folder, default build/release, that holds the trace_parity tool):
#   scripts/gpu_parity.sh trace-input IN.bin [RAYS]    here: the built-in box's BVH and rays
#   scripts/gpu_parity.sh trace-run IN.bin OUT.bin     on the GPU machine: hits and Mrays/s
#   scripts/gpu_parity.sh trace-check IN.bin OUT.bin   here: host traversals, bit for bit
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
nvcc="${NVCC:-/usr/local/cuda/bin/nvcc}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
case "${1:-}" in
run)
    "$nvcc" -std=c++17 --fmad=false -gencode arch=compute_90,code=sm_90 \
        -gencode arch=compute_75,code=compute_75 -I "$root/kernels" -I "$root/tests/cuda" \
        "$root/tests/cuda/gpu_parity.cu" -o "$work/gpu_parity"
    "$work/gpu_parity" "$2" ;;
check)
    "${CXX:-g++}" -std=c++17 -O2 -ffp-contract=off -I "$root/kernels" -I "$root/tests/cuda" \
        "$root/tests/cuda/parity_check.cpp" -o "$work/parity_check"
    "$work/parity_check" "$2" ;;
trace-input)
    "${BUILD:-$root/build/release}/trace_parity" input "$2" ${3:+"$3"} ;;
trace-run)
    "$nvcc" -std=c++17 -O3 --fmad=false -gencode arch=compute_90,code=sm_90 \
        -gencode arch=compute_75,code=compute_75 -I "$root/kernels" -I "$root/tests/cuda" \
        "$root/tests/cuda/trace_parity.cu" -o "$work/trace_parity"
    "$work/trace_parity" "$2" "$3" ;;
trace-check)
    "${BUILD:-$root/build/release}/trace_parity" check "$2" "$3" ;;
*)
    echo "usage: $0 run|check FILE | trace-input IN [RAYS] | trace-run IN OUT | trace-check IN OUT" >&2; exit 2 ;;
esac
