#!/usr/bin/env bash
# The command-line contract of `ringlet convert IN OUT` (docs/file-formats.md): strands between
# .hair, .data, .usda and .obj through metres with z up; bad input gives exit code 1, exactly
# one error line and no output file. Expected bytes of the .data output are built here with
# Python's struct module from the layout (int32 strand count; per strand int32 vertex count and
# float32 x, y, z), independently of the writer.
#
# Needs RINGLET (the built binary); run by ctest as `cli_convert`.
set -u

: "${RINGLET:?set RINGLET to the ringlet binary}"
PYTHON=/usr/bin/python3
DATA=$(cd "$(dirname "${BASH_SOURCE[0]}")/data/strand_targets" && pwd)

work=$(mktemp -d "${TMPDIR:-/tmp}/ringlet_cli_convert.XXXXXX") || exit 1
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/out"

source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"  # checks, fail, ok, expect_*

run() {
  timeout 60 "$RINGLET" "$@" >"$work/stdout" 2>"$work/stderr"
  rc=$?
}

# bad WHAT SUBSTRING ARGS...: exit 1, one error line mentioning SUBSTRING, nothing new in out/.
bad() {
  local what=$1 substring=$2 before after
  shift 2
  before=$(ls -A "$work/out" | sort | tr '\n' ' ')
  run "$@"
  expect_rc "$what" 1
  expect_one_error_line "$what" "$substring"
  after=$(ls -A "$work/out" | sort | tr '\n' ' ')
  if [ "$before" = "$after" ]; then ok; else fail "$what: out/ was [$before], now [$after]"; fi
}

# --- HairSalon .data (y up) -> .usda -> .data (y up): the hair strands come back bit for bit.
run convert "$DATA/hairsalon_yup.data" "$work/out/a.usda" --up-axis y
expect_rc "data -> usda" 0
if grep -q "converted 2 strands, 5 points (1 m per input unit, y up), 2 empty strands skipped" \
  "$work/stdout"; then ok; else fail "data -> usda: summary: $(cat "$work/stdout")"; fi
if grep -q 'upAxis = "Z"' "$work/out/a.usda"; then ok; else fail "a.usda is not z up"; fi
run convert "$work/out/a.usda" "$work/out/b.data" --out-up-axis y
expect_rc "usda -> data" 0
$PYTHON - "$work/out/expected.data" <<'PY'
import struct, sys
# hairsalon_yup.data without its 1-vertex and 0-vertex strands (no hair at those roots).
b = struct.pack('<i', 2)
b += struct.pack('<i', 3) + struct.pack('<9f', 0.0, 1.7, 0.05, 0.0, 1.6, 0.06, 0.01, 1.5, 0.065)
b += struct.pack('<i', 2) + struct.pack('<6f', -0.02, 1.68, -0.04, -0.02, 1.58, -0.05)
open(sys.argv[1], 'wb').write(b)
PY
if cmp -s "$work/out/b.data" "$work/out/expected.data"; then ok; else
  fail "usda -> data: b.data differs from the expected bytes"
fi
rm -f "$work/out/expected.data"

# --- OBJ chains (y up, cm) -> .hair -> .obj equals OBJ -> .obj directly.
run convert "$DATA/segments_yup_cm.obj" "$work/out/c.hair" --up-axis y --units-per-metre 100
expect_rc "obj -> hair" 0
run convert "$work/out/c.hair" "$work/out/c.obj"
expect_rc "hair -> obj" 0
run convert "$DATA/segments_yup_cm.obj" "$work/out/d.obj" --up-axis y --units-per-metre 100 -q
expect_rc "obj -> obj" 0
if [ ! -s "$work/stdout" ]; then ok; else fail "-q printed: $(cat "$work/stdout")"; fi
if cmp -s "$work/out/c.obj" "$work/out/d.obj"; then ok; else fail "obj -> hair -> obj differs"; fi
# Two strands written as chains of 2-vertex `l` segments (the OBJ writer's default): as many
# segments as points minus one per strand.
vertices=$(grep -c '^v ' "$work/out/d.obj"); segments=$(grep -c '^l ' "$work/out/d.obj")
if [ "$segments" -eq $((vertices - 2)) ]; then ok; else fail "d.obj: expected 2 strands ($vertices points, $segments segments)"; fi

# --- Outputs are never replaced without --force, and only regular files with it.
cp "$work/out/d.obj" "$work/out/keep.obj"
bad "existing output" "already exists" convert "$DATA/polylines.obj" "$work/out/d.obj"
if cmp -s "$work/out/d.obj" "$work/out/keep.obj"; then ok; else fail "d.obj changed"; fi
run convert "$DATA/polylines.obj" "$work/out/d.obj" --force
expect_rc "--force" 0
if grep -c '^v ' "$work/out/d.obj" | grep -qx 5; then ok; else fail "--force: d.obj not replaced"; fi
ln -s "$work/out/keep.obj" "$work/out/link.obj"
bad "--force over a symlink" "link.obj" convert "$DATA/polylines.obj" "$work/out/link.obj" --force

# --- Bad input: one line, nothing written.
printf '\377\377\377\377' >"$work/huge.data"
head -c 96 /dev/zero >>"$work/huge.data"
bad "2^32 - 1 strands" "huge.data: header: negative strand count -1" \
  convert "$work/huge.data" "$work/out/never.usda"
printf '\377\377\377\177' >"$work/big.data"
head -c 96 /dev/zero >>"$work/big.data"
bad "2^31 - 1 strands" "a 100-byte file holds at most 24" \
  convert "$work/big.data" "$work/out/never.usda"
printf 'v 0 0 0\nv 0 0 0\nl 1 2\n' >"$work/repeated.obj"
bad "repeated point" "repeated.obj: strand 0 (line 3), point 1: repeated point" \
  convert "$work/repeated.obj" "$work/out/never.hair"
printf '#usda 1.0\ndef BasisCurves "c"\n{\n    int[] curveVertexCounts = [2]\n}\n' >"$work/cubic.usda"
bad "cubic usda" "</c>.type: not authored" convert "$work/cubic.usda" "$work/out/never.obj"
bad "unknown output" "unknown output extension \".txt\"" \
  convert "$DATA/polylines.obj" "$work/out/never.txt"
bad "unknown input" "unknown strand file extension" convert "$work/huge" "$work/out/never.obj"
bad "missing input" "cannot open" convert "$work/missing.obj" "$work/out/never.obj"
bad "--out-up-axis for usda" "--out-up-axis: only for .data outputs" \
  convert "$DATA/polylines.obj" "$work/out/never.usda" --out-up-axis y
bad "--out-units-per-metre for obj" "--out-units-per-metre: only for .hair and .data" \
  convert "$DATA/polylines.obj" "$work/out/never.obj" --out-units-per-metre 100
bad "--up-axis x" "--up-axis" convert "$DATA/polylines.obj" "$work/out/never.obj" --up-axis x
bad "--units-per-metre 0" "units_per_metre: expected a finite number > 0" \
  convert "$DATA/polylines.obj" "$work/out/never.obj" --units-per-metre 0
bad "--width -1" "default_width" convert "$DATA/polylines.obj" "$work/out/never.obj" --width -1
bad "--out-units-per-metre 0 (hair)" "units_per_metre" \
  convert "$DATA/polylines.obj" "$work/out/never.hair" --out-units-per-metre 0

echo "cli_convert: $checks passed, $failures failed"
[ "$failures" -eq 0 ]
