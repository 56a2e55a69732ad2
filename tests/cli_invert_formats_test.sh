#!/usr/bin/env bash
# `ringlet invert` on every polyline target format (docs/inverse.md, docs/file-formats.md): the
# equilibria of the 5 example strands (exact piecewise helices, 4 points per segment) written by
# `ringlet convert` as .hair, .obj, .usda and .data (y up, centimetres) are fitted without their
# root frames and inverted. Expected: where the fit's breaks fall on the helices' breaks, the fit
# recovers them to the float rounding of the files (a point moves by at most 2^-24 |x| ~ 3e-8 m,
# a few 1e-8 L for these 8-40 cm strands; the bound checked is 1e-6 L; measured 2.5e-8 to
# 3.5e-8 L), the inverted rest shapes hold the fitted curves (<= 1e-6 L),
# and every format gives the same fit (same points up to float rounding). Bad input in each
# format: exit 1, one line naming the file, strand and point, nothing written.
#
# Needs RINGLET (the built binary) and EXAMPLES (the examples/ directory); run by ctest as
# `cli_invert_formats`. Exits non-zero if any check failed, after printing what failed.
set -u

: "${RINGLET:?set RINGLET to the ringlet binary}"
: "${EXAMPLES:?set EXAMPLES to the examples directory}"
PYTHON=/usr/bin/python3

work=$(mktemp -d "${TMPDIR:-/tmp}/ringlet_cli_invert_formats.XXXXXX") || exit 1
trap 'rm -rf "$work"' EXIT

source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"  # checks, fail, ok, run, expect_*

# Targets: the equilibria of the example strands, 4 points per segment, no frame.
run solve "$EXAMPLES/strands.json" -o "$work/targets.json"
expect_rc "solve the example strands" 0
run invert "$work/targets.json" -o "$work/exact" -q
expect_rc "invert the exact targets" 0
run convert "$work/exact/equilibrium.hair" "$work/t.obj"
expect_rc "convert to .obj" 0
run convert "$work/exact/equilibrium.hair" "$work/t.usda"
expect_rc "convert to .usda" 0
run convert "$work/exact/equilibrium.hair" "$work/t.data" --out-up-axis y --out-units-per-metre 100
expect_rc "convert to .data (y up, cm)" 0

for target in equilibrium.hair t.obj t.usda t.data; do
  path="$work/$target"
  [ "$target" = equilibrium.hair ] && path="$work/exact/equilibrium.hair"
  flags=()
  [ "$target" = t.data ] && flags=(--up y --units-per-metre 100)
  run invert "$path" -o "$work/out_$target" --segments 15 "${flags[@]}"
  expect_rc "invert $target" 0
  "$PYTHON" - "$work/out_$target/summary.json" <<'PY' && ok || fail "$target: summary.json values"
import json, sys
s = json.load(open(sys.argv[1]))
assert s["strands"] == 5 and s["unstable"] == 0 and s["unconverged"] == 0, s
assert all(r["segments"] == 15 for r in s["strand_results"])
# examples/strands.json has 15, 15, 20, 15 and 40 segments: with 15 segments the breaks of
# strands 0, 1 and 3 fall on points (exact up to the float rounding), those of 2 and 4 do not.
per = [r["fit_max_distance"] / r["length"] for r in s["strand_results"]]
assert all(0 < per[k] <= 1e-6 for k in (0, 1, 3)), per
assert all(per[k] <= 1e-3 for k in (2, 4)), per
assert s["max_deviation_per_length"] <= 1e-6, s["max_deviation_per_length"]
assert s["naive_max_deviation_per_length"] > 0.01, s["naive_max_deviation_per_length"]
PY
done
# Every format gives the same rest shapes as the .hair for the strands fitted exactly (0, 1, 3;
# points equal up to float rounding and the cm round trip of .data): rest curvatures within 1e-3
# relative of the largest (or of 1 /m: strand 0 is straight). (Strands 2 and 4 are approximations whose twist is weakly determined
# by the points: their rest curvatures move with the rounding.)
"$PYTHON" - "$work"/out_{equilibrium.hair,t.obj,t.usda,t.data}/rest_shapes.json <<'PY' && ok || fail "formats disagree"
import json, sys
ref = json.load(open(sys.argv[1]))["strands"]
for path in sys.argv[2:]:
    other = json.load(open(path))["strands"]
    assert len(other) == len(ref)
    for k in (0, 1, 3):
        a, b = ref[k], other[k]
        qa = [x for t in a["rest_curvatures"] for x in t]
        qb = [x for t in b["rest_curvatures"] for x in t]
        big = max(1.0, max(abs(x) for x in qa))  # 1/m: strand 0 is straight
        assert max(abs(x - y) for x, y in zip(qa, qb)) <= 1e-3 * big, path
PY

# The fixtures of the readers' tests: the 2 z-up strands of polylines.obj, fitted automatically.
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
run invert "$here/data/strand_targets/polylines.obj" -o "$work/poly"
expect_rc "invert polylines.obj" 0
grep -q "inverted 2 strands" "$work/stdout" && ok || fail "polylines.obj: $(cat "$work/stdout")"

