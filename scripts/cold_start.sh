#!/usr/bin/env bash
# cold_start.sh — time to the first frame (issue 15, target 5), with empty program caches
# and with warm ones: `wavepath render --spp 1 --profile` and its "startup" section
# (render/startup.h), RUNS times each, cold and warm alternating, medians printed as a
# Markdown table. Cold: a fresh $WP_CACHE_DIR (wavepath's program binaries) and
# $POCL_CACHE_DIR (PoCL's builds and work-group functions) per run; warm: one pair of
# folders filled by an untimed run first. The wall time of the whole process is measured
# outside it too.
#
# usage: scripts/cold_start.sh [BUILD_DIR]      (default: build/release)
# env:   RUNS (default 3), SCENE (default builtin:cornell-box), SIZES (default "800x600 64x48")
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build/release}"
wavepath="$build/wavepath"
runs="${RUNS:-3}"
scene="${SCENE:-builtin:cornell-box}"
read -r -a sizes <<< "${SIZES:-800x600 64x48}"
[[ -x "$wavepath" ]] || { echo "cold_start.sh: no $wavepath (build the wavepath target)" >&2; exit 1; }
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

# One render; appends its startup figures and the process's wall ms to $tmp/<label>.txt.
one() {  # label size wp_cache pocl_cache
    local t0 t1
    t0=$(date +%s%N)
    WP_CACHE_DIR="$3" POCL_CACHE_DIR="$4" "$wavepath" render "$scene" --size "$2" --spp 1 -q \
        -o "$tmp/img.exr" --profile "$tmp/prof.json"
    t1=$(date +%s%N)
    python3 - "$tmp/prof.json" "$(( (t1 - t0) / 1000000 ))" >> "$tmp/$1.txt" <<'EOF'
import json, sys
s = json.load(open(sys.argv[1]))["startup"]
keys = ["exec_to_main_ms", "load_ms", "device_ms", "scene_ms", "programs_ms", "first_frame_ms",
        "first_frame_device_ms", "first_launch_ms", "to_first_frame_ms", "to_first_frame_from_exec_ms",
        "cache_store_ms"]
print(" ".join(str(s.get(k, -1)) for k in keys), sys.argv[2])
EOF
}

echo "load before: $(uptime | sed 's/.*load average: //')  ($scene, spp 1, runs $runs)"
echo
echo "| size | caches | exec→main | load | device | scene | programs | first frame (device + first launches) | main → first frame | exec → first frame | process wall | cache stores after |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
for size in "${sizes[@]}"; do
    warm_wp="$tmp/warm-wp" warm_pocl="$tmp/warm-pocl"
    rm -rf "$warm_wp" "$warm_pocl"
    one warmup "$size" "$warm_wp" "$warm_pocl"  # fills the warm caches
    rm -f "$tmp/cold.txt" "$tmp/warm.txt"
    for ((r = 0; r < runs; ++r)); do
        rm -rf "$tmp/cold-wp" "$tmp/cold-pocl"
        one cold "$size" "$tmp/cold-wp" "$tmp/cold-pocl"
        one warm "$size" "$warm_wp" "$warm_pocl"
    done
    for label in cold warm; do
        # Column medians over the runs.
        awk -v size="$size" -v label="$label" '
            { for (i = 1; i <= NF; ++i) v[i, NR] = $i; n = NR; nf = NF }
            END {
                for (i = 1; i <= nf; ++i) {
                    for (j = 1; j <= n; ++j) a[j] = v[i, j]
                    for (j = 2; j <= n; ++j) for (k = j; k > 1 && a[k - 1] > a[k]; --k) { t = a[k]; a[k] = a[k - 1]; a[k - 1] = t }
                    m[i] = (n % 2) ? a[(n + 1) / 2] : (a[n / 2] + a[n / 2 + 1]) / 2
                }
                printf "| %s | %s | %.0f | %.0f | %.0f | %.0f | %.0f | %.0f (%.0f + %.0f) | **%.0f** | %.0f | %.0f | %.0f |\n",
                       size, label, m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8], m[9], m[10], m[12], m[11]
            }' "$tmp/$label.txt"
    done
done
echo
echo "ms, medians of $runs runs; load after: $(uptime | sed 's/.*load average: //')"
