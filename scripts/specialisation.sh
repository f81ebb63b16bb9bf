#!/usr/bin/env bash
# specialisation.sh — what "model only what the scene needs" buys (issue 15, target 5):
# every scene in scenes/ and the built-in Cornell box rendered with the scene-specialised
# kernels (`--kernels specialised`, the default) and with the generic build that has every
# feature switch on (`--kernels generic`), at equal spp, the two alternating RUNS times
# after one untimed warm-up each (program builds, PoCL's work-group compiles), run r with
# seed r. Prints a Markdown table of the median over runs of `median_ms_per_spp`
# (--profile) and the ratio generic / specialised (> 1: specialisation is faster), and, as
# the generic build's light sampling may spend samples differently (with emitters, half of
# them on its black environment: docs/performance.md), the noise of each at that spp — the
# mean relMSE (`wavepath compare`) between the images of runs r and r + 1 — and the ratio at
# equal error, (ms/spp × relMSE) generic over specialised. docs/performance.md has the
# figures.
#
# usage: scripts/specialisation.sh [BUILD_DIR]      (default: build/release)
# env:   SPP (default 8), RUNS (default 3), SIZE (WxH for every scene; default each
#        scene's own), SCENES (space-separated list; default builtin:cornell-box and
#        scenes/*.json scenes/*.xml)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build/release}"
wavepath="$build/wavepath"
spp="${SPP:-8}"
runs="${RUNS:-3}"
[[ -x "$wavepath" ]] || { echo "specialisation.sh: no $wavepath (build the wavepath target)" >&2; exit 1; }
if [[ -n "${SCENES:-}" ]]; then
    read -r -a scenes <<< "$SCENES"
else
    scenes=(builtin:cornell-box "$root"/scenes/*.json "$root"/scenes/*.xml)
fi
size=()
[[ -n "${SIZE:-}" ]] && size=(--size "$SIZE")
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

# ms/spp of one render (median over its waves, from the profile JSON); the image goes to
# $tmp/<kernels>-<seed>.exr.
ms_per_spp() {  # scene kernels seed
    "$wavepath" render "$1" --kernels "$2" --spp "$spp" --seed "$3" "${size[@]}" -q \
        -o "$tmp/$2-$3.exr" --profile "$tmp/prof.json"
    python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["median_ms_per_spp"])' "$tmp/prof.json"
}
# Mean relMSE between the images of consecutive seeds (two independent renders).
noise() {  # kernels
    local r sum=0
    for ((r = 0; r + 1 < runs; ++r)); do
        sum=$(awk -v s="$sum" -v x="$("$wavepath" compare "$tmp/$1-$r.exr" "$tmp/$1-$((r + 1)).exr" |
              awk '$1 == "relMSE" {print $2}')" 'BEGIN {print s + x}')
    done
    awk -v s="$sum" -v n="$((runs - 1))" 'BEGIN {print s / n}'
}
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR] = $1} END {print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }

echo "load before: $(uptime | sed 's/.*load average: //')  (spp $spp, runs $runs${SIZE:+, size $SIZE})"
echo
echo "| scene | specialised ms/spp | generic ms/spp | generic / specialised | relMSE specialised | relMSE generic | at equal error |"
echo "|---|---|---|---|---|---|---|"
for scene in "${scenes[@]}"; do
    ms_per_spp "$scene" specialised 0 > /dev/null  # warm-up: builds and compiles
    ms_per_spp "$scene" generic 0 > /dev/null
    s=() g=()
    for ((r = 0; r < runs; ++r)); do
        s+=("$(ms_per_spp "$scene" specialised "$r")")
        g+=("$(ms_per_spp "$scene" generic "$r")")
    done
    ms=$(median "${s[@]}") mg=$(median "${g[@]}")
    name="${scene#"$root"/}"
    if ((runs > 1)); then
        es=$(noise specialised) eg=$(noise generic)
    else
        es=0 eg=0
    fi
    awk -v n="$name" -v a="$ms" -v b="$mg" -v ea="$es" -v eb="$eg" 'BEGIN {
        eq = (ea > 0) ? sprintf("%.2f×", b * eb / (a * ea)) : "–"
        printf "| %s | %.1f | %.1f | %.2f× | %.3g | %.3g | %s |\n", n, a, b, b / a, ea, eb, eq}'
done
echo
echo "load after: $(uptime | sed 's/.*load average: //')"
