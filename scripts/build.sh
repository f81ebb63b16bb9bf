#!/usr/bin/env bash
# Configures and builds wavepath (preset "release" unless WP_PRESET says otherwise).
# usage: scripts/build.sh [TARGET...]   (default: every target, tests and benchmarks too;
#        scripts/render.sh builds only `wavepath`, the first picture's target)
set -euo pipefail
cd "$(dirname "$0")/.."
preset=${WP_PRESET:-release}
cmake --preset "$preset" >/dev/null
targets=()
for t in "$@"; do targets+=(--target "$t"); done
cmake --build --preset "$preset" "${targets[@]}"
