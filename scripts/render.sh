#!/usr/bin/env bash
# Fresh-machine render: installs what is missing, builds only the `wavepath` target (the
# tests and fuzzers build in scripts/test.sh), renders.
# Extra arguments go to `wavepath render` (default: the built-in Cornell box).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/setup.sh"
"$root/scripts/build.sh" wavepath
exec "$root/build/${WP_PRESET:-release}/wavepath" render "$@"
