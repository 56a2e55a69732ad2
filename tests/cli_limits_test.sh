#!/usr/bin/env bash
# Limits on the products that drive work and memory, and interrupted or failed writes (issue 16
# items 2 and 4, docs/robustness.md). Each limit: a small input that exceeds it must give exit
# code 1, one error line naming the fields and the limit, and write nothing (it is checked
# before any allocation or solve). Each interrupted or failed write must leave nothing the user
# did not have: no temporary file, no half-written output directory.
#
# Needs RINGLET (the built binary) and EXAMPLES (the examples/ directory); run by ctest as
# `cli_limits`. Exits non-zero if any check failed, after printing what failed.
set -u

: "${RINGLET:?set RINGLET to the ringlet binary}"
: "${EXAMPLES:?set EXAMPLES to the examples directory}"

work=$(mktemp -d "${TMPDIR:-/tmp}/ringlet_cli_limits.XXXXXX") || exit 1
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/in/bodies" "$work/out"
cp "$EXAMPLES/bodies/mannequin.json" "$work/in/bodies/mannequin.json"

source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"  # checks, fail, ok, expect_*

run() {
  timeout 120 "$RINGLET" "$@" >"$work/stdout" 2>"$work/stderr"
  rc=$?
  if [ "$rc" -eq 124 ]; then echo "ringlet: timed out" >>"$work/stderr"; fi
}

# bad WHAT SUBSTRING ARGS...: exit 1, one error line mentioning SUBSTRING, $work/never not made.
bad() {
  local what=$1 substring=$2
  shift 2
  run "$@"
  expect_rc "$what" 1
  expect_one_error_line "$what" "$substring"
  if [ -e "$work/never" ]; then
    fail "$what: wrote $work/never: $(find "$work/never" | head -5 | tr '\n' ' ')"
    rm -rf "$work/never"
  else ok; fi
}

# style NAME JSON-MEMBERS: a hairstyle on the mannequin with the given members.
style() {
  echo "{\"body\": \"bodies/mannequin.json\", $2}" >"$work/in/$1.json"
}

# ============================================================================================
# Limits on products (each input is a few bytes; without the limit each would run for hours or
# allocate gigabytes).

# Dense BFGS: at most 1000 segments (its 3n x 3n matrix: 72 n^2 bytes).
echo '{"solver": {"method": "bfgs"}, "strands": [{"length": 0.1, "segments": 1001}]}' \
  >"$work/in/bfgs.json"
bad "solve: bfgs 1001 segments" \
  'strands[0].segments: 1001 segments exceed the limit of 1000 for the method "bfgs"' \
  solve "$work/in/bfgs.json" -o "$work/never"
# 1000 segments are allowed (the scene parses; --help-free check: a short solve of 1 strand
# would take seconds with 1000 segments, so only the bound is shown by the message above).

# The whole scene: at most 10^7 segments (101 strands of 100,000). Refused at the strand that
# crosses the limit, before its segments are allocated.
/usr/bin/python3 -c '
import sys
root = "\"root\": {\"position\": [0, 0, 0], \"tangent\": [0, 0, -1], \"normal\": [1, 0, 0]}"
s = ",".join(["{\"length\": 1, \"segments\": 100000, " + root + "}"] * 101)
sys.stdout.write("{\"strands\": [" + s + "]}")' >"$work/in/total.json"
bad "solve: 101 x 100,000 segments" \
  "strands[100].segments: 100000 more segments would take the scene beyond its limit of 10000000" \
  solve "$work/in/total.json" -o "$work/never"

# Natural turning |kappa| L at most 10^5 rad (the Kirchhoff certificate's work grows with it).
echo '{"strands": [{"length": 1, "natural_curvature": [1e6, 0]}]}' >"$work/in/turning.json"
bad "solve: natural curvature 1e6 over 1 m" \
  "strands[0].natural_curvature: with natural_twist, turns the strand by 1e+06 rad over its length, more than the limit of 1e+05 rad" \
  solve "$work/in/turning.json" -o "$work/never"

