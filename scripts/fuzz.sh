#!/usr/bin/env bash
# Runs every libFuzzer target of tests/fuzz for a bounded time from its seed corpus and prints the
# executions per target. Builds the targets first (scripts/test_sanitized.sh --build-only). Any
# crash, sanitizer report, exception other than terramesh::InputError, input slower than the
# timeout or allocation over the limits fails the run; the input is kept as an artifact.
# See docs/reliability.md, "Fuzzing".
# Usage: scripts/fuzz.sh [TARGET...]   (default: all; a target is e.g. slam_json or colmap_bin)
# Environment: TERRAMESH_FUZZ_SECONDS (per target, default 20), TERRAMESH_FUZZ_TIMEOUT (seconds one
# input may take, default 10), TERRAMESH_SANITIZE_DIR (default build-sanitize), TERRAMESH_JOBS,
# TERRAMESH_FUZZ_SKIP_BUILD=1 (use the targets already built).
set -euo pipefail
cd "$(dirname "$0")/.."
source_dir="$PWD"
dir="${TERRAMESH_SANITIZE_DIR:-build-sanitize}"
seconds="${TERRAMESH_FUZZ_SECONDS:-20}"
timeout="${TERRAMESH_FUZZ_TIMEOUT:-10}"
targets=("$@")
if [ "${#targets[@]}" -eq 0 ]; then
  for corpus in tests/fuzz/corpus/*/; do
    targets+=("$(basename "$corpus")")
  done
fi

build_targets=()
for target in "${targets[@]}"; do
  if [ ! -f "tests/fuzz/fuzz_${target}.cpp" ]; then
    echo "fuzz.sh: no fuzz target \"$target\" (tests/fuzz/fuzz_${target}.cpp)" >&2
    exit 2
  fi
  build_targets+=(--target "fuzz_${target}")
done
if [ "${TERRAMESH_FUZZ_SKIP_BUILD:-0}" != 1 ]; then
  scripts/test_sanitized.sh --build-only "${build_targets[@]}"
fi

# New inputs go to a working corpus in the build folder, never into the source tree.
work="$dir/fuzz"
mkdir -p "$work/artifacts"
export ASAN_OPTIONS="detect_leaks=1:strict_string_checks=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
# Targets run side by side, TERRAMESH_JOBS at a time (each is one process); the table keeps their order.
jobs="${TERRAMESH_JOBS:-$(nproc)}"
run_target() {
  local target="$1" corpus="$work/corpus/$1" status=0
  mkdir -p "$corpus"
  "$dir/tests/fuzz/fuzz_$target" -max_total_time="$seconds" -timeout="$timeout" \
    -rss_limit_mb=2048 -malloc_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$work/artifacts/$target-" "$corpus" "$source_dir/tests/fuzz/corpus/$target" \
    >"$work/$target.log" 2>&1 || status=$?
  echo "$status" >"$work/$target.status"
}
running=0
for target in "${targets[@]}"; do
  rm -f "$work/$target.status"
  run_target "$target" &
  running=$((running + 1))
  if [ "$running" -ge "$jobs" ]; then
    wait -n || true
    running=$((running - 1))
  fi
done
wait
failed=()
total=0
printf '%-15s %8s %12s %10s %8s  %s\n' target seconds executions "exec/s" corpus result
for target in "${targets[@]}"; do
  log="$work/$target.log"
  status=$(cat "$work/$target.status" 2>/dev/null || echo "?")
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  units=$(find "$work/corpus/$target" -type f | wc -l)
  result=ok
  if [ "$status" != 0 ]; then
    result="FAILED (exit $status, log $log)"
    failed+=("$target")
  fi
  printf '%-15s %8s %12s %10s %8s  %s\n' "$target" "$seconds" "${runs:-?}" "${rate:-?}" "$units" "$result"
  total=$((total + ${runs:-0}))
done
echo "total executions: $total"
if [ "${#failed[@]}" -gt 0 ]; then
  for target in "${failed[@]}"; do
    echo "---- fuzz_$target: $work/$target.log (last lines)" >&2
    tail -40 "$work/$target.log" >&2
  done
  echo "fuzz.sh: failed: ${failed[*]}; reproduce with $dir/tests/fuzz/fuzz_TARGET ARTIFACT, then add the" \
       "input to tests/fuzz/corpus/TARGET/ as regression_NAME once fixed" >&2
  exit 1
fi
