#!/usr/bin/env bash
# run.sh — build and run the SIMD-layout probe on the first OpenCL device (PoCL here).
# Prints ns per path for the four kernels of probe.cl and, from POCL_VECTORIZER_REMARKS=1, PoCL's
# word on which work-group loops it vectorised. Usage: scripts/pocl_simd/run.sh [paths] [runs]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
g++ -std=c++20 -O2 -DCL_HPP_ENABLE_EXCEPTIONS -DCL_HPP_TARGET_OPENCL_VERSION=120 -DCL_HPP_MINIMUM_OPENCL_VERSION=120 \
    "$here/probe.cpp" -lOpenCL -o "$tmp/probe"
export POCL_CACHE_DIR="$tmp/cache"   # cold: the remarks come from the compile
status=0
POCL_VECTORIZER_REMARKS=1 "$tmp/probe" "$here/probe.cl" "${1:-1048576}" "${2:-15}" > "$tmp/log" 2>&1 || status=$?
# PoCL prints its remarks without line ends; one per line, then per kernel (a kernel's
# remarks follow the line that inlines it into its work-group function) the loop verdicts.
sed 's/<unknown>:0:0: /\n/g' "$tmp/log" |
    sed -E 's/^(List vectorization was possible but not beneficial with cost [0-9]+ >= [0-9]+|Cannot SLP vectorize list: [a-z ]+)//' |
    awk '/ns\/path|difference/ { print; next }
         match($0, /inlined into .?_pocl_kernel_[a-z0-9_]+_workgroup.? /) {
             k = $0; sub(/^.*inlined into .?_pocl_kernel_/, "", k); sub(/_workgroup.*$/, "", k); next }
         /^vectorized loop|^loop not vectorized:/ { if (!seen[k, $0]++) print "  PoCL on " k ": " $0 }'
[ "$status" = 0 ] || { echo "probe failed (exit $status):"; tail -20 "$tmp/log"; }
exit "$status"
