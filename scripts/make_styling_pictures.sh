#!/bin/sh
# Before/after pictures of the styling operations (docs/styling.md), each beside its "before":
# wetting the wavy example, drying it again, cutting the straight example at z = -0.12 m with
# --settle, curling it, growing it, and the operations list of examples/hairstyles/wavy_styled.json.
#
#   scripts/make_styling_pictures.sh [BUILD_DIR] [IMAGE_DIR]     (defaults: build, docs/images)
#
# Needs ringlet built in BUILD_DIR and /usr/bin/python3 with numpy and matplotlib. Outputs go to
# BUILD_DIR/styling/<name>/, each summary in BUILD_DIR/styling/<name>.log.
set -eu
cd "$(dirname "$0")/.."
build=${1:-build}
images=${2:-docs/images}
python=/usr/bin/python3
out=$build/styling
mkdir -p "$out" "$images"
if [ ! -x "$build/ringlet" ]; then
  echo "make_styling_pictures.sh: $build/ringlet not found; build it first" >&2
  exit 1
fi
run() {  # run NAME ARGS...
  name=$1
  shift
  echo "== ringlet $* -o $out/$name/"
  "$build/ringlet" "$@" -o "$out/$name" --force | tee "$out/$name.log"
}
run wavy groom examples/hairstyles/wavy_mannequin.json
run wavy_wet style examples/hairstyles/wavy_mannequin.json --wet
$python scripts/plot_groom.py "$out/wavy" "$out/wavy_wet" -o "$images/style_wet.png" \
  --palette wavy --views side --labels "dry" "wet (--wet)" \
  --title "wavy.json dry and wet: E / 10, radius x 1.13, water weight, thinner hull layers"
run straight groom examples/hairstyles/straight_mannequin.json
run straight_cut style examples/hairstyles/straight_mannequin.json --cut-z -0.12 --settle
$python scripts/plot_groom.py "$out/straight" "$out/straight_cut" -o "$images/style_cut.png" \
  --palette straight --views side --labels "groomed" "cut at z = -0.12 m (--settle)" \
  --title "straight.json before and after a cut: the lighter hair rises, --settle re-cuts"
run wavy_wet_dry style examples/hairstyles/wavy_mannequin.json --wet --dry
$python scripts/plot_groom.py "$out/wavy_wet" "$out/wavy_wet_dry" -o "$images/style_dry.png" \
  --palette wavy --views side --labels "wet (--wet)" "dried (--wet --dry)" \
  --title "wavy.json wet, then dried: the exact inverse, the groomed shape comes back"
run straight_curl style examples/hairstyles/straight_mannequin.json --curl 0.01,0.03
$python scripts/plot_groom.py "$out/straight" "$out/straight_curl" -o "$images/style_curl.png" \
  --palette straight --views side --labels "groomed" "--curl 0.01,0.03" \
  --title "straight.json curled: helix R = 1 cm, p = 3 cm"
run straight_grow style examples/hairstyles/straight_mannequin.json --grow 0.02 --steps 5
$python scripts/plot_groom.py "$out/straight" "$out/straight_grow" -o "$images/style_grow.png" \
  --palette straight --views side --labels "groomed, 35 cm" "--grow 0.02 --steps 5" \
  --title "straight.json grown by 5 x 2 cm"
run wavy_styled style examples/hairstyles/wavy_styled.json
$python scripts/plot_groom.py "$out/wavy" "$out/wavy_styled" -o "$images/style_file.png" \
  --palette wavy --views side --labels "wavy.json groomed" "wavy_styled.json operations" \
  --title "the operations list of wavy_styled.json: crown curl, wet, cut -0.14 (settle), dry, grow"
