#!/bin/sh
# The looks of "every strand a solved rod" (docs/benchmarks.md, issue 11): the wavy example with
# procedural children (the masters + wisps model) beside the same head with every child solved
# as a rod (examples/hairstyles/wavy_solved_children.json), path traced from the front and from
# the side, with the groom summaries (times, penetration) in BUILD_DIR/solved_children/*.log.
#
#   scripts/make_solved_children_pictures.sh [BUILD_DIR] [IMAGE_DIR]
#   (defaults: build, docs/images)
#
# Needs ringlet built in BUILD_DIR and Debian's /usr/bin/python3 with matplotlib. Environment:
# SIZE (pixels, default 400), SPP (samples per pixel, default 16).
set -eu
cd "$(dirname "$0")/.."
build=${1:-build}
images=${2:-docs/images}
python=/usr/bin/python3
size=${SIZE:-400}
spp=${SPP:-16}
out=$build/solved_children
mkdir -p "$out" "$images"
if [ ! -x "$build/ringlet" ]; then
  echo "make_solved_children_pictures.sh: $build/ringlet not found; build it first" >&2
  exit 1
fi
# The same hairstyle with procedural children: only wisps.children differs (the body path is
# made absolute, since the copy lives elsewhere).
$python - "$out/wavy_procedural.json" <<'EOF'
import json, os, sys
source = "examples/hairstyles/wavy_solved_children.json"
style = json.load(open(source))
style["wisps"]["children"] = "procedural"
style["body"] = os.path.abspath(os.path.join(os.path.dirname(source), style["body"]))
style["description"] = "wavy_solved_children.json with procedural children (masters + wisps)"
json.dump(style, open(sys.argv[1], "w"), indent=1)
EOF
for name in procedural solved; do
  file=$out/wavy_procedural.json
  [ "$name" = solved ] && file=examples/hairstyles/wavy_solved_children.json
  echo "== groom $name"
  "$build/ringlet" groom "$file" -o "$out/$name" --formats hair --force | tee "$out/$name.log"
  for view in front side; do
    direction=0,-1,0
    [ "$view" = side ] && direction=-1,0,0
    "$build/ringlet" render "$file" -o "$out/${name}_$view.png" --width "$size" \
      --height "$size" --spp "$spp" --view "$direction"
  done
done
$python scripts/combine_images.py -o "$images/solved_children.png" \
  "$out/procedural_front.png" "masters + procedural wisps" \
  "$out/solved_front.png" "every child solved as a rod" \
  "$out/procedural_side.png" "masters + procedural wisps (side)" \
  "$out/solved_side.png" "every child solved (side)"
echo "wrote $images/solved_children.png"
