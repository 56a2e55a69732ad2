#!/usr/bin/env bash
# The command-line contract of `ringlet groom` (docs/hairstyle-format.md): a small hairstyle
# written here grooms into strands.hair, strands.usda, strands.obj, body.obj and masters.json
# whose counts agree with the summary line; --formats, --force, --quiet and --threads behave; the
# body path is resolved relative to the hairstyle file, not the working directory; existing files
# are never overwritten silently; every bad input gives exit code 1, exactly one line on stderr
# naming the field, and creates neither the output directory nor any file in it.
#
# Needs RINGLET (the built binary) and EXAMPLES (the examples/ directory); run by ctest as
# `cli_groom`. Exits non-zero if any check failed, after printing what failed.
set -u

: "${RINGLET:?set RINGLET to the ringlet binary}"
: "${EXAMPLES:?set EXAMPLES to the examples directory}"
PYTHON=/usr/bin/python3

work=$(mktemp -d "${TMPDIR:-/tmp}/ringlet_cli_groom.XXXXXX") || exit 1
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/styles/bodies" "$work/out"
cp "$EXAMPLES/bodies/mannequin.json" "$work/styles/bodies/mannequin.json"

source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"  # checks, fail, ok, run, expect_*

# A small hairstyle: 12 masters of 8 segments, 3 strands of 8 points per wisp (36 strands,
# 288 points). The body path is relative to this file's directory.
style() {  # style NAME EXTRA_MEMBERS: writes $work/styles/NAME.json
  cat >"$work/styles/$1.json" <<EOF
{
  "description": "cli_groom_test: a small head of hair",
  "body": "bodies/mannequin.json",
  "masters": {"count": 12, "seed": 4, "segments": 8, "points_per_segment": 2},
  "hair": {"origin": "caucasian", "curl": "wavy", "length": 0.15, "seed": 2},
  "wisps": {"strands_per_wisp": 3, "points_per_strand": 8},
  "layers": {"count": 3, "thickness": 0.003}${2:+,
  $2}
}
EOF
}
style small ""
SMALL="$work/styles/small.json"

