#!/usr/bin/env bash
# The command-line contract of `ringlet invert` (docs/inverse.md): the equilibria of a scene,
# inverted, hold (the summary's deviation <= 1e-6 L, the naive rest shapes sag), the written scene
# with per-strand rest_curvatures solves back to the same points (independent of invert's own
# verification: `ringlet solve` on rest_shapes.json), a .hair target is fitted and inverted, and
# every bad input gives exit code 1, exactly one line on stderr naming the file (and strand and
# point), and writes nothing.
#
# Needs RINGLET (the built binary) and EXAMPLES (the examples/ directory); run by ctest as
# `cli_invert`. Exits non-zero if any check failed, after printing what failed.
set -u

: "${RINGLET:?set RINGLET to the ringlet binary}"
: "${EXAMPLES:?set EXAMPLES to the examples directory}"
PYTHON=/usr/bin/python3

work=$(mktemp -d "${TMPDIR:-/tmp}/ringlet_cli_invert.XXXXXX") || exit 1
trap 'rm -rf "$work"' EXIT

source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"  # checks, fail, ok, run, expect_*

# Targets: the equilibria of the 5 example strands (exact piecewise helices).
run solve "$EXAMPLES/strands.json" -o "$work/targets.json"
expect_rc "solve the example strands" 0

run invert "$work/targets.json" -o "$work/out"
expect_rc "invert the equilibria" 0
for f in rest_shapes.json equilibrium.hair naive.hair summary.json; do
  [ -f "$work/out/$f" ] && ok || fail "invert did not write $f"
done
grep -q "inverted 5 strands" "$work/stdout" && ok || fail "summary line: $(cat "$work/stdout")"
"$PYTHON" - "$work/out/summary.json" <<'EOF' && ok || fail "summary.json values"
import json, sys
s = json.load(open(sys.argv[1]))
assert s["strands"] == 5 and s["unstable"] == 0 and s["unconverged"] == 0, s
assert s["max_deviation_per_length"] <= 1e-6, s["max_deviation_per_length"]
assert s["naive_max_deviation_per_length"] > 0.01, s["naive_max_deviation_per_length"]
EOF

# --no-naive skips the naive solve only: the same rest shapes and equilibria byte for byte, no
# naive.hair, no naive deviations in the summary (not zeros), and its "naive" is false.
run invert "$work/targets.json" -o "$work/no_naive" --no-naive
expect_rc "invert --no-naive" 0
[ ! -e "$work/no_naive/naive.hair" ] && ok || fail "--no-naive wrote naive.hair"
for f in rest_shapes.json equilibrium.hair; do
  cmp -s "$work/out/$f" "$work/no_naive/$f" && ok || fail "--no-naive changed $f"
done
grep -q "naive solve skipped" "$work/stdout" && ok || fail "--no-naive line: $(cat "$work/stdout")"
"$PYTHON" - "$work/out/summary.json" "$work/no_naive/summary.json" <<'EOF' && ok || fail "--no-naive summary"
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:])
assert a["naive"] is True and b["naive"] is False, (a["naive"], b["naive"])
assert "naive_max_deviation" not in b and "naive_max_deviation_per_length" not in b, b.keys()
assert all("naive_deviation" not in s for s in b["strand_results"])
assert [s["deviation"] for s in a["strand_results"]] == [s["deviation"] for s in b["strand_results"]]
EOF
# With --force over a directory that has an earlier naive.hair, that file goes (not left stale).
cp "$work/out/naive.hair" "$work/no_naive/naive.hair"
run invert "$work/targets.json" -o "$work/no_naive" --no-naive --force
expect_rc "invert --no-naive --force" 0
[ ! -e "$work/no_naive/naive.hair" ] && ok || fail "--no-naive --force left naive.hair"

# Independent check: `ringlet solve` from the written rest shapes reproduces the targets.
run solve "$work/out/rest_shapes.json" -o "$work/again.json"
expect_rc "solve rest_shapes.json" 0
"$PYTHON" - "$work/targets.json" "$work/again.json" <<'EOF' && ok || fail "rest shapes do not hold"
import json, math, sys
a = json.load(open(sys.argv[1]))["strands"]
b = json.load(open(sys.argv[2]))["strands"]
assert len(a) == len(b) == 5
for sa, sb in zip(a, b):
    assert "rest_curvatures" in sb
    L = sum(sa["segment_lengths"])
    d = max(math.dist(p, q) for p, q in zip(sa["points"], sb["points"]))
    assert d <= 1e-6 * L, d