# Outputs at the target's own sampling (issue 25, item 11): a dense target (25 points per helical
# segment, 376 to 1,001 points per strand) comes back with one point per target point, each within
# fit + deviation of its target point; strands 0, 1 and 3, fitted exactly by 15 segments (see
# above), within 1e-6 L (float rounding of the .hair: ~3e-8 L). --points-per-segment 4 gives
# 15 x 4 + 1 = 61 points per strand instead.
run invert "$work/targets.json" -o "$work/dense" --points-per-segment 25 -q
expect_rc "exact targets written with 25 points per segment" 0
run invert "$work/dense/equilibrium.hair" -o "$work/resampled" --segments 15 -q
expect_rc "invert the dense .hair target" 0
run invert "$work/dense/equilibrium.hair" -o "$work/per_segment" --segments 15 -q \
  --points-per-segment 4
expect_rc "invert the dense .hair target, --points-per-segment 4" 0
"$PYTHON" - "$work/dense/equilibrium.hair" "$work/resampled" "$work/per_segment" <<'PY' \
  && ok || fail "equilibrium.hair at the target's sampling"
import json, struct, sys
def read_hair(path):  # docs/file-formats.md: header 128 bytes, segments array when flag 0x1
    data = open(path, "rb").read()
    assert data[:4] == b"HAIR"
    n, points, flags, default_segments = struct.unpack("<IIII", data[4:20])
    offset = 128
    counts = [default_segments] * n
    if flags & 1:
        counts = list(struct.unpack("<%dH" % n, data[offset:offset + 2 * n]))
        offset += 2 * n
    assert flags & 2 and sum(c + 1 for c in counts) == points, (flags, points)
    xyz = struct.unpack("<%df" % (3 * points), data[offset:offset + 12 * points])
    strands, k = [], 0
    for c in counts:
        strands.append([xyz[3 * j:3 * j + 3] for j in range(k, k + c + 1)])
        k += c + 1
    return strands
target = read_hair(sys.argv[1])
out = read_hair(sys.argv[2] + "/equilibrium.hair")
summary = json.load(open(sys.argv[2] + "/summary.json"))["strand_results"]
assert [len(s) for s in target] == [15 * 25 + 1, 15 * 25 + 1, 20 * 25 + 1, 15 * 25 + 1,
                                    40 * 25 + 1], [len(s) for s in target]
assert [len(s) for s in out] == [len(s) for s in target], [len(s) for s in out]
for k, (a, b, r) in enumerate(zip(target, out, summary)):
    worst = max(sum((x - y) ** 2 for x, y in zip(p, q)) ** 0.5 for p, q in zip(a, b))
    bound = r["fit_max_distance"] + r["deviation"] + 1e-6 * r["length"]
    if k in (0, 1, 3):
        bound = 1e-6 * r["length"]
    assert worst <= bound, (k, worst, bound, r["length"])
per_segment = read_hair(sys.argv[3] + "/equilibrium.hair")
assert [len(s) for s in per_segment] == [61] * 5, [len(s) for s in per_segment]
PY

# Bad inputs: one line naming the file (and strand and point), nothing written.
bad() {  # bad WHAT SUBSTRING ARGS...
  local what=$1 substring=$2
  shift 2
  rm -rf "$work/none"
  run invert "$@" -o "$work/none"
  expect_rc "$what" 1
  expect_one_error_line "$what" "$substring"
  [ ! -e "$work/none" ] && ok || fail "$what: wrote $work/none"
}
bad "missing file" "missing.obj" "$work/missing.obj"
printf 'v 0 0 0\nv 0 0 -0.1\nv 0 0 -0.1\nl 1 2 3\n' >"$work/repeat.obj"
bad "repeated point (.obj)" "repeat.obj: strand 0" "$work/repeat.obj"
grep -q "point 2" "$work/stderr" && ok || fail "repeated point: $(cat "$work/stderr")"
printf 'v 0 0 0\nv 0 0 -0.1\nv 0 0 -0.2\nl 1 2\nl 3\n' >"$work/short.obj"
bad "1-point strand (.obj)" "short.obj" "$work/short.obj"
printf '#usda 1.0\n(\n    metersPerUnit = 1\n    upAxis = "Z"\n)\n\ndef BasisCurves "c"\n{\n    uniform token type = "linear"\n    int[] curveVertexCounts = [3]\n    point3f[] points = [(0, 0, 0), (0, 0, -0.1), (nan, 0, -0.2)]\n}\n' >"$work/nan.usda"
bad "NaN point (.usda)" "nan.usda" "$work/nan.usda"
head -c 30 "$work/t.data" >"$work/truncated.data"
bad "truncated .data" "truncated.data" "$work/truncated.data"
bad ".usda with --up" "--ignore-usda-metadata" "$work/t.usda" --up y
bad "bad --units-per-metre" "--units-per-metre" "$work/t.obj" --units-per-metre 0

# --------------------------------------------------------------------------------------------
if [ "$failures" -ne 0 ]; then
  echo "cli_invert_formats_test: $failures of $((checks + failures)) checks FAILED" >&2
  exit 1
fi
echo "cli_invert_formats_test: all $checks checks passed"
