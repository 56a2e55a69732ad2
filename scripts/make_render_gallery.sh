#!/bin/sh
# Rendered pictures for docs/rendering.md: the four example hairstyles on the sphere mannequin
# (examples/hairstyles/*_mannequin.json; the head-and-shoulders gallery of docs/hairstyles.md is
# scripts/render_gallery.sh), dry vs wet,
# circular vs elliptic fibres, hair colour by melanin, and multiple scattering vs the fast
# transmittance preview on blonde hair.
#
#   scripts/make_render_gallery.sh [BUILD_DIR] [IMAGE_DIR]     (defaults: build, docs/images)
#
# Needs ringlet built in BUILD_DIR and /usr/bin/python3 with matplotlib (for the side-by-side
# panels). Work files go to BUILD_DIR/gallery/. SIZE and SPP (environment) change the panels'
# resolution and samples per pixel (defaults 360 and 16).
set -eu
cd "$(dirname "$0")/.."
build=${1:-build}
images=${2:-docs/images}
python=/usr/bin/python3
size=${SIZE:-360}
spp=${SPP:-16}
out=$build/gallery
mkdir -p "$out" "$images"
if [ ! -x "$build/ringlet" ]; then
  echo "make_render_gallery.sh: $build/ringlet not found; build it first" >&2
  exit 1
fi
ringlet=$build/ringlet
body=examples/bodies/mannequin.json

# One fixed camera for the comparisons, so that only the compared parameter changes: from the
# front-right, slightly above, as the default framed camera (render_json.h), at the head.
cat > "$out/camera.json" <<'EOF'
{"render": {"camera": {"position": [0.42, 0.84, 0.16], "look_at": [0.0, 0.0, -0.07],
                       "fov_degrees": 30}}}
EOF

# 1. The four example hairstyles, groomed and rendered with their own hair types (the
#    eccentricity of each type is the mechanical one).
for style in straight wavy curly african; do
  echo "== groom $style --render"
  "$ringlet" groom examples/hairstyles/${style}_mannequin.json -o "$out/$style" --force --render \
    --width "$size" --height "$size" --spp "$spp" | tee "$out/$style.log"
done
$python scripts/combine_images.py -o "$images/render_styles.png" \
  "$out/straight/render.png" "straight (caucasian)" \
  "$out/wavy/render.png" "wavy (caucasian)" \
  "$out/curly/render.png" "curly (caucasian)" \
  "$out/african/render.png" "african (kinky)"

render() {  # render OUTPUT.png INPUT ARGS...
  output=$1
  shift
  echo "== render $* -> $output"
  "$ringlet" render "$@" -o "$output" --force --settings "$out/camera.json" \
    --width "$size" --height "$size" --spp "$spp"
}

# 2. Dry vs wet: the wet hair's shape and its optics (a water film darkens it; docs/rendering.md),
#    both groomed or styled and rendered in one process (--render: a .hair file does not carry
#    the wetness), same camera.
for state in dry wet; do
  $python - "$out/wavy_$state.json" "$out/camera.json" "$state" <<'EOF'
import json, os, sys
source = "examples/hairstyles/wavy_mannequin.json"
style = json.load(open(source))
style["body"] = os.path.abspath(os.path.join(os.path.dirname(source), style["body"]))
style.setdefault("render", {}).update(json.load(open(sys.argv[2]))["render"])
if sys.argv[3] == "wet":
    style["operations"] = [{"wet": {}}]
json.dump(style, open(sys.argv[1], "w"), indent=1)
EOF
  command=groom  # ringlet style needs an operation: the dry hair is groomed
  [ "$state" = wet ] && command=style
  echo "== $command wavy_$state --render"
  "$ringlet" $command "$out/wavy_$state.json" -o "$out/wavy_$state" --force --render \
    --width "$size" --height "$size" --spp "$spp" | tee "$out/wavy_$state.log"