EOF

# A .hair target: the naive equilibria (4 points per segment in the file), fitted with 15
# segments and inverted. The file has no root frame: the fit refines the root tangent with the
# curve (docs/inverse.md); its accuracy on every format is checked by cli_invert_formats_test.sh,
# here the inversion of the fitted curve (<= 1e-6 L) and the reported fit error's consistency
# with the per-strand values.
run invert "$work/out/naive.hair" -o "$work/hair" --segments 15
expect_rc "invert a .hair target" 0
"$PYTHON" - "$work/hair/summary.json" <<'EOF' && ok || fail "hair summary.json values"
import json, sys
s = json.load(open(sys.argv[1]))
assert s["strands"] == 5 and s["unstable"] == 0, s
per = [r["fit_max_distance"] / r["length"] for r in s["strand_results"]]
assert 0 < s["fit_max_distance_per_length"] == max(per), (s["fit_max_distance_per_length"], per)
assert all(r["segments"] == 15 for r in s["strand_results"])
assert s["max_deviation_per_length"] <= 1e-6, s["max_deviation_per_length"]
EOF

# Without --body no hairstyle is written (a hairstyle needs a body).
[ ! -e "$work/out/hairstyle.json" ] && [ ! -e "$work/out/explicit_masters.json" ] && ok ||
  fail "invert without --body wrote a hairstyle"

# The sag-free groom (docs/inverse.md, "The sag-free groom"): the masters of a small groom on the
# sphere mannequin, inverted with the body, are groomed again from OUT/hairstyle.json to the
# same centrelines (the groom's own masters.json against the original one, 1e-9 L; measured
# 5e-16 L: each solve starts at its target and stops there, 0 iterations), and `ringlet style`
# wets (the mean tip drops by 2.3 cm) and cuts that hairstyle. With masters.seed 1 every target
# is certified stable (seed 2 has one that is not without more contact: reported, exit code 2).
cat >"$work/small.json" <<EOF
{"body": "$EXAMPLES/bodies/mannequin.json",
 "masters": {"count": 12, "seed": 1, "segments": 10},
 "hair": {"origin": "caucasian", "curl": "wavy", "length": 0.2},
 "wisps": {"strands_per_wisp": 3, "points_per_strand": 8}}
EOF
run groom "$work/small.json" -o "$work/g" --formats json
expect_rc "groom the small hairstyle" 0
run invert "$work/g/masters.json" -o "$work/sagfree" --body "$EXAMPLES/bodies/mannequin.json" \
  --hair-type caucasian/wavy
expect_rc "invert the groom's masters with --body" 0
expect_files "invert --body outputs" "$work/sagfree" explicit_masters.json equilibrium.hair \
  hairstyle.json naive.hair rest_shapes.json summary.json
run groom "$work/sagfree/hairstyle.json" -o "$work/g2" --formats json
expect_rc "groom the sag-free hairstyle" 0
"$PYTHON" - "$work/g/masters.json" "$work/g2/masters.json" <<'EOF' && ok || fail "sag-free groom"
import json, math, sys
a = json.load(open(sys.argv[1]))["strands"]
b = json.load(open(sys.argv[2]))["strands"]
assert len(a) == len(b) == 12, (len(a), len(b))
worst = 0.0
for sa, sb in zip(a, b):
    assert "rest_curvatures" in sb and "rest_curvatures" not in sa
    assert sb["stable"] and sb["termination"] == "converged", sb["message"]
    L = sum(sa["segment_lengths"])
    assert len(sa["points"]) == len(sb["points"])
    worst = max(worst, max(math.dist(p, q) for p, q in zip(sa["points"], sb["points"])) / L)
print("sag-free groom: largest distance from the targets %.3g L" % worst)
assert worst <= 1e-9, worst
EOF
run style "$work/sagfree/hairstyle.json" -o "$work/wet" --formats json --wet
expect_rc "wet the sag-free hairstyle" 0
run style "$work/sagfree/hairstyle.json" -o "$work/cut" --formats json --cut-length 0.1
expect_rc "cut the sag-free hairstyle" 0
"$PYTHON" - "$work/g2/masters.json" "$work/wet/masters.json" "$work/cut/masters.json" <<'EOF' \
  && ok || fail "style on the sag-free hairstyle"
