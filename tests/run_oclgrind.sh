#!/usr/bin/env bash
# run_oclgrind.sh OCLGRIND TESTS WAVEPATH — runs the tiny kernel tests ([oclgrind] and the
# layout probe) under Oclgrind's checks and fails on any report it writes (issue 5, case 9);
# then renders two small scenes (and one adaptive render with a target error) with the same
# seed under Oclgrind and on the default
# device (PoCL) and requires the images to agree (per-pixel z-test with both variances,
# and relMSE < 1e-9: they differ only by the last-ulp freedom OpenCL gives sqrt, sin, cos
# and log, measured 7e-15 and 1e-13).
# The intersect and layout tests run with every check. The watertight probe test runs
# without --uninitialized: Oclgrind 21.10's uninitialized-value plugin crashes inside
# itself (a segfault in Uninitialized::instructionExecuted) on kernels/test_hard.cl's ray
# generator; its intersect launches are the same kernels as the first test's.
set -u
oclgrind=$1
tests=$2
wavepath=${3:-}
log=$(mktemp)
trap 'rm -f "$log"' EXIT
status=0
run() {  # run CHECKS... -- TEST-SPEC
  local checks=()
  while [ "$1" != "--" ]; do checks+=("$1"); shift; done
  shift
  : >"$log"
  echo "run_oclgrind: oclgrind ${checks[*]} $tests \"$1\""
  "$oclgrind" "${checks[@]}" --log "$log" "$tests" "$1" || status=1
  if [ -s "$log" ]; then
    echo "run_oclgrind: Oclgrind reported problems:"
    cat "$log"
    status=1
  fi
}
run --check-api --data-races --uninitialized -- \
  "oclgrind: intersect on a tiny scene equals the host traversal bit for bit,shared struct layouts match between host and device"
run --check-api --data-races -- "oclgrind: the watertight probe on tiny meshes"
# Image level: the whole renderer (every stage, NEE + MIS, mirror, GGX) under Oclgrind's
# API and race checks (the uninitialized-value plugin crashes inside itself on generate).
if [ -n "$wavepath" ]; then
  dir=$(mktemp -d)
  trap 'rm -f "$log"; rm -rf "$dir"' EXIT
  # The third run: adaptive sampling with a target error (the active-list generate and
  # accumulate kernels, adaptive_error; docs/adaptive.md), stopped by --spp. The fourth: the
  # same with RQMC replicates (accumulate_film_active_replicates, adaptive_error_replicates)
  # and an AOV over the active list (aov_accumulate_active).
  # (No Sobol run, with or without replicates: LLVM turns the bit reversals of sobol.h into
  # llvm.bitreverse.i32, which Oclgrind 21.10 cannot run, "Undefined external function".)
  for run_args in "builtin:cornell-box --spp 2 --sampler random" "builtin:veach-plates --spp 2 --sampler random" \
                  "builtin:veach-plates --spp 12 --sampler random --adaptive --min-spp 2 --adaptive-threshold 1e-2 --target-error 1e-6" \
                  "builtin:veach-plates --spp 8 --sampler random --adaptive --min-spp 2 --adaptive-threshold 1e-2 --target-error 1e-6 --replicates 2 --aov albedo"; do
    read -r -a extra <<<"$run_args"
    args=(render "${extra[0]}" --size 8x6 --depth 3 --seed 3 --variance -q "${extra[@]:1}")
    : >"$log"
    echo "run_oclgrind: oclgrind --check-api --data-races wavepath ${args[*]}"
    "$oclgrind" --check-api --data-races --log "$log" "$wavepath" "${args[@]}" -o "$dir/og.exr" || status=1
    if [ -s "$log" ]; then
      echo "run_oclgrind: Oclgrind reported problems:"
      cat "$log"
      status=1
    fi
    "$wavepath" "${args[@]}" -o "$dir/pocl.exr" || status=1
    "$wavepath" compare "$dir/og.exr" "$dir/pocl.exr" --variance "$dir/og.var.exr" \
      --ref-variance "$dir/pocl.var.exr" --min-pass 0.9975 --max-relmse 1e-9 || status=1
  done
  # The feature buffers (aov stage, through the box's mirror) and the denoise stage.
  args=(render builtin:cornell-box --size 8x6 --spp 2 --depth 3 --seed 3 --sampler random --aov all --denoise -q)
  : >"$log"
  echo "run_oclgrind: oclgrind --check-api --data-races wavepath ${args[*]}"
  "$oclgrind" --check-api --data-races --log "$log" "$wavepath" "${args[@]}" -o "$dir/dn.exr" || status=1
  if [ -s "$log" ]; then
    echo "run_oclgrind: Oclgrind reported problems:"
    cat "$log"
    status=1
  fi
fi
exit $status