done
$python scripts/combine_images.py -o "$images/render_wet.png" \
  "$out/wavy_dry/render.png" "wavy, dry" \
  "$out/wavy_wet/render.png" "wavy, wet (E / 10, swollen, heavier, darker)"
e_caucasian=0.705  # sqrt(1 - 1/1.41^2): caucasian ellipticity 1.41 (docs/hair-types.md)

# 3. Circular vs elliptic fibres on the same (straight) groom, close up on the side of the head
#    with the key light on the camera's side, so that the highlights show: only the optics
#    change; with e > 0 the TRT lobe's centre moves with the orientation of each strand's
#    cross-section (Marschner et al. 2003, section 4.3), which the groom takes from the masters'
#    material frames.
cat > "$out/closeup.json" <<'EOF'
{"render": {"camera": {"position": [0.5, -0.1, -0.12], "look_at": [0.06, 0.0, -0.08],
                       "fov_degrees": 32},
            "key_light": {"direction": [1.0, 0.1, 0.35], "angular_radius_degrees": 1.146,
                          "irradiance": [3, 3, 3]}}}
EOF
e_african=0.798  # sqrt(1 - 1/1.66^2): african ellipticity 1.66
closeup() {  # closeup OUTPUT.png ARGS...
  output=$1
  shift
  echo "== render close-up $* -> $output"
  "$ringlet" render examples/hairstyles/straight_mannequin.json -o "$output" --force \
    --settings "$out/closeup.json" --width "$size" --height "$size" --spp "$spp" \
    --eumelanin 0.6 --pheomelanin 0.1 --shadows fibre_transmittance "$@"
}
closeup "$out/circular.png" --eccentricity 0
closeup "$out/elliptic.png" --eccentricity $e_african
$python - "$out/circular.png" "$out/elliptic.png" "$out/difference.png" <<'EOF'
import sys
import matplotlib.image as mpimg
import numpy as np
a, b = (mpimg.imread(p)[..., :3] for p in sys.argv[1:3])
mpimg.imsave(sys.argv[3], np.clip(4.0 * np.abs(b - a), 0.0, 1.0))
EOF
$python scripts/combine_images.py -o "$images/render_eccentricity.png" \
  "$out/circular.png" "circular fibres (e = 0)" \
  "$out/elliptic.png" "elliptic fibres (e = 0.80, as african hair)" \
  "$out/difference.png" "|difference| x 4"

# 4. Hair colour by pigment (Chiang et al. 2016's melanin absorption), wavy shapes.
render "$out/black.png" "$out/wavy/strands.hair" --body $body --eccentricity $e_caucasian \
  --eumelanin 8 --pheomelanin 0
render "$out/brown.png" "$out/wavy/strands.hair" --body $body --eccentricity $e_caucasian \
  --eumelanin 1.3 --pheomelanin 0.2
render "$out/blonde.png" "$out/wavy/strands.hair" --body $body --eccentricity $e_caucasian \
  --eumelanin 0.3 --pheomelanin 0.05
render "$out/red.png" "$out/wavy/strands.hair" --body $body --eccentricity $e_caucasian \
  --eumelanin 0.3 --pheomelanin 2.5
$python scripts/combine_images.py -o "$images/render_melanin.png" \
  "$out/black.png" "black (eumelanin 8)" "$out/brown.png" "brown (1.3, pheo 0.2)" \
  "$out/blonde.png" "blonde (0.3, pheo 0.05)" "$out/red.png" "red (0.3, pheo 2.5)"

# 5. Multiple scattering: blonde hair path traced vs the single-scattering preview.
render "$out/blonde_preview.png" "$out/wavy/strands.hair" --body $body \
  --eccentricity $e_caucasian --eumelanin 0.3 --pheomelanin 0.05 --shadows fibre_transmittance
$python scripts/combine_images.py -o "$images/render_multiple_scattering.png" \
  "$out/blonde_preview.png" "blonde, direct light + fibre transmittance" \
  "$out/blonde.png" "blonde, path traced (16 bounces)"
