#!/usr/bin/env bash
# Makes docs/images/blender_groom.png (docs/blender.md): grooms
# examples/hairstyles/wavy_mannequin.json with
# the built `ringlet`, imports the folder with the built add-on into headless Blender and renders
# it with Cycles. Usage: scripts/make_blender_picture.sh [BUILD_DIR] [SIZE] [SAMPLES]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${1:-$root/build}
size=${2:-480}
samples=${3:-64}
work=$(mktemp -d "${TMPDIR:-/tmp}/ringlet_blender_picture.XXXXXX")
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/scripts" "$work/config"
"$build/ringlet" groom "$root/examples/hairstyles/wavy_mannequin.json" -o "$work/groom" --quiet
BLENDER_USER_SCRIPTS="$work/scripts" BLENDER_USER_CONFIG="$work/config" \
  blender -b --factory-startup --python-exit-code 1 \
  --python "$root/scripts/blender_picture.py" -- \
  "$build/blender/ringlet_blender.zip" "$work/groom" "$work/blender_groom.png" "$size" "$samples" |
  grep '^picture:'
cp "$work/blender_groom.png" "$root/docs/images/blender_groom.png"
ls -l "$root/docs/images/blender_groom.png"
