#!/bin/sh
# The pictures of docs/inverse.md: long straight hair groomed on the sphere mannequin (it rests on
# the head, the back and the shoulders) is the target; `ringlet invert` computes the rest shapes
# that hold it under gravity with the body's support forces as unknowns, and writes the forward
# equilibria of the inverted and of the naive rest shapes (rest = target); plot_inverse.py draws
# the three side by side.
#
#   scripts/make_inverse_pictures.sh [BUILD_DIR] [IMAGE_DIR]     (defaults: build, docs/images)
#
# Needs ringlet built in BUILD_DIR and /usr/bin/python3 with numpy and matplotlib. Outputs go to
# BUILD_DIR/inverse/{groom,invert}/ (summary.json there), the log to BUILD_DIR/inverse/*.log.
set -eu
cd "$(dirname "$0")/.."
build=${1:-build}
images=${2:-docs/images}
python=/usr/bin/python3
out=$build/inverse
mkdir -p "$out" "$images"
if [ ! -x "$build/ringlet" ]; then
  echo "make_inverse_pictures.sh: $build/ringlet not found; build it first" >&2
  exit 1
fi
style=examples/hairstyles/long_straight.json
body=examples/bodies/mannequin.json
# The hairstyle gives every master the clearance 4 mm (wisp radius 4 mm, tip_scale 1, no hull
# layers): the inversion uses the same, so the groomed hair lies on its clearance surface.
"$build/ringlet" groom "$style" -o "$out/groom" --formats json --force | tee "$out/groom.log"
status=0
"$build/ringlet" invert "$out/groom/masters.json" -o "$out/invert" --body "$body" \
  --clearance 0.004 --hair-type asian/straight --force | tee "$out/invert.log" || status=$?
if [ "$status" -ne 0 ] && [ "$status" -ne 2 ]; then exit "$status"; fi
$python scripts/plot_inverse.py "$out/groom" "$out/invert" -o "$images/inverse_head.png" \
  --body "$body" --views side,back --scale 0.02
