#!/usr/bin/env bash
# The command-line contract of `ringlet solve` (docs/scene-format.md): the examples solve and
# write every documented key, --points-per-segment, --force and --quiet behave, existing files
# are never overwritten silently, and every bad scene gives exit code 1, exactly one line on
# stderr naming the field, and no file at all (neither output nor temporary).
#
# Needs RINGLET (the built binary) and EXAMPLES (the examples/ directory); run by ctest as
# `cli_contract`. Exits non-zero if any check failed, after printing what failed.
set -u

: "${RINGLET:?set RINGLET to the ringlet binary}"
: "${EXAMPLES:?set EXAMPLES to the examples directory}"
PYTHON=/usr/bin/python3

work=$(mktemp -d "${TMPDIR:-/tmp}/ringlet_cli_test.XXXXXX") || exit 1
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/out" "$work/scenes" "$work/bad_out"

source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"  # checks, fail, ok, run, expect_*

# run ARGS...: runs the binary from here (these tests pass paths relative to the working
# directory); sets $rc and leaves stdout and stderr in $work/stdout, $work/stderr.
run() {
  "$RINGLET" "$@" >"$work/stdout" 2>"$work/stderr"
  rc=$?
}

expect_empty_dir() {  # expect_empty_dir WHAT DIR
  if [ -z "$(ls -A "$2")" ]; then ok; else
    fail "$1: files left in $2: $(ls -A "$2" | tr '\n' ' ')"
    rm -rf "${2:?}"/* "${2:?}"/.[!.]*
  fi
}

# Checks a result file: the documented keys, n k + 1 points, n curvature triples, summary counts
# consistent with the strands, and (with EXPECT=solved) every strand converged and stable.
check_result() {  # check_result WHAT FILE POINTS_PER_SEGMENT EXPECT(solved|any) [STRANDS]
  if "$PYTHON" - "$2" "$3" "$4" "${5:-0}" <<'EOF' >"$work/check" 2>&1; then ok; else
import json, sys
path, k, expect, want_strands = sys.argv[1], int(sys.argv[2]), sys.argv[3], int(sys.argv[4])
d = json.load(open(path))
errors = []
for key in ("strands", "summary", "units"):
    if key not in d:
        errors.append("missing top-level key " + key)
strands = d.get("strands", [])
if want_strands and len(strands) != want_strands:
    errors.append("%d strands, expected %d" % (len(strands), want_strands))
keys = ("points", "curvatures", "segment_lengths", "energy", "gradient_norm", "residual",
        "iterations", "evaluations", "termination", "stable", "min_hessian_eigenvalue",
        "stability_restarts", "message")
for i, s in enumerate(strands):
    missing = [key for key in keys if key not in s]
    if missing:
        errors.append("strands[%d] lacks %s" % (i, ", ".join(missing)))
        continue
    n = len(s["segment_lengths"])
    if len(s["points"]) != n * k + 1:
        errors.append("strands[%d]: %d points, expected n k + 1 = %d" % (i, len(s["points"]), n * k + 1))
    if len(s["curvatures"]) != n or any(len(c) != 3 for c in s["curvatures"]):
        errors.append("strands[%d]: curvatures are not n = %d triples" % (i, n))
    if any(len(p) != 3 for p in s["points"]):
        errors.append("strands[%d]: a point is not a triple" % i)
    for key in ("elastic", "gravity", "total"):
        if key not in s["energy"]:
            errors.append("strands[%d].energy lacks %s" % (i, key))
    if s["termination"] not in ("converged", "max_iterations", "line_search_failed", "non_finite"):
        errors.append("strands[%d]: unknown termination %r" % (i, s["termination"]))
    if expect == "solved" and (s["termination"] != "converged" or s["stable"] is not True):
        errors.append("strands[%d]: %s, stable=%s: %s" % (i, s["termination"], s["stable"], s["message"]))
summary = d.get("summary", {})
for key in ("strands", "converged", "stable", "seconds"):
    if key not in summary:
        errors.append("summary lacks " + key)
if summary.get("strands") != len(strands):
    errors.append("summary.strands = %r, file has %d" % (summary.get("strands"), len(strands)))
if summary.get("converged") != sum(s.get("termination") == "converged" for s in strands):
    errors.append("summary.converged does not count the converged strands")
if summary.get("stable") != sum(s.get("stable") is True for s in strands):
    errors.append("summary.stable does not count the stable strands")
if errors:
    print("; ".join(errors))
    sys.exit(1)
EOF
    fail "$1: $(cat "$work/check")"
  fi
}

# --------------------------------------------------------------------------------------------
# The examples solve, converge and are stable; the summary is on stdout, nothing on stderr.
for name in horizontal_10cm vertical_curly strands; do
  out="$work/out/$name.json"
  run solve "$EXAMPLES/$name.json" -o "$out"
  expect_rc "solve $name" 0
  [ -s "$work/stderr" ] && fail "solve $name: unexpected stderr: $(cat "$work/stderr")" || ok
  grep -q '^solved [0-9]* strands\{0,1\}: ' "$work/stdout" && ok ||
    fail "solve $name: no total line on stdout: $(cat "$work/stdout")"
  grep -q '^strand 0: converged, stable' "$work/stdout" && ok ||
    fail "solve $name: no line for strand 0 on stdout: $(cat "$work/stdout")"
  [ -f "$out" ] && check_result "solve $name" "$out" 1 solved || fail "solve $name: no output"
done
check_result "strands.json has several strands" "$work/out/strands.json" 1 solved 5
check_result "horizontal_10cm.json has one strand" "$work/out/horizontal_10cm.json" 1 solved 1

# --points-per-segment k gives n k + 1 points.
for k in 1 4; do
  run solve "$EXAMPLES/vertical_curly.json" -o "$work/out/curly_k$k.json" --points-per-segment "$k"
  expect_rc "--points-per-segment $k" 0
  check_result "--points-per-segment $k" "$work/out/curly_k$k.json" "$k" solved
done

# --check: the Kirchhoff certificate passes at the default tolerance (1e-6) and fails loudly,
# with exit 2 and one error line naming kirchhoff_residual, at an impossible one (1e-15: the
# solver stops at a residual of ~1e-10); the result is written either way.
run solve "$EXAMPLES/strands.json" -o "$work/out/checked.json" --check
expect_rc "--check" 0
grep -q '"kirchhoff_residual"' "$work/out/checked.json" && ok || fail "--check: no kirchhoff_residual key"
run solve "$EXAMPLES/strands.json" -o "$work/out/check_fails.json" --check --check-tolerance 1e-15 --quiet
expect_rc "--check above tolerance" 2
expect_one_error_line "--check above tolerance" "kirchhoff_residual above"
[ -f "$work/out/check_fails.json" ] && ok || fail "--check above tolerance: result not written"
run solve "$EXAMPLES/strands.json" -o "$work/out/check_bad_tol.json" --check --check-tolerance -1
expect_rc "--check-tolerance -1" 1
[ -f "$work/out/check_bad_tol.json" ] && fail "--check-tolerance -1 wrote a file" || ok

# --quiet prints nothing on success.
run solve "$EXAMPLES/horizontal_10cm.json" -o "$work/out/quiet.json" --quiet
expect_rc "--quiet" 0
[ -s "$work/stdout" ] || [ -s "$work/stderr" ] && fail "--quiet printed: $(cat "$work/stdout" "$work/stderr")" || ok

# An existing output is refused and untouched without --force, replaced with it.
existing="$work/out/existing.json"
echo "precious" >"$existing"
run solve "$EXAMPLES/horizontal_10cm.json" -o "$existing"
expect_rc "existing output without --force" 1
expect_one_error_line "existing output without --force" "already exists"
[ "$(cat "$existing")" = "precious" ] && ok || fail "existing output was modified without --force"
run solve "$EXAMPLES/horizontal_10cm.json" -o "$existing" --force
expect_rc "existing output with --force" 0
check_result "existing output with --force" "$existing" 1 solved 1

# The output may not be the scene itself, even with --force.
cp "$EXAMPLES/horizontal_10cm.json" "$work/scenes/self.json"
for force in "" "--force"; do
  run solve "$work/scenes/self.json" -o "$work/scenes/self.json" $force
  expect_rc "output = input $force" 1
  expect_one_error_line "output = input $force" "scene file"
  cmp -s "$EXAMPLES/horizontal_10cm.json" "$work/scenes/self.json" && ok ||
    fail "output = input $force: the scene was modified"
done

# A strand that does not converge: exit 2, results still written, the summary says so.
cat >"$work/scenes/budget.json" <<'EOF'
{"strands": [{"length": 0.3, "root": {"position": [0, 0, 0], "tangent": [1, 0, 0], "normal": [0, 0, 1]}}],
 "solver": {"max_iterations": 1}}
EOF
run solve "$work/scenes/budget.json" -o "$work/out/budget.json"
expect_rc "non-converged strand" 2
check_result "non-converged strand" "$work/out/budget.json" 1 any 1
grep -q '"termination": "max_iterations"' "$work/out/budget.json" && ok ||
  fail "non-converged strand: termination is not max_iterations"
grep -q '^solved 1 strand: 0 converged' "$work/stdout" && ok ||
  fail "non-converged strand: total line does not say so: $(cat "$work/stdout")"

# A write that fails (missing directory) is exit 1 and leaves nothing.
run solve "$EXAMPLES/horizontal_10cm.json" -o "$work/bad_out/missing/out.json"
expect_rc "output in a missing directory" 1
expect_one_error_line "output in a missing directory" "missing/out.json"
expect_empty_dir "output in a missing directory" "$work/bad_out"

# --------------------------------------------------------------------------------------------
# Usage.
run --version
expect_rc "--version" 0
grep -q '^ringlet [0-9]' "$work/stdout" && ok || fail "--version printed: $(cat "$work/stdout")"
run --help
expect_rc "--help" 0
grep -q 'solve' "$work/stdout" && ok || fail "--help does not list solve"
run solve --help
expect_rc "solve --help" 0
for option in --output --points-per-segment --force --quiet; do
  grep -q -- "$option" "$work/stdout" && ok || fail "solve --help does not mention $option"
done

run
expect_rc "no command" 1
expect_one_error_line "no command" "subcommand"
run frobnicate
expect_rc "unknown command" 1
expect_one_error_line "unknown command" "frobnicate"
run solve "$EXAMPLES/horizontal_10cm.json"
expect_rc "missing --output" 1
expect_one_error_line "missing --output" "--output"
for k in 0 -1 1.5 x; do
  run solve "$EXAMPLES/horizontal_10cm.json" -o "$work/bad_out/k.json" --points-per-segment "$k"
  expect_rc "--points-per-segment $k" 1
  expect_one_error_line "--points-per-segment $k" "--points-per-segment"
  expect_empty_dir "--points-per-segment $k" "$work/bad_out"
done

# --------------------------------------------------------------------------------------------
# Bad scenes: exit 1, one line on stderr naming the field, nothing written.

# bad NAME FIELD < scene: writes the scene from stdin and checks the contract on it.
bad() {
  local name=$1 field=$2 scene="$work/scenes/$1.json"
  cat >"$scene"
  run solve "$scene" -o "$work/bad_out/$name.json"
  expect_rc "bad scene $name" 1
  expect_one_error_line "bad scene $name" "$field"
  [ -s "$work/stdout" ] && fail "bad scene $name: printed on stdout: $(cat "$work/stdout")" || ok
  expect_empty_dir "bad scene $name" "$work/bad_out"
}

ROOT='"root": {"position": [0, 0, 0], "tangent": [1, 0, 0], "normal": [0, 0, 1]}'

bad missing_length 'strands[0].length' <<EOF
{"strands": [{$ROOT}]}
EOF
bad unknown_field 'strands[0].lenght' <<EOF
{"strands": [{"lenght": 0.1, "length": 0.1, $ROOT}]}
EOF
bad unknown_top_level_field 'gravty' <<EOF
{"gravty": [0, 0, -9.81], "strands": [{"length": 0.1, $ROOT}]}
EOF
bad wrong_type 'strands[0].length' <<EOF
{"strands": [{"length": "10 cm", $ROOT}]}
EOF
bad non_finite_length 'strands[0].length' <<EOF
{"strands": [{"length": 1e999, $ROOT}]}
EOF
bad zero_length 'strands[0].length' <<EOF
{"strands": [{"length": 0, $ROOT}]}
EOF
bad negative_radius 'strands[1].radius' <<EOF
{"strands": [{"length": 0.1, $ROOT}, {"length": 0.1, "radius": -1, $ROOT}]}
EOF
bad zero_modulus 'strands[0].young_modulus' <<EOF
{"strands": [{"length": 0.1, "young_modulus": 0, $ROOT}]}
EOF
bad eccentricity_one 'strands[0].eccentricity' <<EOF
{"strands": [{"length": 0.1, "eccentricity": 1, $ROOT}]}
EOF
bad ellipticity_below_one 'strands[0].ellipticity' <<EOF
{"strands": [{"length": 0.1, "ellipticity": 0.8, $ROOT}]}
EOF
bad eccentricity_and_ellipticity 'strands[0].ellipticity' <<EOF
{"strands": [{"length": 0.1, "eccentricity": 0.3, "ellipticity": 1.2, $ROOT}]}
EOF
bad zero_tangent 'strands[0].root.tangent' <<'EOF'
{"strands": [{"length": 0.1, "root": {"position": [0, 0, 0], "tangent": [0, 0, 0], "normal": [0, 0, 1]}}]}
EOF
bad parallel_normal 'strands[0].root.normal' <<'EOF'
{"strands": [{"length": 0.1, "root": {"position": [0, 0, 0], "tangent": [0, 0, -1], "normal": [0, 0, 2]}}]}
EOF
bad missing_root 'strands[0].root' <<'EOF'
{"strands": [{"length": 0.1}]}
EOF
bad zero_segments 'strands[0].segments' <<EOF
{"strands": [{"length": 0.1, "segments": 0, $ROOT}]}
EOF
bad too_many_segments 'strands[0].segments' <<EOF
{"strands": [{"length": 0.1, "segments": 100000000, $ROOT}]}
EOF
bad fractional_segments 'strands[0].segments' <<EOF
{"strands": [{"length": 0.1, "segments": 2.5, $ROOT}]}
EOF
bad empty_strands 'strands' <<'EOF'
{"strands": []}
EOF
bad segment_lengths_sum 'strands[0].segment_lengths' <<EOF
{"strands": [{"length": 0.1, "segment_lengths": [0.05, 0.04], $ROOT}]}
EOF
bad segment_lengths_and_grading 'strands[0].grading' <<EOF
{"strands": [{"length": 0.1, "segment_lengths": [0.05, 0.05], "grading": 2, $ROOT}]}
EOF
bad bad_method 'solver.method' <<EOF
{"strands": [{"length": 0.1, $ROOT}], "solver": {"method": "gradient_descent"}}
EOF
bad duplicate_field 'strands[0].length' <<EOF
{"strands": [{"length": 0.1, "length": 0.2, $ROOT}]}
EOF
bad invalid_json 'line 3, column' <<'EOF'
{
  "strands": [
    {"length": 0.1,, }
  ]
}
EOF
bad empty_file 'line 1, column 1' </dev/null

# An unreadable scene (missing file, directory) is the same: one line, exit 1, nothing written.
run solve "$work/scenes/does_not_exist.json" -o "$work/bad_out/x.json"
expect_rc "missing scene file" 1
expect_one_error_line "missing scene file" "does_not_exist.json"
expect_empty_dir "missing scene file" "$work/bad_out"
run solve "$work/scenes" -o "$work/bad_out/x.json"
expect_rc "scene is a directory" 1
expect_one_error_line "scene is a directory" "directory"
expect_empty_dir "scene is a directory" "$work/bad_out"

# --------------------------------------------------------------------------------------------
# `ringlet style`: operations in order, groom outputs plus grow steps; bad operations rejected.
mkdir -p "$work/style_bad"
cat >"$work/style.json" <<EOF
{
  "body": "$EXAMPLES/bodies/mannequin.json",
  "scalp": {"head": {"centre": [0, 0, 0], "up": [0, 0, 1], "front": [0, 1, 0]}, "radius": 0.1},
  "masters": {"count": 12, "seed": 1, "segments": 10, "grading": "auto"},
  "hair": {"origin": "caucasian", "curl": "wavy", "length": 0.25, "seed": 1},
  "wisps": {"strands_per_wisp": 3, "points_per_strand": 12}
}
EOF
run style "$work/style.json" --wet --cut-z -0.15 --settle --dry --grow 0.01 --steps 2 \
  -o "$work/style_out"
expect_rc "style wet/cut/dry/grow" 0
for f in strands.hair strands.usda strands.obj masters.json step_001.hair step_002.hair grow.usda; do
  if [ -s "$work/style_out/$f" ]; then ok; else fail "style: $f not written"; fi
done
if "$PYTHON" -c '
import json, sys
ops = [o["name"] for o in json.load(open(sys.argv[1]))["style"]["operations"]]
sys.exit(0 if ops == ["wet", "cut", "dry", "grow"] else 1)
' "$work/style_out/masters.json"; then ok; else
  fail "style: operations not reported in command-line order"
fi
# Brush strokes as data (docs/styling.md, "Brushes"): a file's mirrored sculpt stroke behind the
# head and a puff at the crown replay bit for bit, change the hair, and are reported in order.
"$PYTHON" - "$work/style.json" "$work/sculpt.json" <<'EOF'
import json, sys
doc = json.load(open(sys.argv[1]))
doc["operations"] = [
    {"sculpt": {"from": [0.02, -0.12, -0.05], "to": [0.05, -0.13, -0.04], "radius": 0.08,
                "mirror": True}},
    {"puff": {"angle": 0.3, "centre": [0, 0, 0.1], "radius": 0.08, "falloff": "linear"}}]
json.dump(doc, open(sys.argv[2], "w"))
EOF
run style "$work/sculpt.json" -o "$work/sculpt_a"
expect_rc "style sculpt/puff" 0
run style "$work/sculpt.json" -o "$work/sculpt_b"
expect_rc "style sculpt/puff again" 0
cmp -s "$work/sculpt_a/strands.hair" "$work/sculpt_b/strands.hair" && ok ||
  fail "style sculpt/puff: two runs differ"
run groom "$work/style.json" -o "$work/sculpt_plain"
expect_rc "groom before sculpt" 0
if cmp -s "$work/sculpt_a/strands.hair" "$work/sculpt_plain/strands.hair"; then
  fail "style sculpt/puff: the strands equal the unstyled groom's"
else ok; fi
if "$PYTHON" -c '
import json, sys
ops = json.load(open(sys.argv[1]))["style"]["operations"]
names = [o["name"] for o in ops]
sys.exit(0 if names == ["sculpt", "puff"] and all(o["strands"] > 0 for o in ops) else 1)
' "$work/sculpt_a/masters.json"; then ok; else
  fail "style sculpt/puff: operations not reported, or one changed no master: $(cat "$work/sculpt_a/masters.json" | head -c 600)"
fi
sed 's/"radius": 0.08, "mirror"/"radius": 0, "mirror"/' "$work/sculpt.json" >"$work/sculpt_bad.json"
run style "$work/sculpt_bad.json" -o "$work/style_bad/x"
expect_rc "style sculpt radius 0" 1
expect_one_error_line "style sculpt radius 0" "operations[0].sculpt.radius: expected a finite number in (0, 10]"
expect_empty_dir "style sculpt radius 0" "$work/style_bad"
# The length, clump, frizz and curl brushes: after a bob cut (clip records), a mirrored shortening
# at the back, a clump at the crown, a frizz at the side and a curl brush replay bit for bit,
# change the hair, and are reported; a bad factor is one line naming the field, nothing written.
"$PYTHON" - "$work/style.json" "$work/brushes.json" <<'EOF'
import json, sys
doc = json.load(open(sys.argv[1]))
doc["operations"] = [
    {"cut": {"sphere": {"centre": [0, 0, 0], "radius": 0.16}}},
    {"length": {"factor": 0.7, "centre": [0.03, -0.1, -0.05], "radius": 0.08, "mirror": True}},
    {"clump": {"factor": 0.5, "centre": [0, 0, 0.1], "radius": 0.08, "falloff": "linear"}},
    {"frizz": {"amplitude": 0.004, "centre": [0.1, 0, 0], "radius": 0.1, "strength": 0.5}},
    {"curl": {"radius": 0.01, "pitch": 0.03,
              "brush": {"centre": [0, 0, 0.1], "radius": 0.08, "mirror": True}}}]
json.dump(doc, open(sys.argv[2], "w"))
EOF
run style "$work/brushes.json" -o "$work/brushes_a" --formats hair,json
expect_rc "style length/clump/frizz" 0
run style "$work/brushes.json" -o "$work/brushes_b" --formats hair,json
expect_rc "style length/clump/frizz again" 0
cmp -s "$work/brushes_a/strands.hair" "$work/brushes_b/strands.hair" && ok ||
  fail "style length/clump/frizz: two runs differ"
if cmp -s "$work/brushes_a/strands.hair" "$work/sculpt_plain/strands.hair"; then
  fail "style length/clump/frizz: the strands equal the unstyled groom's"
else ok; fi
if "$PYTHON" -c '
import json, sys
ops = json.load(open(sys.argv[1]))["style"]["operations"]
names = [o["name"] for o in ops]
ok = names == ["cut", "length", "clump", "frizz", "curl"] and all(o["strands"] > 0 for o in ops[1:])
sys.exit(0 if ok and "clipped strands rescaled" in ops[1]["message"] else 1)
' "$work/brushes_a/masters.json"; then ok; else
  fail "style length/clump/frizz: operations not reported, or one changed no master: $(head -c 900 "$work/brushes_a/masters.json")"
fi
sed 's/"factor": 0.7/"factor": 0/' "$work/brushes.json" >"$work/brushes_bad.json"
run style "$work/brushes_bad.json" -o "$work/style_bad/x"
expect_rc "style length factor 0" 1
expect_one_error_line "style length factor 0" "operations[1].length.factor: expected a finite number in (0, 10]"
expect_empty_dir "style length factor 0" "$work/style_bad"
# The output options of `groom` (one code, cli/outputs.h): --formats chooses the strand files and
# with them the grow files (steps as .hair with "hair", grow.usda with "usda");
# --hair-units-per-metre scales every .hair coordinate (read back here from the file's layout,
# docs/file-formats.md: 128-byte header, optional uint16 segment counts, float32 points).
run style "$work/style.json" --cut-z -0.15 --grow 0.01 --steps 2 --formats hair,json \
  --hair-units-per-metre 100 -o "$work/style_cm"
expect_rc "style --formats hair,json --hair-units-per-metre 100" 0
listed=$(cd "$work/style_cm" && ls | tr '\n' ' ')
[ "$listed" = "masters.json step_001.hair step_002.hair strands.hair " ] && ok ||
  fail "style --formats hair,json wrote: $listed"
run style "$work/style.json" --cut-z -0.15 --grow 0.01 --steps 2 --formats hair,usda \
  -o "$work/style_m"
expect_rc "style --formats hair,usda" 0
listed=$(cd "$work/style_m" && ls | tr '\n' ' ')
[ "$listed" = "grow.usda step_001.hair step_002.hair strands.hair strands.usda " ] && ok ||
  fail "style --formats hair,usda wrote: $listed"
if "$PYTHON" - "$work/style_m" "$work/style_cm" <<'EOF' >"$work/check" 2>&1; then ok; else
import struct, sys
def points(path):
    data = open(path, "rb").read()
    strands, count, bits = struct.unpack("<III", data[4:16])
    at = 128 + (2 * strands if bits & 1 else 0)
    return struct.unpack("<%df" % (3 * count), data[at:at + 12 * count])
for name in ["strands.hair", "step_001.hair", "step_002.hair"]:
    m, cm = points(sys.argv[1] + "/" + name), points(sys.argv[2] + "/" + name)
    assert len(m) == len(cm) > 0, name
    # float32 rounding of x and of 100 x: relative 2^-23 each.
    worst = max(abs(c - 100 * x) for x, c in zip(m, cm))
    assert worst <= 1e-5 * max(abs(c) for c in cm), (name, worst)
EOF
  fail "style --hair-units-per-metre 100: coordinates not 100 x metres: $(cat "$work/check")"
fi
run style "$work/style.json" --wet --formats hair,fbx -o "$work/style_bad/x"
expect_rc "style unknown --formats" 1
expect_one_error_line "style unknown --formats" '--formats: unknown format "fbx"'
run style "$work/style.json" --wet --spp 4 -o "$work/style_bad/x"
expect_rc "style --spp without --render" 1
expect_one_error_line "style --spp without --render" "--spp: only with --render"
run style "$work/style.json" --wet --hair-units-per-metre 0 -o "$work/style_bad/x"
expect_rc "style --hair-units-per-metre 0" 1
expect_one_error_line "style --hair-units-per-metre 0" "--hair-units-per-metre"
run style "$work/style.json" --curl 0.01 -o "$work/style_bad/x"
expect_rc "style bad --curl" 1
expect_one_error_line "style bad --curl" "--curl"
run style "$work/style.json" --curl=-0.01,0.02 -o "$work/style_bad/x"
expect_rc "style negative curl radius" 1
expect_one_error_line "style negative curl radius" "curl.radius"
run style "$work/style.json" --dry -o "$work/style_bad/x"
expect_rc "style dry hair" 1
expect_one_error_line "style dry hair" "not wet"
run style "$work/style.json" --grow 0 -o "$work/style_bad/x"
expect_rc "style grow 0" 1
expect_one_error_line "style grow 0" "grow.step"
run style "$work/style.json" -o "$work/style_bad/x"
expect_rc "style without operation" 1
expect_one_error_line "style without operation" "operation"
expect_empty_dir "style bad input" "$work/style_bad"

# New cut and selection flags, in command-line order.
run style "$work/style.json" --curl 0.01,0.03 --curl-polar 0,0.8 --cut-sphere 0,0,0,0.25 \
  --settle --cut-length 0.2 --cut-plane 0,-1,0,0.05 -o "$work/style_flags"
expect_rc "style new flags" 0
if "$PYTHON" -c '
import json, sys
d = json.load(open(sys.argv[1]))
ops = d["style"]["operations"]
names = [(o["name"], o["from"]) for o in ops]
want = [("curl", "--curl --curl-polar"), ("cut", "--cut-sphere"), ("cut", "--cut-length"),
        ("cut", "--cut-plane")]
# The curl acted on the crown only (some, not all, of the 12 masters); no master is longer than
# the length cut (exact: a length edit).
lengths = [sum(s["segment_lengths"]) for s in d["strands"]]
ok = names == want and 0 < ops[0]["strands"] < 12 and max(lengths) <= 0.2 + 1e-12
sys.exit(0 if ok else 1)
' "$work/style_flags/masters.json"; then ok; else
  fail "style new flags: operations, origins or lengths wrong in masters.json"
fi
# A hairstyle file with an "operations" list: applied first, then the command line's.
"$PYTHON" -c '
import json, sys
d = json.load(open(sys.argv[1]))
d["operations"] = [{"wet": {}}, {"cut": {"z": -0.15, "settle": True}},
                   {"grow": {"step": 0.01, "steps": 2}}]
json.dump(d, open(sys.argv[2], "w"))
' "$work/style.json" "$work/style_ops.json"
run style "$work/style_ops.json" --dry --grow 0.005 --steps 1 -o "$work/style_file"
expect_rc "style file operations" 0
for f in strands.hair strands.usda strands.obj masters.json step_001.hair step_002.hair \
  step_003.hair grow.usda; do
  if [ -s "$work/style_file/$f" ]; then ok; else fail "style file operations: $f not written"; fi
done
if "$PYTHON" -c '
import json, sys
d = json.load(open(sys.argv[1]))
names = [(o["name"], o["from"]) for o in d["style"]["operations"]]
want = [("wet", "operations[0]"), ("cut", "operations[1]"), ("grow", "operations[2]"),
        ("dry", "--dry"), ("grow", "--grow")]
sys.exit(0 if names == want and d["style"]["wet"] is False else 1)
' "$work/style_file/masters.json"; then ok; else
  fail "style file operations: not applied file first, then command line"
fi
# The file's list alone is enough; groom reads the same file and says it did not apply it.
run style "$work/style_ops.json" -o "$work/style_file_only"
expect_rc "style file operations only" 0
run groom "$work/style_ops.json" -o "$work/groom_ops"
expect_rc "groom file with operations" 0
if grep -q "3 styling operations were not applied" "$work/stdout"; then ok; else
  fail "groom file with operations: no note in the summary: $(cat "$work/stdout")"
fi
# Bad values of the new flags and of the file's operations: one line naming the flag or the
# field, exit code 1, nothing written.
style_bad() {  # style_bad WHAT SUBSTRING FILE ARGS...
  local what=$1 substring=$2 file=$3
  shift 3
  run style "$file" "$@" -o "$work/style_bad/x"
  expect_rc "$what" 1
  expect_one_error_line "$what" "$substring"
}
style_bad "style --cut-sphere 3 values" "--cut-sphere: expected X,Y,Z,R" "$work/style.json" \
  --cut-sphere 0,0,0
style_bad "style --cut-sphere r < 0" "--cut-sphere: cut.radius" "$work/style.json" \
  --cut-sphere 0,0,0,-0.1
style_bad "style --cut-sphere nan" "--cut-sphere: cut.centre" "$work/style.json" \
  --cut-sphere nan,0,0,0.2
style_bad "style --cut-length 0" "--cut-length: cut.length" "$work/style.json" --cut-length 0
style_bad "style --cut-length text" "--cut-length" "$work/style.json" --cut-length short
style_bad "style --cut-plane zero normal" "--cut-plane: cut.normal" "$work/style.json" \
  --cut-plane 0,0,0,0.1
style_bad "style --cut-plane 3 values" "--cut-plane: expected NX,NY,NZ,D" "$work/style.json" \
  --cut-plane 0,0,1
style_bad "style --curl-polar first" "--curl-polar: expected after a --curl" \
  "$work/style.json" --curl-polar 0,1 --curl 0.01,0.02
style_bad "style --curl-polar reversed" "selection.polar_angle" "$work/style.json" \
  --curl 0.01,0.02 --curl-polar 1,0.5
style_bad "style --curl-height text" "--curl-height: expected MIN,MAX" "$work/style.json" \
  --curl 0.01,0.02 --curl-height low,high
style_bad "style --curl-masters negative" "--curl-masters: expected master indices" \
  "$work/style.json" --curl 0.01,0.02 --curl-masters 1,-2
style_bad "style --curl-masters out of range" "selection.indices: 12 is not a master index" \
  "$work/style.json" --curl 0.01,0.02 --curl-masters 0,12
"$PYTHON" -c '
import json, sys
d = json.load(open(sys.argv[1]))
d["operations"] = [{"wet": {}}, {"cut": {"z": "low"}}]
json.dump(d, open(sys.argv[2], "w"))
' "$work/style.json" "$work/style_bad_ops.json"
style_bad "style bad file operation" \
  'operations[1].cut.z: expected a finite number (m), got "low"' "$work/style_bad_ops.json"
run groom "$work/style_bad_ops.json" -o "$work/style_bad/x"
expect_rc "groom bad file operation" 1
expect_one_error_line "groom bad file operation" "operations[1].cut.z"
"$PYTHON" -c '
import json, sys
d = json.load(open(sys.argv[1]))
d["operations"] = [{"dry": {}}]
json.dump(d, open(sys.argv[2], "w"))
' "$work/style.json" "$work/style_dry_ops.json"
style_bad "style file dry on dry hair" "operations[0]: dry: the hair is not wet" \
  "$work/style_dry_ops.json"
expect_empty_dir "style bad new flags" "$work/style_bad"

# --------------------------------------------------------------------------------------------
if [ "$failures" -ne 0 ]; then
  echo "cli_test: $failures of $((checks + failures)) checks FAILED" >&2
  exit 1
fi
echo "cli_test: all $checks checks passed"