# Checks an output directory against the summary line and the documented contents.
check_outputs() {  # check_outputs WHAT DIR
  if "$PYTHON" - "$2" "$work/stdout" <<'EOF' >"$work/check" 2>&1; then ok; else
import json, re, struct, sys
out, stdout = sys.argv[1], open(sys.argv[2]).read()
errors = []
m = re.search(r"^groomed (\d+) masters \((\d+) converged, (\d+) unconverged, (\d+) unstable; "
              r"(\d+) iterations\), (\d+) strands, (\d+) points$", stdout, re.M)
if not m:
    print("no summary line on stdout: " + stdout)
    sys.exit(1)
masters, converged, _, _, iterations, strands, points = map(int, m.groups())
if (masters, converged, strands, points) != (12, 12, 36, 288):
    errors.append("summary says %d masters (%d converged), %d strands, %d points; expected "
                  "12 (12), 36, 288" % (masters, converged, strands, points))
# .hair: "HAIR", uint32 strand count, uint32 point count (docs/file-formats.md).
head = open(out + "/strands.hair", "rb").read(128)
if head[:4] != b"HAIR":
    errors.append("strands.hair does not start with HAIR")
hair_strands, hair_points = struct.unpack("<II", head[4:12])
if (hair_strands, hair_points) != (strands, points):
    errors.append("strands.hair header: %d strands, %d points; summary: %d, %d"
                  % (hair_strands, hair_points, strands, points))
# .hair info text (bytes 40-127): the unit it was written in (metres by default).
info = head[40:128].split(b"\0", 1)[0].decode("ascii")
if info != "ringlet hair curves; 1 unit per metre (metres); z up; thickness: diameter":
    errors.append("strands.hair info text: %r" % info)
# .hair arrays (points, thickness, colour: bits 2 | 4 | 16, equal counts so no segments array).
import numpy
data = open(out + "/strands.hair", "rb").read()
arrays = struct.unpack("<I", data[12:16])[0]
if arrays != 2 | 4 | 16 or len(data) != 128 + 28 * hair_points:
    errors.append("strands.hair arrays 0x%x, %d bytes: expected points, thickness and colour"
                  % (arrays, len(data)))
else:
    n = hair_points
    thickness = numpy.frombuffer(data, "<f4", n, 128 + 12 * n).reshape(strands, -1)
    colours = numpy.frombuffer(data, "<f4", 3 * n, 128 + 16 * n).reshape(n, 3)
    # Colour: exp(-3 sigma_a) of the default melanins (render_json.h: eumelanin 1.3,
    # pheomelanin 0.2; Chiang et al. 2016's absorption per unit concentration written here).
    sigma = 1.3 * numpy.array([0.419, 0.697, 1.37]) + 0.2 * numpy.array([0.187, 0.4, 1.05])
    want = numpy.exp(-3.0 * sigma)
    if numpy.abs(colours - want).max() > 1e-7:
        errors.append("strands.hair colours %s, expected exp(-3 sigma_a) = %s"
                      % (colours[0], want))
    # Default taper (wisp.h): the tip is 1/5 of the root's diameter (every strand is longer than
    # the 6 cm taper), and no strand gets thicker toward the tip.
    ratio = thickness[:, -1] / thickness[:, 0]
    if numpy.abs(ratio - 0.2).max() > 1e-6:
        errors.append("strands.hair tip/root thickness ratios %s, expected 0.2" % ratio[:4])
    if (numpy.diff(thickness, axis=1) > 0).any():
        errors.append("strands.hair: a strand gets thicker toward its tip")
# OBJ: one 2-vertex segment per edge: points - strands segments, each "l i i+1".
segments = [line.split() for line in open(out + "/strands.obj") if line.startswith("l ")]
if len(segments) != points - strands:
    errors.append("strands.obj has %d 'l' lines, expected %d segments"
                  % (len(segments), points - strands))
if any(len(l) != 3 or int(l[2]) != int(l[1]) + 1 for l in segments):
    errors.append("strands.obj: an 'l' element is not a 2-vertex segment (i, i + 1)")
# body.obj: the mannequin's 9 spheres as UV spheres of 23 x 48 + 2 vertices.
body = open(out + "/body.obj").read().splitlines()
objects = [l.split()[1] for l in body if l.startswith("o ")]
if objects[:2] != ["head", "jaw"] or len(objects) != 9:
    errors.append("body.obj objects %s: expected the mannequin's 9 spheres" % objects)
if sum(1 for l in body if l.startswith("v ")) != 9 * (23 * 48 + 2):
    errors.append("body.obj: wrong vertex count")
# USDA: one BasisCurves prim with one vertex count per strand, and the strands' colour.
usda = open(out + "/strands.usda").read()
counts = re.search(r"int\[\] curveVertexCounts = \[([^\]]*)\]", usda)
if not usda.startswith("#usda 1.0") or "def BasisCurves" not in usda or not counts:
    errors.append("strands.usda is not a BasisCurves layer")
elif len(counts.group(1).split(",")) != strands:
    errors.append("strands.usda: %d curve vertex counts, expected %d"
                  % (len(counts.group(1).split(",")), strands))
if "color3f[] primvars:displayColor = [" not in usda:
    errors.append("strands.usda has no primvars:displayColor")
# masters.json: one solved strand per master and the groom counts.
d = json.load(open(out + "/masters.json"))
g = d.get("groom", {})
if len(d.get("strands", [])) != masters:
    errors.append("masters.json has %d strands, expected %d" % (len(d.get("strands", [])), masters))
for key, want in (("masters", masters), ("strands", strands), ("points", points),
                  ("converged", converged), ("iterations", iterations)):
    if g.get(key) != want:
        errors.append("masters.json groom.%s = %r, summary says %d" % (key, g.get(key), want))
for key in ("layers", "wisp_radii"):
    if len(g.get(key, [])) != masters:
        errors.append("masters.json groom.%s does not have one entry per master" % key)
if not all(0 <= l < 3 for l in g.get("layers", [])) or len(set(g.get("layers", []))) < 2:
    errors.append("masters.json groom.layers = %r: expected several of 0, 1, 2" % g.get("layers"))
if not all(s.get("termination") == "converged" for s in d.get("strands", [])):
    errors.append("masters.json: a master did not converge")
if errors:
    print("; ".join(errors))
    sys.exit(1)
EOF
    fail "$1: $(cat "$work/check")"
  fi
}

# --------------------------------------------------------------------------------------------
# A groom writes the five files; the summary is on stdout, nothing on stderr.
run groom "$SMALL" -o "$work/out/all"
expect_rc "groom" 0
[ -s "$work/stderr" ] && fail "groom: unexpected stderr: $(cat "$work/stderr")" || ok
expect_files "groom" "$work/out/all" strands.hair strands.usda strands.obj body.obj \
  masters.json
