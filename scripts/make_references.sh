#!/usr/bin/env bash
# make_references.sh — regenerate the stored references of the [image] regression tests
# (tests/references/<scene>.exr + <scene>.var.exr: mean and variance of the mean), on
# purpose only: the tests never make a missing reference. Settings must match
# tests/test_image_regression.cpp (64x48, depth 3); references use 4096 spp and seed 1000
# (the tests render 128 spp with seed 7).
#
# usage: scripts/make_references.sh [BUILD_DIR]   (default: build/release)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build/release}"
wavepath="$build/wavepath"
[[ -x "$wavepath" ]] || { echo "make_references.sh: no wavepath binary at $wavepath (build first)" >&2; exit 1; }
out="$root/tests/references"
mkdir -p "$out"
for scene in cornell-box closed-box-furnace; do
    echo "make_references.sh: $scene"
    "$wavepath" render "builtin:$scene" --size 64x48 --depth 3 --spp 4096 --seed 1000 \
        --variance -q -o "$out/$scene.exr"
done
du -ch "$out"/*.exr | tail -1
