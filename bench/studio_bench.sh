#!/usr/bin/env bash
# The studio's benchmark: `bench/studio_bench.sh [BUILD_DIR]` runs bench/studio_bench.script in
# ringlet-studio under xvfb-run with Mesa's llvmpipe (or on the display given by $DISPLAY with
# RINGLET_BENCH_GPU=1) and prints the `bench:`, `frames:` and `memory:` lines
# (docs/benchmarks.md, "The studio"). Not a test: speed targets live here, not in ctest.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=${1:-$ROOT/build}
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
sed -e "s|@EXAMPLES@|$ROOT/examples|g" "$ROOT/bench/studio_bench.script" > "$OUT/script.txt"
echo "machine: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)"
if [ "${RINGLET_BENCH_GPU:-0}" = 1 ]; then
  "$BUILD/studio/ringlet-studio" --script "$OUT/script.txt" --size 1280x800
else
  LIBGL_ALWAYS_SOFTWARE=1 xvfb-run -a -s "-screen 0 1280x800x24" \
    "$BUILD/studio/ringlet-studio" --script "$OUT/script.txt" --size 1280x800
fi
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