grep -q '^placed 12 of 12 roots' "$work/stdout" && ok ||
  fail "groom: no root line on stdout: $(cat "$work/stdout")"
grep -q '^max penetration .* -> ' "$work/stdout" && ok ||
  fail "groom: no penetration/timing line on stdout: $(cat "$work/stdout")"
check_outputs "groom" "$work/out/all"

# --formats hair writes only that file.
run groom "$SMALL" -o "$work/out/hair_only" --formats hair
expect_rc "--formats hair" 0
expect_files "--formats hair" "$work/out/hair_only" strands.hair
run groom "$SMALL" -o "$work/out/two" --formats obj,json --quiet
expect_rc "--formats obj,json" 0
expect_files "--formats obj,json" "$work/out/two" strands.obj masters.json

# --quiet prints nothing on success.
[ -s "$work/stdout" ] || [ -s "$work/stderr" ] &&
  fail "--quiet printed: $(cat "$work/stdout" "$work/stderr")" || ok

# The result does not depend on the thread count: byte-identical geometry files.
run groom "$SMALL" -o "$work/out/t1" --threads 1 --quiet
expect_rc "--threads 1" 0
run groom "$SMALL" -o "$work/out/t2" --threads 2 --quiet
expect_rc "--threads 2" 0
for f in strands.hair strands.obj strands.usda; do
  cmp -s "$work/out/t1/$f" "$work/out/t2/$f" && ok || fail "--threads 1 and 2 give different $f"
done
cmp -s "$work/out/t1/strands.hair" "$work/out/all/strands.hair" && ok ||
  fail "--threads 1 and the default thread count give different strands.hair"

# --hair-units-per-metre 100 writes centimetres: same header counts, different bytes.
run groom "$SMALL" -o "$work/out/cm" --formats hair --hair-units-per-metre 100 --quiet
expect_rc "--hair-units-per-metre 100" 0
cmp -s "$work/out/cm/strands.hair" "$work/out/all/strands.hair" &&
  fail "--hair-units-per-metre 100 wrote the same bytes as metres" || ok
cmp -s <(head -c 12 "$work/out/cm/strands.hair") <(head -c 12 "$work/out/all/strands.hair") && ok ||
  fail "--hair-units-per-metre 100 changed the strand or point count"
# ... and its header says so (bytes 40-127), instead of "metres".
[ "$(head -c 128 "$work/out/cm/strands.hair" | tail -c 88 | tr -d '\0')" = \
  "ringlet hair curves; 100 units per metre (centimetres); z up; thickness: diameter" ] && ok ||
  fail "--hair-units-per-metre 100: the header does not state centimetres"

# An existing file is refused and untouched without --force (and nothing else is written),
# replaced with it.
mkdir -p "$work/out/existing"
echo "precious" >"$work/out/existing/strands.obj"
run groom "$SMALL" -o "$work/out/existing"
expect_rc "existing file without --force" 1
expect_one_error_line "existing file without --force" "strands.obj: already exists"
[ "$(cat "$work/out/existing/strands.obj")" = "precious" ] && ok ||
  fail "existing file was modified without --force"
expect_files "existing file without --force" "$work/out/existing" strands.obj
# ... but another format may be written next to it.
run groom "$SMALL" -o "$work/out/existing" --formats hair --quiet
expect_rc "existing directory, other format" 0
expect_files "existing directory, other format" "$work/out/existing" strands.obj strands.hair
run groom "$SMALL" -o "$work/out/existing" --force
expect_rc "existing file with --force" 0
expect_files "existing file with --force" "$work/out/existing" \
  strands.hair strands.usda strands.obj body.obj masters.json
cmp -s "$work/out/existing/strands.obj" "$work/out/all/strands.obj" && ok ||
  fail "--force did not replace strands.obj with the groom"

# Masters that do not converge: exit 2, files still written, the summary and a warning say so.
style budget '"solver": {"max_iterations": 1}'
run groom "$work/styles/budget.json" -o "$work/out/budget"
expect_rc "unconverged masters" 2
expect_files "unconverged masters" "$work/out/budget" \
  strands.hair strands.usda strands.obj body.obj masters.json
grep -q '^groomed 12 masters (0 converged, 12 unconverged' "$work/stdout" && ok ||
  fail "unconverged masters: summary does not say so: $(cat "$work/stdout")"
grep -q 'did not reach a stable equilibrium' "$work/stderr" && ok ||
  fail "unconverged masters: no warning on stderr: $(cat "$work/stderr")"

# --------------------------------------------------------------------------------------------
# Bad input: exit 1, one line on stderr naming the field, no output directory or file.

