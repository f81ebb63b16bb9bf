#!/usr/bin/env bash
# make_convergence_plot.sh — the speed-against-error figure of docs/speed-vs-error.md:
# the built-in Cornell box at 96x72, depths 2 and 5 with the stackless traversal and depth 5
# with the stack traversal, 3 runs of 3 s each,
# against a depth-5 reference of 8192 spp rendered by converge itself (own seed, variance).
# Writes docs/convergence.csv, docs/convergence.png and prints the equal-time table.
#
# usage: scripts/make_convergence_plot.sh [BUILD_DIR]   (default: build/release)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build/release}"
configs=(--config "depth2=--depth 2 --size 96x72" --config "depth5=--depth 5 --size 96x72"
         --config "depth5-stack=--depth 5 --size 96x72 --traversal stack")
"$build/wavepath" converge --time 3 --runs 3 "${configs[@]}" \
    --reference-options "--depth 5 --size 96x72" --reference-spp 8192 \
    --csv "$root/docs/convergence.csv"
python3 "$root/scripts/plot_convergence.py" "$root/docs/convergence.csv" \
    -o "$root/docs/convergence.png" --title "Cornell box 96x72: relMSE against time and spp"