# Hairstyles: masters x segments, masters x (1 + children) x segments when every child is
# solved, masters x strands per wisp x points (2^31 - 1), and bfgs segments. Checked when the
# file is read: before any root is placed or master solved.
style masters '"masters": {"count": 1000000, "segments": 20}'
bad "groom: 10^6 masters x 20 segments" \
  "masters.count x masters.segments = 20000000 segments to solve, more than the limit of 10000000" \
  groom "$work/in/masters.json" -o "$work/never"
style children '"masters": {"count": 1000, "segments": 20}, "wisps": {"strands_per_wisp": 1000, "children": "solved"}'
bad "groom: 1000 masters x 1001 solved strands x 20 segments" \
  "masters.count x (1 + wisps.strands_per_wisp) x masters.segments = 20020000 segments" \
  groom "$work/in/children.json" -o "$work/never"
style points '"masters": {"count": 10000, "segments": 5}, "wisps": {"strands_per_wisp": 1000, "points_per_strand": 256}'
bad "groom: 2.56e9 wisp points" \
  "masters.count x wisps.strands_per_wisp x wisps.points_per_strand = 2560000000 points, more than the limit of 2^28" \
  groom "$work/in/points.json" -o "$work/never"
style bfgs_style '"masters": {"count": 10, "segments": 1001}, "solver": {"method": "bfgs"}'
bad "groom: bfgs with 1001 segments" \
  'masters.segments: 1001 segments exceed the limit of 1000 for the method "bfgs"' \
  groom "$work/in/bfgs_style.json" -o "$work/never"

# Renders: pixels at most 2^26, camera samples at most 2^30; the options, the settings file and
# groom --render (before the groom).
style tiny '"masters": {"count": 12, "seed": 4, "segments": 5, "points_per_segment": 2}, "hair": {"length": 0.1}, "wisps": {"strands_per_wisp": 3, "points_per_strand": 6}, "layers": {"count": 1}'
run groom "$work/in/tiny.json" -o "$work/in/groom" --quiet
expect_rc "groom of the tiny hairstyle" 0
HAIR="$work/in/groom/strands.hair"
bad "render --width 16384 --height 16384" \
  "width x height = 16384 x 16384 = 268435456 pixels, more than the limit of 2^26" \
  render "$HAIR" --width 16384 --height 16384 -o "$work/never/image.png"
bad "render 2048 x 2048 x 512 spp" \
  "width x height x samples_per_pixel = 2048 x 2048 x 512 = 2147483648 camera samples, more than the limit of 2^30" \
  render "$HAIR" --width 2048 --height 2048 --spp 512 -o "$work/never/image.png"
echo '{"render": {"width": 4096, "height": 4096, "samples_per_pixel": 128}}' >"$work/in/settings.json"
bad "render --settings 4096 x 4096 x 128" \
  "settings.json: render: width x height x samples_per_pixel = 4096 x 4096 x 128" \
  render "$HAIR" --settings "$work/in/settings.json" -o "$work/never/image.png"
start=$(date +%s)
bad "groom --render 8192 x 8192 x 64" "--width, --height, --spp (or the file's render settings)" \
  groom "$work/in/tiny.json" --render --width 8192 --height 8192 --spp 64 -o "$work/never"
[ $(($(date +%s) - start)) -lt 10 ] && ok || fail "groom --render limit: not refused before the groom"

# ============================================================================================
# Failed and interrupted writes

