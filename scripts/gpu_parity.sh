#!/usr/bin/env bash
# gpu_parity.sh — the shared BSDF code of every material kind, run on an NVIDIA GPU (CUDA)
# and compared with the same code compiled as host C++ (tests/cuda/gpu_parity.cu,
# parity_check.cpp). Not part of CI (CI has no GPU).
#   scripts/gpu_parity.sh run OUT.bin     on the GPU machine: build and run the CUDA side
#   scripts/gpu_parity.sh check OUT.bin   anywhere: recompute on the host and compare
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
*)
    echo "usage: $0 run|check FILE" >&2; exit 2 ;;
esac
