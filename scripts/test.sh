#!/usr/bin/env bash
# Fresh-machine test run: installs what is missing, builds, runs every test with ctest.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/setup.sh"
"$root/scripts/build.sh"
cd "$root/build/${WP_PRESET:-release}"
ctest --output-on-failure -j "$(nproc)" "$@"
