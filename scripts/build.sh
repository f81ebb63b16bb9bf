#!/usr/bin/env bash
# Configures and builds wavepath (preset "release" unless WP_PRESET says otherwise).
set -euo pipefail
cd "$(dirname "$0")/.."
preset=${WP_PRESET:-release}
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset"