# bad_run WHAT FIELD ARGS...: runs groom with ARGS and an output directory that does not exist.
bad_run() {
  local what=$1 field=$2
  shift 2
  run groom "$@" -o "$work/never/out"
  expect_rc "$what" 1
  expect_one_error_line "$what" "$field"
  [ -s "$work/stdout" ] && fail "$what: printed on stdout: $(cat "$work/stdout")" || ok
  if [ -e "$work/never" ]; then
    fail "$what: created $work/never: $(find "$work/never")"
    rm -rf "$work/never"
  else ok; fi
}

# bad NAME FIELD < hairstyle: writes the hairstyle from stdin next to the body and checks it.
bad() {
  cat >"$work/styles/$1.json"
  bad_run "bad hairstyle $1" "$2" "$work/styles/$1.json"
}

bad unknown_origin 'hair.origin' <<'EOF'
{"body": "bodies/mannequin.json", "hair": {"origin": "martian"}, "masters": {"count": 5}}
EOF
grep -qF 'asian, caucasian, african' "$work/stderr" && ok ||
  fail "unknown origin: valid names not listed"
grep -qF 'hair_type' "$work/stderr" && fail "unknown origin: names hair_type, not a key of the file" ||
  ok
bad unknown_curl 'hair.curl' <<'EOF'
{"body": "bodies/mannequin.json", "hair": {"curl": "frizzy"}, "masters": {"count": 5}}
EOF
bad malformed_json 'line 2, column' <<'EOF'
{"body": "bodies/mannequin.json",
 "masters": {"count": 5,, }}
EOF
bad missing_body_file 'body: ' <<'EOF'
{"body": "bodies/no_such_body.json", "masters": {"count": 5}}
EOF
grep -qF 'no_such_body.json' "$work/stderr" && ok || fail "missing body file: path not named"
bad negative_count 'masters.count' <<'EOF'
{"body": "bodies/mannequin.json", "masters": {"count": -3}}
EOF
bad zero_strands_per_wisp 'wisps.strands_per_wisp' <<'EOF'
{"body": "bodies/mannequin.json", "masters": {"count": 5}, "wisps": {"strands_per_wisp": 0}}
EOF
bad unknown_key 'wisps.strand_per_wisp' <<'EOF'
{"body": "bodies/mannequin.json", "masters": {"count": 5}, "wisps": {"strand_per_wisp": 3}}
EOF
bad bad_layer_thickness 'layers.thickness' <<'EOF'
{"body": "bodies/mannequin.json", "masters": {"count": 5}, "layers": {"thickness": -0.002}}
EOF
bad empty_mesh_scalp 'scalp.mesh' <<'EOF'
{"body": "bodies/mannequin.json", "masters": {"count": 5}, "scalp": {"mesh": "head"}}
EOF
bad empty_file 'line 1, column 1' </dev/null

bad_run "missing hairstyle file" "no_such_style.json" "$work/styles/no_such_style.json"
bad_run "unknown --formats name" "--formats" "$SMALL" --formats hair,fbx
grep -qF 'fbx' "$work/stderr" && ok || fail "unknown --formats: the bad name is not quoted"
bad_run "empty --formats" "--formats" "$SMALL" --formats ""
bad_run "--hair-units-per-metre 0" "--hair-units-per-metre" "$SMALL" --hair-units-per-metre 0
bad_run "--threads -1" "--threads" "$SMALL" --threads -1

# The output path is an existing file: refused, even with --force, and left untouched.
echo "not a directory" >"$work/out/plain_file"
for force in "" "--force"; do
  run groom "$SMALL" -o "$work/out/plain_file" $force
  expect_rc "output is a file $force" 1
  expect_one_error_line "output is a file $force" "not a directory"
  [ "$(cat "$work/out/plain_file")" = "not a directory" ] && ok ||
    fail "output is a file $force: the file was modified"
done

# Usage.
run groom --help
expect_rc "groom --help" 0
for option in --output --formats --force --threads --quiet --hair-units-per-metre; do
  grep -q -- "$option" "$work/stdout" && ok || fail "groom --help does not mention $option"
done
run groom "$SMALL"
expect_rc "missing --output" 1
expect_one_error_line "missing --output" "--output"

# --------------------------------------------------------------------------------------------
if [ "$failures" -ne 0 ]; then
  echo "cli_groom_test: $failures of $((checks + failures)) checks FAILED" >&2
  exit 1
fi
echo "cli_groom_test: all $checks checks passed"
