#!/bin/sh
# The pictures of docs/hairstyles.md's gallery: every example hairstyle on the head-and-shoulders
# mesh, groomed (or styled, when the file has an operations list) once and path traced from the
# front and from the side with `ringlet render`, each picture 400 px wide.
#
#   scripts/render_gallery.sh [BUILD_DIR] [IMAGE_DIR]     (defaults: build, docs/images)
#
# Needs ringlet built in BUILD_DIR and Debian's /usr/bin/python3 with numpy and matplotlib (the
# cameras' settings files and the downscaling). Re-run it after a renderer change to refresh every
# gallery picture. Work files go to BUILD_DIR/hairstyle_gallery/ (the groom summaries in
# STYLE.log). Environment: SIZE (rendered width and height, default 400; a multiple of 400 is
# box-downscaled to 400 px, e.g. SIZE=800 for a 2 x 2 supersampled picture), SPP (samples per
# pixel, default 16, the main job's) and STYLES (the examples to render, default all six).
set -eu
cd "$(dirname "$0")/.."
build=${1:-build}
images=${2:-docs/images}
python=/usr/bin/python3
size=${SIZE:-400}
spp=${SPP:-16}
styles=${STYLES:-"wavy straight curly african ringlets bob"}
out=$build/hairstyle_gallery
mkdir -p "$out" "$images"
if [ ! -x "$build/ringlet" ]; then
  echo "render_gallery.sh: $build/ringlet not found; build it first" >&2
  exit 1
fi
ringlet=$build/ringlet

for style in $styles; do
  file=examples/hairstyles/$style.json
  # A file with an operations list is styled (ringlet style applies it); others are groomed.
  command=groom
  if grep -q '"operations"' "$file"; then command=style; fi
  echo "== $command $style"
  "$ringlet" $command "$file" -o "$out/$style" --formats hair,json --force | tee "$out/$style.log"

  # Two settings files: the hairstyle's own "render" object (hair colour) with a fixed camera,
  # the same for every example so that the pictures compare: 1 m from the head's axis, looking
  # at the chin's height, 34 degrees of field (the head, the shoulders and 45-cm hair in frame).
  # The front camera looks at the face (+y); the side camera at the person's left (from -x),
  # the side the default key light (from the front-left, above) falls on. Also prints the body
  # file and the fibre eccentricity of the hair type (docs/hair-types.md), which a .hair file
  # does not carry.
  set -- $($python - "$file" "$out/$style" <<'EOF'
import json
import os
import sys

path, prefix = sys.argv[1], sys.argv[2]
document = json.load(open(path))
eccentricity = {"asian": 0.632, "caucasian": 0.705, "african": 0.798}  # docs/hair-types.md
origin = document.get("hair", {}).get("origin", "caucasian")
cameras = {
    "front": {"position": [0.0, 1.0, 0.0], "look_at": [0.0, 0.0, -0.1]},
    "side": {"position": [-1.0, 0.0, 0.0], "look_at": [0.0, 0.0, -0.1]},
}
for view, camera in cameras.items():
    render = dict(document.get("render", {}))
    render["camera"] = dict(camera, fov_degrees=34)
    with open(f"{prefix}_{view}.json", "w") as f:
        json.dump({"render": render}, f)
body = document["body"]
print(os.path.normpath(os.path.join(os.path.dirname(path), body)), eccentricity[origin])
EOF
)
  body=$1
  eccentricity=$2
  for view in front side; do
    echo "== render $style $view"
    "$ringlet" render "$out/$style/strands.hair" --body "$body" --eccentricity "$eccentricity" \
      --settings "$out/${style}_$view.json" --width "$size" --height "$size" --spp "$spp" \
      -o "$out/${style}_$view.png" --force | tee -a "$out/$style.log"
    # A k x k box downscale to 400 px when SIZE = 400 k (averaging the sRGB codes: a preview,
    # not a radiometric filter); other sizes are copied as rendered.
    $python - "$out/${style}_$view.png" "$images/hairstyle_${style}_$view.png" <<'EOF'
import sys

import matplotlib.image as mpimg
import numpy as np

image = mpimg.imread(sys.argv[1])[..., :3]
k = image.shape[0] // 400
if k >= 2 and image.shape[0] == 400 * k and image.shape[1] == 400 * k:
    image = image.reshape(400, k, 400, k, 3).mean(axis=(1, 3))
mpimg.imsave(sys.argv[2], np.clip(image, 0.0, 1.0))
EOF
  done
done
ls -l "$images"/hairstyle_*.png
