#!/usr/bin/env bash
# ringlet's .usda files read by a USD implementation that is not ringlet's: TinyUSDZ
# (tests/usd/tinyusdz_read.mjs, its npm WebAssembly build, installed by scripts/setup.sh into
# tests/usd/node_modules). `ringlet simulate --hair-per-frame` of a small hairstyle shaken for
# 0.5 s: TinyUSDZ reads hair.usda as a layer and composes it as a stage; the stage metadata
# (time codes as the USD specification sets them) and, at every time code, the points it read
# equal the .hair file of that frame (read here from the cyHair layout, not by ringlet) as
# float32, bit for bit; curveVertexCounts equal the .hair's segment counts, widths its
# thickness. Then `ringlet groom`'s strands.usda against its strands.hair the same way, and a
# truncated file, which TinyUSDZ must refuse (so the check can fail).
#
# Needs RINGLET and EXAMPLES; run by ctest as `usd_tinyusdz`. Exit 77 (skipped) without node
# or the installed reader; non-zero if any check failed.
set -u

: "${RINGLET:?set RINGLET to the ringlet binary}"
: "${EXAMPLES:?set EXAMPLES to the examples directory}"
PYTHON=/usr/bin/python3
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
reader="$here/tinyusdz_read.mjs"
if ! command -v node >/dev/null || [ ! -f "$here/node_modules/tinyusdz/tinyusdz.wasm" ]; then
  echo "skipped: node or TinyUSDZ missing (scripts/setup.sh installs them into tests/usd/node_modules)"
  exit 77
fi

work=$(mktemp -d "${TMPDIR:-/tmp}/ringlet_usd.XXXXXX") || exit 1
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/styles/bodies"
cp "$EXAMPLES/bodies/mannequin.json" "$work/styles/bodies/mannequin.json"
source "$here/../cli_lib.sh"  # checks, fail, ok, run, expect_*

# 6 masters of 8 segments, 3 strands of 8 points per wisp: 18 strands, 144 points.
cat >"$work/styles/small.json" <<EOF
{
  "description": "tinyusdz_test: a small head of hair",
  "body": "bodies/mannequin.json",
  "masters": {"count": 6, "seed": 4, "segments": 8, "points_per_segment": 2},
  "hair": {"origin": "caucasian", "curl": "wavy", "length": 0.15, "seed": 2},
  "wisps": {"strands_per_wisp": 3, "points_per_strand": 8},
  "layers": {"count": 3, "thickness": 0.003}
}
EOF

