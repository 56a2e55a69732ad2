#!/bin/sh
# Regenerates the matplotlib pictures of docs/hairstyles.md ("On the sphere mannequin"): grooms the
# four example hairstyles on the paper's sphere mannequin (examples/hairstyles/*_mannequin.json) and
# a no-hull-layer variant of the wavy one, draws them, and draws the strand growing on a sphere.
#
#   scripts/make_gallery.sh [BUILD_DIR] [IMAGE_DIR]     (defaults: build, docs/images)
#
# Needs ringlet and the drape_example tool built in BUILD_DIR:
#   cmake -S . -B build -G Ninja -DRINGLET_BUILD_TOOLS=ON -DRINGLET_BUILD_TESTS=OFF
#   cmake --build build --target ringlet_cli drape_example
# and /usr/bin/python3 with numpy and matplotlib. The grooms go to BUILD_DIR/gallery/<style>/,
# with each summary in BUILD_DIR/gallery/<style>.log; the volume numbers are printed at the end.
set -eu
cd "$(dirname "$0")/.."
build=${1:-build}
images=${2:-docs/images}
python=/usr/bin/python3
out=$build/gallery
mkdir -p "$out" "$images"
for tool in "$build/ringlet" "$build/tools/drape_example"; do
  if [ ! -x "$tool" ]; then
    echo "make_gallery.sh: $tool not found; build it first (see the comment at the top)" >&2
    exit 1
  fi
done

groom() {  # groom HAIRSTYLE NAME
  echo "== ringlet groom $1 -o $out/$2/"
  "$build/ringlet" groom "$1" -o "$out/$2" --force | tee "$out/$2.log"
}

for style in straight wavy curly african; do
  groom "examples/hairstyles/${style}_mannequin.json" "$style"
  # The title: the hairstyle's description up to its first colon.
  description=$($python -c "import json, sys; print(json.load(open(sys.argv[1]))['description']
      .split(':')[0])" "examples/hairstyles/${style}_mannequin.json")
  $python scripts/plot_groom.py "$out/$style" -o "$images/groom_$style.png" --palette "$style" \
    --title "${style}_mannequin.json: $description"
done

# The same wavy hairstyle without hull layers (Lee & Ko 2001): one layer of zero thickness.
# A temporary copy of the example, with the body path made absolute.
$python - "$out/wavy_no_layers.json" <<'PY'
import json, os, sys
style = json.load(open("examples/hairstyles/wavy_mannequin.json"))
style["body"] = os.path.abspath("examples/bodies/mannequin.json")
style["layers"] = {"count": 1, "thickness": 0}
style["description"] = "wavy_mannequin.json without hull layers (docs/hairstyles.md)"
json.dump(style, open(sys.argv[1], "w"), indent=1)
PY
groom "$out/wavy_no_layers.json" wavy_no_layers
$python scripts/plot_groom.py "$out/wavy_no_layers" "$out/wavy" -o "$images/groom_layers.png" \
  --palette wavy --views side,slice --labels "layers: 1, 0 mm" "layers: 4 x 3 mm" \
  --title "wavy_mannequin.json without and with hull layers (Lee & Ko 2001)"

# The paper's Figure 2 (right): a curly strand growing on a sphere.
echo "== drape_example $out/drape.csv"
"$build/tools/drape_example" "$out/drape.csv" | tee "$out/drape.log"
$python scripts/plot_drape.py "$out/drape.csv" "$images/drape_sphere.png"

echo "== volume over the top half of the head (m)"
$python scripts/plot_groom.py --stats "$out/straight" "$out/wavy" "$out/curly" "$out/african" \
  "$out/wavy_no_layers"
ls -l "$images"/groom_*.png "$images/drape_sphere.png"
