#!/usr/bin/env bash
# make_sampling_plot.sh — the importance-sampling figures of docs/importance-sampling.md:
# `wavepath converge` at equal time (GGX glossy everywhere) of
#   uniform     the original estimator: --sampling uniform --sampler random --rr-depth -1
#   cosine, nee BSDF sampling only / NEE only (with the defaults: Sobol, roulette from 3)
#   mis-random  MIS with the counter-based random numbers
#   mis         the default: MIS, Owen-scrambled Sobol, roulette from bounce 3
# on
#   * the built-in Cornell box, 96x72, depth 5, against an 8192-spp reference (defaults);
#   * builtin:veach-plates, 192x128, depth 3, against a 4096-spp reference (defaults);
# RUNS runs of TIME seconds per configuration (default 2 x 3 s). Writes
# docs/sampling-cornell.csv, docs/sampling-veach.csv, docs/sampling-cornell.png,
# docs/sampling.png (the Veach scene) and prints the equal-time tables. Then renders each
# strategy on the Veach scene for TIME seconds and prints relMSE per plate (per roughness)
# against the reference (scripts/plate_errors.py).
#
# usage: scripts/make_sampling_plot.sh [BUILD_DIR] [TIME] [RUNS]   (default build/release 3 2)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build/release}"
time_s="${2:-3}"
runs="${3:-2}"
wp="$build/wavepath"
configs() {  # SIZE DEPTH
    local o="--size $1 --depth $2"
    echo "uniform=--sampling uniform --sampler random --rr-depth -1 $o"
    echo "cosine=--sampling cosine $o"
    echo "nee=--sampling nee $o"
    echo "mis-random=--sampling mis --sampler random $o"
    echo "mis=--sampling mis $o"
}
args() { configs "$@" | while read -r c; do printf -- '--config\0%s\0' "$c"; done; }
mapfile -d '' cornell < <(args 96x72 5)
mapfile -d '' veach < <(args 192x128 3)

"$wp" converge --time "$time_s" --runs "$runs" -q "${cornell[@]}" \
    --reference-options "--size 96x72 --depth 5" --reference-spp 8192 \
    --csv "$root/docs/sampling-cornell.csv"
python3 "$root/scripts/plot_convergence.py" "$root/docs/sampling-cornell.csv" \
    -o "$root/docs/sampling-cornell.png" --title "Cornell box 96x72, depth 5: relMSE by --sampling"

"$wp" converge builtin:veach-plates --time "$time_s" --runs "$runs" -q "${veach[@]}" \
    --reference-options "--size 192x128 --depth 3" --reference-spp 4096 \
    --csv "$root/docs/sampling-veach.csv"
python3 "$root/scripts/plot_convergence.py" "$root/docs/sampling-veach.csv" \
    -o "$root/docs/sampling.png" --title "veach-plates 192x128, depth 3: relMSE by --sampling"

# Per-plate errors at equal time against the converge reference.
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
configs 192x128 3 | while IFS='=' read -r name opts; do
    # shellcheck disable=SC2086
    "$wp" render builtin:veach-plates $opts --spp 1000000 --time "$time_s" --seed 77 -q \
        -o "$tmp/$name.exr"
done
python3 "$root/scripts/plate_errors.py" "$root/docs/sampling-veach.ref.exr" \
    "$tmp"/uniform.exr "$tmp"/cosine.exr "$tmp"/nee.exr "$tmp"/mis-random.exr "$tmp"/mis.exr