# compare USDA_JSON FRAMES FPS HAIR...: what TinyUSDZ read against the .hair files (one per time
# code; FRAMES 0 for a file without time samples).
compare() {
  "$PYTHON" - "$@" <<'EOF'
import json, struct, sys
import numpy as np
usd = json.load(open(sys.argv[1]))
frames, fps, hairs = int(sys.argv[2]), float(sys.argv[3]), sys.argv[4:]
errors = []

def read_hair(path):
    # cyHair (cemyuksel.com/research/hairmodels): a 128-byte header ("HAIR", strand and point
    # counts, flags, defaults), then the arrays the flags name, in this order.
    data = open(path, "rb").read()
    magic, strands, points, flags, segs, thick, transp = struct.unpack_from("<4sIIIIff", data, 0)
    assert magic == b"HAIR", path
    at, out = 128, {}
    if flags & 1:
        out["segments"] = np.frombuffer(data, "<u2", strands, at).astype(int); at += 2 * strands
    else:
        out["segments"] = np.full(strands, segs)
    if flags & 2:
        out["points"] = np.frombuffer(data, "<f4", 3 * points, at); at += 12 * points
    if flags & 4:
        out["thickness"] = np.frombuffer(data, "<f4", points, at); at += 4 * points
    else:
        out["thickness"] = np.full(points, thick, np.float32)
    return out

meta, prims = usd["metadata"], usd["prims"]
if usd["stage_root_prims"] != 1:
    errors.append("stage: %s root prims, expected 1" % usd["stage_root_prims"])
if meta.get("defaultPrim") != "hair" or meta.get("upAxis") != "Z" or meta.get("metersPerUnit") != 1:
    errors.append("layer metadata: %s" % meta)
if frames:
    for name, want in [("startTimeCode", 0), ("endTimeCode", frames - 1),
                       ("timeCodesPerSecond", fps), ("framesPerSecond", fps)]:
        if meta.get(name) != want:
            errors.append("%s = %s, expected %s" % (name, meta.get(name), want))
hair = prims.get("hair", {})
attrs, samples = hair.get("attributes", {}), hair.get("time_samples", {})
if hair.get("type") != "BasisCurves" or attrs.get("type") != "linear" or attrs.get("wrap") != "nonperiodic":
    errors.append("prim: %s, type %s, wrap %s" % (hair.get("type"), attrs.get("type"), attrs.get("wrap")))
first = read_hair(hairs[0])
counts = attrs.get("curveVertexCounts", [])
if counts != list(first["segments"] + 1):
    errors.append("curveVertexCounts %s, .hair segments + 1 %s" % (counts[:6], list(first["segments"] + 1)[:6]))
widths = np.float32(attrs.get("widths", []))
if not np.array_equal(widths, first["thickness"]):
    errors.append("widths differ from the .hair thickness (%d against %d values)" % (len(widths), len(first["thickness"])))
if frames:
    points = samples.get("points", {})
    if sorted(int(t) for t in points) != list(range(frames)):
        errors.append("points time samples at %s, expected 0..%d" % (sorted(points)[:6], frames - 1))
    series = [(points.get(str(k), []), hairs[k]) for k in range(frames)]
else:
    series = [(attrs.get("points", []), hairs[0])]
moved = 0.0
for k, (values, path) in enumerate(series):
    want = read_hair(path)["points"]
    got = np.float32(values)
    if got.shape != want.shape or not np.array_equal(got, want):
        worst = np.max(np.abs(got - want)) if got.shape == want.shape else None
        errors.append("time %d: %d values, .hair %d; largest difference %s" % (k, got.size, want.size, worst))
    elif k:
        moved = max(moved, float(np.max(np.abs(got - np.float32(series[0][0])))))
if frames and not moved > 1e-3:
    errors.append("the samples barely differ (%.3g m): not a motion" % moved)
print("\n".join(errors))
sys.exit(1 if errors else 0)
EOF
}

# --- ringlet simulate: time-sampled points ------------------------------------------------------
run simulate "$work/styles/small.json" -o "$work/sim" --motion shake --duration 0.5 --fps 12 --hair-per-frame
expect_rc "simulate" 0
if node "$reader" "$work/sim/hair.usda" >"$work/sim.json" 2>"$work/reader.err"; then ok; else
  fail "TinyUSDZ: $(head -c 600 "$work/reader.err")"
fi
if compare "$work/sim.json" 7 12 "$work"/sim/frame_000{0..6}.hair >"$work/check" 2>&1; then ok; else
  fail "simulate hair.usda read by TinyUSDZ: $(cat "$work/check")"
fi

# --- ringlet groom: one static curve set ------------------------------------------------------
run groom "$work/styles/small.json" -o "$work/groom"
expect_rc "groom" 0
if node "$reader" "$work/groom/strands.usda" >"$work/groom.json" 2>"$work/reader.err"; then ok; else
  fail "TinyUSDZ: $(head -c 600 "$work/reader.err")"
fi
if compare "$work/groom.json" 0 24 "$work/groom/strands.hair" >"$work/check" 2>&1; then ok; else
  fail "groom strands.usda read by TinyUSDZ: $(cat "$work/check")"
fi

# --- the reader refuses a broken file ---------------------------------------------------------
head -c 2000 "$work/sim/hair.usda" >"$work/broken.usda"
if node "$reader" "$work/broken.usda" >/dev/null 2>"$work/reader.err"; then
  fail "TinyUSDZ accepted a truncated hair.usda"
elif grep -q "cannot read" "$work/reader.err"; then ok; else
  fail "TinyUSDZ on a truncated file: $(head -c 300 "$work/reader.err")"
fi

echo "$checks checks, $failures failures"
[ "$failures" -eq 0 ]