# A full disk, simulated without root by a file-size limit (ulimit -f, in KiB; SIGXFSZ ignored
# so that write() fails with EFBIG instead of killing the process): the groom's files are all
# staged first, so a failure writes none of them and removes the directory it created.
groom_limited() {  # groom_limited KIB ARGS...
  local kib=$1
  shift
  (
    trap '' XFSZ
    ulimit -f "$kib"
    exec timeout 120 "$RINGLET" groom "$@"
  ) >"$work/stdout" 2>"$work/stderr"
  rc=$?
}
groom_limited 4 "$work/in/tiny.json" -o "$work/out/full/groom" --quiet
expect_rc "groom on a full disk" 1
expect_one_error_line "groom on a full disk" "File too large (nothing was written)"
[ ! -e "$work/out/full" ] && ok || fail "groom on a full disk left $(find "$work/out/full")"
# With --force over an earlier output: every old file is kept as it was.
mkdir -p "$work/out/old"
for f in masters.json strands.hair strands.usda strands.obj; do echo "old $f" >"$work/out/old/$f"; done
groom_limited 4 "$work/in/tiny.json" -o "$work/out/old" --force --quiet
expect_rc "groom --force on a full disk" 1
expect_one_error_line "groom --force on a full disk" "(nothing was written)"
expect_files "groom --force on a full disk" "$work/out/old" masters.json strands.hair strands.usda \
  strands.obj
for f in masters.json strands.hair strands.usda strands.obj; do
  [ "$(cat "$work/out/old/$f")" = "old $f" ] && ok || fail "groom on a full disk changed old $f"
done
# solve: one file, the same rule.
(
  trap '' XFSZ
  ulimit -f 1
  exec timeout 120 "$RINGLET" solve "$EXAMPLES/strands.json" -o "$work/out/solve_full.json" --quiet
) >"$work/stdout" 2>"$work/stderr"
rc=$?
expect_rc "solve on a full disk" 1
expect_one_error_line "solve on a full disk" "solve_full.json: cannot write: File too large"
expect_files "solve on a full disk" "$work/out" old

# SIGINT / SIGTERM while a groom writes its files (a larger head: ~10 MB of .usda): the signal
# is sent as soon as a temporary file appears; the command must end by the signal, leave no
# temporary and no partial output directory.
style big '"masters": {"count": 40, "seed": 3, "segments": 5}, "hair": {"length": 0.1}, "wisps": {"strands_per_wisp": 300, "points_per_strand": 32}, "layers": {"count": 1}'
for signal in INT TERM; do
  out="$work/out/sig_$signal"
  # A background job of a script ignores SIGINT (bash, without job control) and ringlet keeps
  # an ignored signal ignored (as nohup wants): env restores the default first.
  env --default-signal=INT,TERM "$RINGLET" groom "$work/in/big.json" -o "$out" --quiet \
    >"$work/stdout" 2>"$work/stderr" &
  pid=$!
  shopt -s nullglob dotglob
  sent=0
  for _ in $(seq 1 20000); do
    temporaries=("$out"/.*.tmp-*)
    if [ ${#temporaries[@]} -gt 0 ]; then
      kill -s "$signal" "$pid" 2>/dev/null && sent=1
      break
    fi
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.005
  done
  wait "$pid"
  rc=$?
  if [ "$sent" -eq 1 ]; then
    expected=$((128 + $(kill -l "$signal")))
    [ "$rc" -eq "$expected" ] && ok || fail "groom SIG$signal: exit code $rc, expected $expected"
    left=("$out"/.*.tmp-*)
    [ ${#left[@]} -eq 0 ] && ok || fail "groom SIG$signal left temporaries: ${left[*]}"
    [ ! -e "$out" ] && ok || fail "groom SIG$signal left $(ls -A "$out" | tr '\n' ' ')"
  else
    fail "groom SIG$signal: no temporary file seen before the groom ended (rc $rc); the test could not interrupt the write"
  fi
  shopt -u nullglob dotglob
done

# --------------------------------------------------------------------------------------------
if [ "$failures" -ne 0 ]; then
  echo "cli_limits_test: $failures of $((checks + failures)) checks FAILED" >&2
  exit 1
fi
echo "cli_limits_test: all $checks checks passed"
