#!/usr/bin/env bash
# run_oclgrind.sh OCLGRIND TESTS — runs the tiny kernel tests ([oclgrind] and the layout
# probe) under Oclgrind's checks and fails on any report it writes (issue 5, case 9).
# The intersect and layout tests run with every check. The watertight probe test runs
# without --uninitialized: Oclgrind 21.10's uninitialized-value plugin crashes inside
# itself (a segfault in Uninitialized::instructionExecuted) on kernels/test_hard.cl's ray
# generator; its intersect launches are the same kernels as the first test's.
set -u
oclgrind=$1
tests=$2
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
exit $status
