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
# FUZZ_RSS_LIMIT_MB (default 2048) and FUZZ_TIMEOUT (seconds per input, default 10) override.
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
failed=()
while IFS='|' read -r name max_len dict seeds; do
  [ -n "$name" ] || continue
  if [ $# -gt 0 ] && [[ " $* " != *" $name "* ]]; then continue; fi
  seed_dir="$build/fuzz-seeds/$name"
  corpus="$build/fuzz-corpus/$name"
  rm -rf "$seed_dir"
  mkdir -p "$corpus"
  # shellcheck disable=SC2086  # seeds holds several arguments (globs are expanded by the script)
  python3 "$source_dir/tests/fuzz/make_corpus.py" "$seed_dir" "$source_dir" "$max_len" $seeds \
    > /dev/null
  dict_args=()
  [ "$dict" = none ] || dict_args=(-dict="$source_dir/tests/fuzz/$dict")
  log="$build/fuzz-logs/$name.log"
  start=$(date +%s)
  status=0
  "$build/tests/fuzz/fuzz_$name" -max_total_time="$seconds" -max_len="$max_len" \
    -rss_limit_mb="$rss" -timeout="$timeout" -print_final_stats=1 "${dict_args[@]}" \
    -artifact_prefix="$build/fuzz-artifacts/$name-" "$corpus" "$seed_dir" > "$log" 2>&1 || status=$?
  elapsed=$(( $(date +%s) - start ))
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | cut -d' ' -f2)
  ft=$(grep -o 'ft: [0-9]*' "$log" | tail -1 | cut -d' ' -f2)
  corpus_size=$(find "$corpus" -type f | wc -l)
  echo "fuzz $name: ${elapsed} s, ${runs:-?} executions, cov ${cov:-?}, ft ${ft:-?}, corpus ${corpus_size} (+$(find "$seed_dir" -type f | wc -l) seeds), exit $status"
  if [ "$status" -ne 0 ]; then
    failed+=("$name")
    grep -m 20 -E 'ERROR|SUMMARY|reader |Test unit written|==[0-9]+==' "$log" || true
    echo "  (full log: $log)"
  fi
done < "$list"
if [ ${#failed[@]} -ne 0 ]; then
  echo "run_fuzzers.sh: failed: ${failed[*]}"
  exit 1
fi