import json, sys
dry, wet, cut = (json.load(open(f))["strands"] for f in sys.argv[1:4])
mean_tip_z = lambda s: sum(x["points"][-1][2] for x in s) / len(s)
# Wet hair is 10x softer and heavier: the sag-free shape sags (by millimetres at least).
assert mean_tip_z(wet) < mean_tip_z(dry) - 1e-3, (mean_tip_z(wet), mean_tip_z(dry))
for d, c in zip(dry, cut):
    assert abs(sum(c["segment_lengths"]) - min(0.1, sum(d["segment_lengths"]))) < 1e-12
    n = len(c["segment_lengths"])
    assert n < len(d["segment_lengths"])
    # The kept segments keep their rest curvatures, the shortened one's included.
    assert c["rest_curvatures"] == d["rest_curvatures"][:n]
EOF

# Existing outputs are not overwritten without --force.
run invert "$work/targets.json" -o "$work/out"
expect_rc "existing outputs" 1
expect_one_error_line "existing outputs" "already exists"

# Bad inputs: one line, nothing written.
bad() {  # bad WHAT SUBSTRING ARGS...
  local what=$1 substring=$2
  shift 2
  rm -rf "$work/none"
  run invert "$@" -o "$work/none"
  expect_rc "$what" 1
  expect_one_error_line "$what" "$substring"
  [ ! -e "$work/none" ] && ok || fail "$what: wrote $work/none"
}
printf 'HAIR' >"$work/truncated.hair"
bad "truncated .hair" "truncated.hair: header" "$work/truncated.hair"
"$PYTHON" - "$work/repeat.hair" <<'EOF'
import struct, sys
# Yuksel .hair: one strand of 3 points, the third repeating the second.
points = [0, 0, 0, 0, 0, -0.1, 0, 0, -0.1]
header = b"HAIR" + struct.pack("<IIIIff3f", 1, 3, 0x2, 2, 1e-4, 1.0, 0, 0, 0)
header += b"\0" * (128 - len(header))
open(sys.argv[1], "wb").write(header + struct.pack("<9f", *points))
EOF
bad "repeated point" "strand 0, point 2: repeated point" "$work/repeat.hair"
echo '{"strands": [{"points": [[0,0,0],[0,0,-0.1]], "curvatures": [[1,0,0]], "segment_lengths": [0.1]}]}' \
  >"$work/off.json"
bad "points off the helix" "strands[0].points[1]: does not lie on the helix" "$work/off.json"
echo '{"strands": [{"points": [[0,0,0]], "curvatures": [], "segment_lengths": []}]}' >"$work/empty.json"
bad "no curvatures" "strands[0].curvatures" "$work/empty.json"
bad "unknown format" "unknown target format" "$work/targets.txt"
bad "bad --up" "--up" "$work/targets.json" --up x
bad "bad hair type" "--hair-type" "$work/targets.json" --hair-type martian
# The body loads while the targets are read and fitted: its error still comes first, alone, with
# a good target, a target that cannot be read, one whose fit fails and one of an unknown format;
# a bad target with a good body reports the target.
echo '{"spheres": [{"name": "head", "center": [0, 0, 0], "radius": -1}]}' >"$work/bad_body.json"
for target in "$work/targets.json" "$work/truncated.hair" "$work/repeat.hair" \
  "$work/targets.txt"; do
  bad "missing body, target $(basename "$target")" "nobody.json" "$target" --body "$work/nobody.json"
  bad "bad body, target $(basename "$target")" "bad_body.json" "$target" --body "$work/bad_body.json"
done
bad "truncated .hair with a body" "truncated.hair: header" "$work/truncated.hair" \
  --body "$EXAMPLES/bodies/mannequin.json"
bad "repeated point with a body" "strand 0, point 2: repeated point" "$work/repeat.hair" \
  --body "$EXAMPLES/bodies/mannequin.json"

# --------------------------------------------------------------------------------------------
if [ "$failures" -ne 0 ]; then
  echo "cli_invert_test: $failures of $((checks + failures)) checks FAILED" >&2
  exit 1
fi
echo "cli_invert_test: all $checks checks passed"
