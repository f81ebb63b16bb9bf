#!/usr/bin/env bash
# mpi_scaling.sh — the measurements of docs/distributed.md: strong scaling of one render over
# 1 and 2 MPI ranks on this machine (one process without mpirun, mpirun -np 1 with Open MPI's
# default binding (a core) and unbound, -np 2 bound to a core each and unbound), RUNS times each, and the cost of one film reduction
# (mpi_reduce_bench) for 800x600 and 3840x2160 films, with and without the variance, over
# shared memory and over TCP on loopback.
#
# usage: scripts/mpi_scaling.sh [BUILD_DIR]     (default: build/release)
# env:   RUNS (default 3), SPP (default 32), SIZE (default 800x600)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build/release}"
runs="${RUNS:-3}"
spp="${SPP:-32}"
size="${SIZE:-800x600}"
[[ -x "$build/wavepath" && -x "$build/mpi_reduce_bench" ]] ||
  { echo "mpi_scaling.sh: build wavepath and mpi_reduce_bench in $build (WP_WITH_MPI)" >&2; exit 1; }
export POCL_CACHE_DIR="${POCL_CACHE_DIR:-$build/pocl-cache}" WP_CACHE_DIR="${WP_CACHE_DIR:-$build/wp-cache}"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_btl_vader_single_copy_mechanism=none
export OMPI_MCA_btl_tcp_if_include=lo OMPI_MCA_oob_tcp_if_include=lo
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
args=(render --size "$size" --spp "$spp" -q)
"$build/wavepath" "${args[@]}" -o "$tmp/warm.exr"  # programs into the caches, untimed
echo "# strong scaling: wavepath ${args[*]} ($(nproc) cores)"
for i in $(seq "$runs"); do
  echo "load average: $(cut -d' ' -f1-3 /proc/loadavg)"
  for cfg in single np1 np1-bind-none np2-bind-core np2-bind-none; do
    case $cfg in
      single) cmd=("$build/wavepath");;
      np1) cmd=(mpirun -np 1 "$build/wavepath");;  # Open MPI binds 1-2 ranks to a core by default
      np1-bind-none) cmd=(mpirun -np 1 --bind-to none "$build/wavepath");;
      np2-bind-core) cmd=(mpirun -np 2 --bind-to core "$build/wavepath");;
      np2-bind-none) cmd=(mpirun -np 2 --bind-to none "$build/wavepath");;
    esac
    s=$(date +%s.%N)
    "${cmd[@]}" "${args[@]}" -o "$tmp/$cfg.exr" --profile "$tmp/$cfg.json"
    e=$(date +%s.%N)
    python3 - "$tmp/$cfg.json" "$cfg" "$s" "$e" <<'PY'
import json, sys
j = json.load(open(sys.argv[1])); d = j.get("distributed", {})
print(f"{sys.argv[2]:14s} wall {float(sys.argv[4]) - float(sys.argv[3]):6.2f} s  render {j['settings']['render_s']:6.2f} s"
      + (f"  reduce {d['reduce_ms']:.1f} ms  film i/o {d['film_io_ms']:.1f} ms  rounds {d['rounds']}" if d else ""))
PY
  done
done
echo "# one film reduction, 2 ranks (median and best of 10)"
for v in none variance; do
  for sz in "800 600" "3840 2160"; do
    mpirun --oversubscribe -np 2 "$build/mpi_reduce_bench" $sz $v 10 | sed 's/^/shared memory: /'
    mpirun --oversubscribe -np 2 --mca btl self,tcp "$build/mpi_reduce_bench" $sz $v 10 | sed 's/^/tcp loopback:  /'
  done
done
