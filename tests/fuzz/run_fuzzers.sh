#!/usr/bin/env bash
# Runs every libFuzzer harness of a fuzz build (tests/fuzz, docs/robustness.md#fuzzing) for a
# given time each, under ASan + UBSan, starting from its seed corpus; fails on any crash,
# sanitizer report, leak, time-out (-timeout) or memory excess (-rss_limit_mb).
#
#   tests/fuzz/run_fuzzers.sh BUILD_DIR SECONDS [NAME...]
#
# BUILD_DIR is a build configured with -DCMAKE_CXX_COMPILER=clang++-14 -DRINGLET_FUZZ=ON and
# built with --target fuzzers; NAME restricts the run to some harnesses (scene_json, ...).
# Seeds are regenerated from examples/ into BUILD_DIR/fuzz-seeds/NAME on every run; what the
# fuzzer finds is kept in BUILD_DIR/fuzz-corpus/NAME (reused by the next run, so long runs can
# be continued) and crashing inputs in BUILD_DIR/fuzz-artifacts/. One summary line per harness:
# executions, coverage (cov: edges, ft: features) and corpus size, from libFuzzer's final stats.
# FUZZ_RSS_LIMIT_MB (default 2048), FUZZ_TIMEOUT (seconds per input, default 10) and FUZZ_JOBS
# (harnesses run side by side, default the number of cores) override.
set -euo pipefail
source_dir="$(cd "$(dirname "$0")/../.." && pwd)"
build="$1"
seconds="$2"
shift 2
list="$build/fuzzers.txt"
[ -f "$list" ] || { echo "run_fuzzers.sh: $list not found (configure with -DRINGLET_FUZZ=ON)"; exit 1; }
rss="${FUZZ_RSS_LIMIT_MB:-2048}"
timeout="${FUZZ_TIMEOUT:-10}"
mkdir -p "$build/fuzz-artifacts" "$build/fuzz-logs"
# One harness per core at a time (FUZZ_JOBS overrides; each harness is one process): CI's time.
jobs="${FUZZ_JOBS:-$(nproc)}"
run_one() {
  local name="$1" max_len="$2" dict="$3" seeds="$4"
  local seed_dir="$build/fuzz-seeds/$name" corpus="$build/fuzz-corpus/$name"
  # Failed until it ends well: an error anywhere in here (set -e) leaves the mark.
  touch "$build/fuzz-logs/$name.failed"
  rm -rf "$seed_dir"
  mkdir -p "$corpus"
  # shellcheck disable=SC2086  # seeds holds several arguments (globs are expanded by the script)
  python3 "$source_dir/tests/fuzz/make_corpus.py" "$seed_dir" "$source_dir" "$max_len" $seeds \
    > /dev/null || { echo "fuzz $name: making the seed corpus failed"; return 1; }
  local dict_args=()
  [ "$dict" = none ] || dict_args=(-dict="$source_dir/tests/fuzz/$dict")
  local log="$build/fuzz-logs/$name.log" start status=0
  start=$(date +%s)
  "$build/tests/fuzz/fuzz_$name" -max_total_time="$seconds" -max_len="$max_len" \
    -rss_limit_mb="$rss" -timeout="$timeout" -print_final_stats=1 "${dict_args[@]}" \
    -artifact_prefix="$build/fuzz-artifacts/$name-" "$corpus" "$seed_dir" > "$log" 2>&1 || status=$?
  local elapsed=$(( $(date +%s) - start )) runs cov ft corpus_size summary
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1 || true)
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | cut -d' ' -f2 || true)
  ft=$(grep -o 'ft: [0-9]*' "$log" | tail -1 | cut -d' ' -f2 || true)
  corpus_size=$(find "$corpus" -type f | wc -l)
  summary="fuzz $name: ${elapsed} s, ${runs:-?} executions, cov ${cov:-?}, ft ${ft:-?}, corpus ${corpus_size} (+$(find "$seed_dir" -type f | wc -l) seeds), exit $status"
  if [ "$status" -ne 0 ]; then
    summary+=$'\n'"$(grep -m 20 -E 'ERROR|SUMMARY|reader |Test unit written|==[0-9]+==' "$log" || true)"
    summary+=$'\n'"  (full log: $log)"
  else
    rm -f "$build/fuzz-logs/$name.failed"
  fi
  echo "$summary"   # one write, so the lines of harnesses running side by side do not interleave
}
rm -f "$build"/fuzz-logs/*.failed
names=()
while IFS='|' read -r name max_len dict seeds; do
  [ -n "$name" ] || continue
  if [ $# -gt 0 ] && [[ " $* " != *" $name "* ]]; then continue; fi
  names+=("$name")
  while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n || true; done
  run_one "$name" "$max_len" "$dict" "$seeds" &
done < "$list"
wait
failed=()
for name in "${names[@]}"; do
  if [ -e "$build/fuzz-logs/$name.failed" ]; then failed+=("$name"); fi
done
if [ ${#failed[@]} -ne 0 ]; then
  echo "run_fuzzers.sh: failed: ${failed[*]}"
  exit 1
fi
