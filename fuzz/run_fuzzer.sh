#!/usr/bin/env bash
# run_fuzzer.sh BINARY NAME SECONDS FINDINGS_DIR — one bounded libFuzzer run (a ctest entry).
#
# Copies fuzz/corpus/NAME (seeds) and fuzz/regressions/NAME (inputs that once failed) into a
# scratch corpus, fuzzes for SECONDS with the dictionary fuzz/dict/NAME.dict, and fails on
# any crash, leak, timeout (> 5 s for one input), out-of-memory (> 2 GiB), sanitizer report
# or non-zero exit. Failing inputs are kept in FINDINGS_DIR/NAME/ and shown (hex dump) with
# the command that reproduces them. The seed folders are never modified.
set -uo pipefail
bin=$1 name=$2 seconds=$3 findings=$4
here="$(cd "$(dirname "$0")" && pwd)"
scratch="$(mktemp -d "${TMPDIR:-/tmp}/wp-fuzz-$name-XXXXXX")"
trap 'rm -rf "$scratch"' EXIT
mkdir -p "$scratch/corpus" "$scratch/artifacts"
for d in "$here/corpus/$name" "$here/regressions/$name"; do
  [ -d "$d" ] && find "$d" -maxdepth 1 -type f ! -name 'README*' -exec cp {} "$scratch/corpus/" \;
done
dict=()
[ -f "$here/dict/$name.dict" ] && dict=(-dict="$here/dict/$name.dict")

export ASAN_OPTIONS="halt_on_error=1:abort_on_error=1:detect_leaks=1:allocator_may_return_null=0:${ASAN_OPTIONS:-}"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:${UBSAN_OPTIONS:-}"
export LSAN_OPTIONS="suppressions=$here/lsan.supp:print_suppressions=0:${LSAN_OPTIONS:-}"
# -max_len: small inputs reach the parsers' corners fastest; 16 KiB still fits every seed.
# -seed and -runs: a fixed random seed (WP_FUZZ_SEED, default 1) and a fixed number of
# inputs (WP_FUZZ_RUNS, default 100,000), so that a CI run is reproducible: the same binary
# and corpus explore the same inputs on any machine (a time limit alone let a faster run go
# further and find what the previous one had not). SECONDS stays as a cap. Fuzz longer or
# with other seeds by hand to find new bugs.
"$bin" "${dict[@]}" -seed="${WP_FUZZ_SEED:-1}" -runs="${WP_FUZZ_RUNS:-100000}" \
  -max_total_time="$seconds" -timeout=5 -rss_limit_mb=2048 \
  -malloc_limit_mb=1024 -max_len=16384 -print_final_stats=1 \
  -artifact_prefix="$scratch/artifacts/" "$scratch/corpus" >"$scratch/log" 2>&1
rc=$?
found=$(find "$scratch/artifacts" -type f | wc -l)
if [ "$rc" -eq 0 ] && [ "$found" -eq 0 ]; then
  grep -E '^(#[0-9]+ +DONE|Done [0-9]+ runs|stat::number_of_executed_units|stat::peak_rss_mb)' "$scratch/log"
  echo "fuzz_$name: no crash, leak, hang or sanitizer report in ${WP_FUZZ_RUNS:-100000} inputs (seed ${WP_FUZZ_SEED:-1})"
  exit 0
fi

# Failure: the log's tail, the inputs, how to reproduce
tail -n 80 "$scratch/log"
mkdir -p "$findings/$name"
for f in "$scratch"/artifacts/*; do
  [ -f "$f" ] || continue
  cp "$f" "$findings/$name/"
  echo "---- input $(basename "$f") ($(wc -c <"$f") bytes), kept as $findings/$name/$(basename "$f"):"
  od -A d -c "$f" | head -n 40
  echo "reproduce: $bin $findings/$name/$(basename "$f")"
done
echo "fuzz_$name: FAILED (exit $rc, $found failing input(s))"
exit 1
